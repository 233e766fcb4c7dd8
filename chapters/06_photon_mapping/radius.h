// Lesson 6, section 5: the default radius. The radius trades the kernel's bias (the estimate is
// the light blurred over a disk of radius r: kernel.h) against its noise (the fewer photons in
// the disk, the noisier): the image decides which matters, so the default is measured in pixels.
//
// A pixel's footprint: its patch of the image plane at distance 1 from the pinhole has side
// a = sqrt(A_image / (W H)) (square pixels), so on a surface at distance d facing the camera a
// pixel covers a square of side a d. Take d as the median distance of what the camera sees.
// With one light subpath per pixel per iteration (N = W H, as lesson 5 traces and vertex
// connection and merging does), and the light spread evenly over the visible surfaces (their
// area about W H (a d)^2, the image's pixels laid on them), each bounce lands about
// N / (W H (a d)^2) = 1 / (a d)^2 photons per unit area: a disk of radius r = k a d holds about
// pi k^2 photons per bounce. k = 2 gives about 12 (a relative noise near 1 / sqrt(12) = 0.29 per
// iteration and bounce, which the iterations average down) for a blur 4 pixels across; halving k
// would quadruple the variance, doubling it would blur 8 pixels. Scenes where the light is not
// spread evenly (a small lit patch, a caustic) gather more or fewer: the Cornell box at 512 x 512
// gathers about 10 in all at its first hits, Whitted's scene (a point light over an open floor
// under a sky) far fewer, since the sky takes a fifth of the light subpaths and starts none
// (photons.h), half of the lamp's go up into it, and the floor reaches far beyond the view.
// Progressive photon mapping shrinks the radius from there.
//
// Limits: at most 5% of the scene's bounding-box diagonal (an image a few pixels wide would
// otherwise blur across the whole scene), at least 1e-4 of it (a camera touching a wall would
// otherwise get a radius near 0, which no photon reaches); with no camera ray hitting anything,
// d is the distance to the box's centre.
#pragma once

#include <optional>

#include "scene/scene.h"

namespace lessons {

// Pixel footprints per radius: k above.
inline constexpr float kRadiusInPixels = 2.0f;

// The side a of one pixel's patch of the image plane at distance 1 (the camera's angular pixel
// size, in radians at the image's centre).
float pixel_side_at_unit_distance(const Camera& camera, int width, int height);

// The median distance from the pinhole to the first hit of the rays through a grid of 16 x 16
// film positions spread evenly over the image (pixel centres, no randomness); none if none hits.
std::optional<float> median_hit_distance(const Scene& scene);

// k pixel footprints at the median distance, within the limits above (a committed scene, with
// its camera and image size).
float default_photon_radius(const Scene& scene, float pixels = kRadiusInPixels);

}  // namespace lessons
