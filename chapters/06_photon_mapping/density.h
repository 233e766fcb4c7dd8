// Lesson 6, section 4: the radiance estimate. At a camera-path vertex x, seen from direction wo,
// the reflected radiance is the reflection equation
//   L_r(x, wo) = integral over wi of f(wo, wi) L_i(x, wi) |cos theta_i| d(wi).
// The photons estimate it without tracing a single ray from x. N light subpaths land their
// vertices on the surfaces with some density; carrying beta each (photons.h), they satisfy, for
// any function g of a surface point and a direction (a measurement in Veach's path-integral
// form, Veach 1997, ch. 8, lesson 5's beta being each subpath's contribution over its density),
//   E[ sum over photons of beta_p g(y_p, wi_p) ] = integral over surfaces and directions of
//                                                 g(y, wi) L_i(y, wi) |cos theta_i| d(wi) dA(y).
// Taking g(y, wi) = K(|y - x|) f(wo, wi) (kernel.h) and dividing by N:
//   L_r(x, wo) ~ (1/N) sum over photons within r of K(|y_p - x|) f(wo, wi_p) beta_p,
// Jensen's radiance estimate ("Global Illumination using Photon Maps", EGWR 1996) with its
// photon powers written as beta_p / N. Its expectation is L_r(y, wo) averaged over the disk
// about x with weights K (the kernel's bias; exact as r -> 0). There is no cosine at the
// receiving end: light arriving at a slant spreads its flux over more area, so photons land
// with a density per unit area already
// proportional to |cos theta_i| (the cosine of the geometry term, which the density of y_p holds,
// lesson 5's p_A = p(w) |cos| / d^2). With an interpolated shading normal n_s the camera side
// wants f |wi . n_s| (lesson 4's estimator, lesson 5's join at the camera vertex) where the
// photons' density holds |wi . n_p|, the cosine at the photon's own surface (its geometric
// normal, stored with it): each photon is weighted by |wi . n_s| / |wi . n_p| (1 on flat
// surfaces); beta itself already carries lesson 5's adjoint correction at every earlier bounce
// (light_side_scattering).
//
// Which photons count: the estimate assumes that the photons near x lie on x's surface, lit
// from x's side. A photon counts if the normal on the side its light arrived from agrees with
// the normal on the side the camera sees x from (their dot product > 0): this keeps out the
// photons on the back of a thin wall or floor (light through walls) and on a surface facing x
// across a gap smaller than r. Photons on a neighbouring surface whose normal is less than 90
// degrees from x's (a shallow crease, a curved surface) still count: the kernel's bias near
// edges, which shrinks with r (a box's right-angled corners keep them out). f(wo, wi_p) is
// the BSDF at x (the camera side's, lesson 5's convention): a reflecting BSDF is 0 for photons
// arriving from behind x's geometric surface.
#pragma once

#include <cstdint>
#include <optional>

#include "06_photon_mapping/kernel.h"
#include "06_photon_mapping/photon_map.h"
#include "geometry/interaction.h"
#include "materials/bsdf.h"

namespace lessons {

struct RadianceEstimate {
    Color L{0.0f};         // the estimate of L_r(x, wo), W / (sr m^2)
    uint32_t photons = 0;  // how many photons counted (within r, on x's side)
};

// The density estimate of the radiance reflected at x (hit `si`, its BSDF `bsdf` as the camera
// side sees it) towards wo (unit, pointing away from the surface), from the photons of `grid`
// within its radius, which came from `light_paths` light subpaths (N above, LightPaths::count).
// Only photons of vertex y_i with min_vertex <= i <= max_vertex count (photon mapping's 2: light
// that has bounced at least once, direct light being next-event estimation's; max_vertex keeps
// the paths within --max-depth).
RadianceEstimate reflected_radiance(const PhotonGrid& grid, const SurfaceInteraction& si,
                                    const Bsdf& bsdf, const Vec3& wo, Kernel kernel,
                                    int light_paths, uint32_t min_vertex = 1,
                                    uint32_t max_vertex = UINT32_MAX);

// One photon's term of the estimate, K(|y_p - x|) f(wo, wi_p) beta_p |wi . n_s| / |wi . n_p|
// (not yet divided by N), or none if it does not count at x (its side, or beyond r).
std::optional<Color> photon_term(const Photon& p, const SurfaceInteraction& si, const Bsdf& bsdf,
                                 const Vec3& wo, Kernel kernel, float radius);

// Whether photon p may be counted at x (normal n_geo, seen from wo): the rule above.
bool photon_on_same_side(const Photon& p, const Vec3& n_geo, const Vec3& wo);

}  // namespace lessons
