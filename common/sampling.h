// Sampling routines, each beside its density (STYLE.md: they come in pairs).
//
// Every routine maps uniform numbers u in [0, 1)^2 to a point of its domain; the matching
// *_pdf gives the density of that point with respect to the domain's natural measure: solid
// angle for directions (per steradian), area for points on shapes. Local directions have the
// surface normal along +z. All outputs are finite for u at 0 and at 1 - 2^-24.
#pragma once

#include <algorithm>
#include <cmath>

#include "math.h"

namespace lessons {

// Uniform point on the unit disk, by Shirley and Chiu's concentric map (which keeps strata
// compact and has no singularity at the center).
inline Vec2 sample_concentric_disk(const Vec2& u) {
    const Vec2 o = 2.0f * u - Vec2(1.0f);
    if (o.x == 0.0f && o.y == 0.0f) return Vec2(0.0f);
    float r, theta;
    if (std::fabs(o.x) > std::fabs(o.y)) {
        r = o.x;
        theta = (kPi / 4.0f) * (o.y / o.x);
    } else {
        r = o.y;
        theta = kPi / 2.0f - (kPi / 4.0f) * (o.x / o.y);
    }
    return r * Vec2(std::cos(theta), std::sin(theta));
}

// Uniform direction on the hemisphere z > 0: p(w) = 1 / (2 pi). (z = 1 - u.x lies in (0, 1], so
// no sample lies exactly on the horizon, where the density jumps to 0.)
inline Vec3 sample_uniform_hemisphere(const Vec2& u) {
    const float z = 1.0f - u.x;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniform_hemisphere_pdf() {
    return 1.0f / (2.0f * kPi);
}

// Cosine-weighted direction on the hemisphere: p(w) = cos(theta) / pi (Malley's method: a
// uniform point on the disk, lifted to the hemisphere).
inline Vec3 sample_cosine_hemisphere(const Vec2& u) {
    const Vec2 d = sample_concentric_disk(u);
    const float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
    return {d.x, d.y, z};
}
inline float cosine_hemisphere_pdf(float cos_theta) {
    return std::max(cos_theta, 0.0f) * kInvPi;
}

// Uniform direction on the unit sphere: p(w) = 1 / (4 pi).
inline Vec3 sample_uniform_sphere(const Vec2& u) {
    const float z = 1.0f - 2.0f * u.x;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniform_sphere_pdf() {
    return 1.0f / (4.0f * kPi);
}

// Uniform direction in the cone of half-angle theta_max around +z, given by
// one_minus_cos_max = 1 - cos(theta_max) (passed this way so that tiny cones, such as a small
// light far away, keep their precision): p(w) = 1 / (2 pi (1 - cos(theta_max))).
inline Vec3 sample_uniform_cone(const Vec2& u, float one_minus_cos_max) {
    const float one_minus_cos = u.x * one_minus_cos_max;
    const float cos_theta = 1.0f - one_minus_cos;
    // sin^2 = (1 - cos)(1 + cos), without the cancellation of 1 - cos^2.
    const float sin_theta = std::sqrt(std::max(0.0f, one_minus_cos * (2.0f - one_minus_cos)));
    const float phi = 2.0f * kPi * u.y;
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}
inline float uniform_cone_pdf(float one_minus_cos_max) {
    return 1.0f / (2.0f * kPi * one_minus_cos_max);
}

// Uniform point on a triangle, as barycentric weights (b1, b2) of its second and third
// vertices: p = 1 / area.
inline Vec2 sample_uniform_triangle(const Vec2& u) {
    const float s = std::sqrt(u.x);
    return {s * (1.0f - u.y), s * u.y};
}

// Multiple importance sampling weights for a sample drawn from strategy f (density pdf_f),
// against strategy g (density pdf_g), one sample each (Veach 1997, ch. 9).
inline float balance_heuristic(float pdf_f, float pdf_g) {
    return pdf_f + pdf_g > 0.0f ? pdf_f / (pdf_f + pdf_g) : 0.0f;
}
// pdf_f^2 / (pdf_f^2 + pdf_g^2), written as 1 / (1 + (pdf_g / pdf_f)^2) so that the squares of
// large densities (a tiny light seen from afar) cannot overflow.
inline float power_heuristic(float pdf_f, float pdf_g) {
    if (!(pdf_f > 0.0f)) return 0.0f;
    const float ratio = pdf_g / pdf_f;
    return 1.0f / (1.0f + ratio * ratio);
}

}  // namespace lessons
