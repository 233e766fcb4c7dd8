// Smooth interfaces: mirror reflection, Snell refraction and the Fresnel equations.
//
// Conventions: directions point away from the surface. `n` is a unit normal on the
// side of the incident direction wi, so cos_i = dot(wi, n) >= 0. eta = n_t / n_i is the ratio
// of the refractive index on the far side to the index on wi's side.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "geometry/math.h"

namespace lessons {

// Mirror direction of wi about n: 2 (wi . n) n - wi.
inline Vec3 reflect(const Vec3& wi, const Vec3& n) {
    return 2.0f * glm::dot(wi, n) * n - wi;
}

// Refracted direction of unit wi through an interface with normal n (on wi's side) and
// eta = n_t / n_i, by Snell's law n_i sin(theta_i) = n_t sin(theta_t); none on total internal
// reflection (sin(theta_t) > 1). The result is unit length and on the far side of n.
inline std::optional<Vec3> refract(const Vec3& wi, const Vec3& n, float eta) {
    const float cos_i = glm::dot(wi, n);
    const float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return std::nullopt;
    const float cos_t = std::sqrt(1.0f - sin2_t);
    return -wi / eta + (cos_i / eta - cos_t) * n;
}

// Fraction of unpolarised light reflected by a smooth dielectric interface: the exact Fresnel
// equations, the mean of the s- and p-polarised reflectances
//   r_s = (n_i cos_i - n_t cos_t) / (n_i cos_i + n_t cos_t)
//   r_p = (n_t cos_i - n_i cos_t) / (n_t cos_i + n_i cos_t),   F = (r_s^2 + r_p^2) / 2,
// written with eta = n_t / n_i. Returns 1 under total internal reflection. cos_i in [0, 1].
inline float fresnel_dielectric(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, 0.0f, 1.0f);
    const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;
    const float cos_t = std::sqrt(1.0f - sin2_t);
    const float r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    const float r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5f * (r_s * r_s + r_p * r_p);
}

// Schlick's approximation F = F0 + (1 - F0)(1 - cos)^5, F0 = ((eta - 1) / (eta + 1))^2, with
// cos taken on the side of the lower index (the transmitted angle when leaving a denser medium),
// and 1 under total internal reflection. Cheaper; for glass of index 1.5 seen from air it is
// exact at normal and grazing incidence and at most 0.036 too low in between (near 85 degrees).
inline float fresnel_schlick(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, 0.0f, 1.0f);
    float cos = cos_i;
    if (eta < 1.0f) {  // leaving a denser medium: use the transmitted angle
        const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
        if (sin2_t >= 1.0f) return 1.0f;
        cos = std::sqrt(1.0f - sin2_t);
    }
    const float f0 = ((eta - 1.0f) / (eta + 1.0f)) * ((eta - 1.0f) / (eta + 1.0f));
    const float m = 1.0f - cos;
    return f0 + (1.0f - f0) * m * m * m * m * m;
}

}  // namespace lessons
