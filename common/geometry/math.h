// Vectors, rays and orthonormal frames: the geometric vocabulary of every lesson.
// Built on GLM. Positions and directions are single-precision world-space vectors; radiance is
// an RGB triple of linear values in W / (sr m^2) per channel.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <limits>

namespace lessons {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Color = glm::vec3;  // linear RGB radiance, irradiance or reflectance

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

// A ray o + t d for t in (0, t_max]. d need not be unit length; t is in units of |d|.
struct Ray {
    Vec3 origin{0.0f};
    Vec3 dir{0.0f, 0.0f, 1.0f};
    float t_max = kInfinity;

    Vec3 at(float t) const { return origin + t * dir; }
};

// gamma(n) = n u / (1 - n u), u = 2^-24: a bound on the relative error of n successive float
// operations (Higham; pbrt-v4 section 6.8). Used for conservative bounds and offsets.
inline constexpr float gamma_bound(int n) {
    constexpr float u = 0x1p-24f;
    return n * u / (1.0f - n * u);
}

// The next float above v, as std::nextafter(v, +inf) gives it (NaN stays a NaN), inline (each ray
// origin takes three, and the library call costs more than the rest of the offset): floats of one
// sign are ordered as their bit patterns, so one step is one unit of the pattern.
inline float next_float_up(float v) {
    if (std::isnan(v) || v == kInfinity) return v;
    if (v == 0.0f) return std::numeric_limits<float>::denorm_min();  // from +0 and from -0
    const uint32_t bits = std::bit_cast<uint32_t>(v);
    return std::bit_cast<float>(v > 0.0f ? bits + 1 : bits - 1);
}
// The next float below v: std::nextafter(v, -inf).
inline float next_float_down(float v) {
    return -next_float_up(-v);
}
inline float max_component(const Vec3& v) {
    return std::fmax(v.x, std::fmax(v.y, v.z));
}
inline float min_component(const Vec3& v) {
    return std::fmin(v.x, std::fmin(v.y, v.z));
}
inline bool is_finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool is_black(const Color& c) {
    return c.x <= 0.0f && c.y <= 0.0f && c.z <= 0.0f;
}
// Rec. 709 luminance of a linear RGB value.
inline float luminance(const Color& c) {
    return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

// An orthonormal frame (s, t, n) around a unit normal n. Directions in the local frame have
// n along +z, so cos(theta) of a local direction is its z component.
// Construction: Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 2017), which has
// no branch on a threshold and stays orthonormal to float precision for every unit n.
struct Frame {
    Vec3 s, t, n;

    explicit Frame(const Vec3& normal) : n(normal) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z);
        const float b = n.x * n.y * a;
        s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
        t = Vec3(b, sign + n.y * n.y * a, -n.y);
    }
    Vec3 to_local(const Vec3& v) const { return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)}; }
    Vec3 to_world(const Vec3& v) const { return v.x * s + v.y * t + v.z * n; }
};

}  // namespace lessons
