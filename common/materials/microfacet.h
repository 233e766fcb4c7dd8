// The GGX (Trowbridge-Reitz) microfacet distribution with Smith masking-shadowing.
//
// Local frame: the macro-surface normal is +z. alpha is the roughness (the distribution's
// width). References: Walter et al., "Microfacet Models for Refraction through Rough Surfaces"
// (EGSR 2007); Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs"
// (JCGT 2014); Heitz, "Sampling the GGX Distribution of Visible Normals" (JCGT 2018).
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/math.h"

namespace lessons {

// D(m) = alpha^2 / (pi ((m.n)^2 (alpha^2 - 1) + 1)^2): density of microfacet normals m per
// unit solid angle, normalised so that the integral of D(m) (m.n) dm over the hemisphere is 1
// (the projected microfacet area equals the macro-surface area).
inline float ggx_D(const Vec3& m, float alpha) {
    if (m.z <= 0.0f) return 0.0f;
    const float a2 = alpha * alpha;
    const float t = m.z * m.z * (a2 - 1.0f) + 1.0f;
    return a2 / (kPi * t * t);
}

// Smith's Lambda(w) for GGX: (-1 + sqrt(1 + alpha^2 tan^2(theta))) / 2.
inline float ggx_lambda(const Vec3& w, float alpha) {
    const float cos2 = w.z * w.z;
    if (cos2 <= 0.0f) return kInfinity;
    const float tan2 = std::max(0.0f, 1.0f - cos2) / cos2;
    return 0.5f * (-1.0f + std::sqrt(1.0f + alpha * alpha * tan2));
}

// Masking G1(w) = 1 / (1 + Lambda(w)): the fraction of microfacets facing w that w sees.
inline float ggx_G1(const Vec3& w, float alpha) {
    return 1.0f / (1.0f + ggx_lambda(w, alpha));
}

// Height-correlated masking-shadowing G2(wo, wi) = 1 / (1 + Lambda(wo) + Lambda(wi)).
inline float ggx_G2(const Vec3& wo, const Vec3& wi, float alpha) {
    return 1.0f / (1.0f + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}

// A microfacet normal m drawn from the distribution of normals visible from wo (wo.z > 0),
// D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z (Heitz 2018): stretch wo to the configuration where
// alpha = 1, sample the projected area of a hemisphere there, and unstretch.
inline Vec3 sample_ggx_visible_normal(const Vec3& wo, float alpha, const Vec2& u) {
    const Vec3 v = glm::normalize(Vec3(alpha * wo.x, alpha * wo.y, wo.z));
    const float len2 = v.x * v.x + v.y * v.y;
    const Vec3 t1 = len2 > 0.0f ? Vec3(-v.y, v.x, 0.0f) / std::sqrt(len2) : Vec3(1, 0, 0);
    const Vec3 t2 = glm::cross(v, t1);
    const float r = std::sqrt(u.x);
    const float phi = 2.0f * kPi * u.y;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    const float s = 0.5f * (1.0f + v.z);
    p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
    const Vec3 n_h = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * v;
    return glm::normalize(Vec3(alpha * n_h.x, alpha * n_h.y, std::max(1e-7f, n_h.z)));
}

}  // namespace lessons
