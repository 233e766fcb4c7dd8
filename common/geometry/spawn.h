// Spawning secondary rays without self-intersection (docs/accuracy.md, hard case 3).
//
// A hit point computed in floating point lies a little off the true surface, on either side.
// A ray started exactly there can re-hit the surface it leaves ("shadow acne"). A fixed epsilon
// fails at both ends of the range of scales: too large for small features (rays jump through
// them), too small far from the origin (the rounding error of a coordinate near 1e4 already
// exceeds 1e-3). Instead, as pbrt-v4 does (Pharr, Jakob, Humphreys, "Physically Based
// Rendering", 4th ed., section 6.8), every hit point carries a conservative bound on its own
// rounding error, per axis; the new ray starts just outside the box of that size around the
// point, along the geometric normal, on the side it leaves towards. The offset is as small as
// the arithmetic allows at every scale.
#pragma once

#include <cmath>

#include "geometry/math.h"

namespace lessons {

// A point on a surface as spawning needs it.
struct SurfacePoint {
    Vec3 p;      // position
    Vec3 error;  // per-axis bound on |p - true surface point|
    Vec3 n;      // geometric normal (either side)
};

// Moves p off its surface along n, to the side direction w points into, by the projection of
// its error box onto the normal, then one more float step away so rounding cannot undo it.
inline Vec3 offset_ray_origin(const SurfacePoint& s, const Vec3& w) {
    const Vec3 n = glm::dot(w, s.n) < 0.0f ? -s.n : s.n;
    const float d = glm::dot(glm::abs(n), s.error);
    Vec3 out = s.p + d * n;
    // One more float step along n in each axis (also when the error bound is zero).
    for (int i = 0; i < 3; ++i) {
        if (n[i] > 0.0f)
            out[i] = next_float_up(out[i]);
        else if (n[i] < 0.0f)
            out[i] = next_float_down(out[i]);
    }
    return out;
}

// A ray leaving a surface in direction dir.
inline Ray spawn_ray(const SurfacePoint& from, const Vec3& dir) {
    return Ray{offset_ray_origin(from, dir), dir, kInfinity};
}

// A shadow ray from a surface towards a point `target` that is not on a surface (e.g. a point
// light). It covers t in (0, 1): the target itself is at t = 1 and is excluded.
inline Ray spawn_ray_to(const SurfacePoint& from, const Vec3& target) {
    const Vec3 origin = offset_ray_origin(from, target - from.p);
    return Ray{origin, target - origin, 1.0f};
}

// A shadow ray between two surface points: both ends are offset off their surfaces, towards
// each other, so the surface left is never hit. The surface reached (e.g. an area light) can
// still be found near t = 1: the offset bounds the end point's error, not that of the hit
// distance the intersection test computes (lesson 4's light-path test caught a triangle blocking
// segments that ended on it). So callers also name the primitive the segment ends on to
// Scene::occluded, which ignores it.
inline Ray spawn_ray_between(const SurfacePoint& from, const SurfacePoint& to) {
    const Vec3 origin = offset_ray_origin(from, to.p - from.p);
    const Vec3 target = offset_ray_origin(to, from.p - to.p);
    return Ray{origin, target - origin, 1.0f};
}

}  // namespace lessons
