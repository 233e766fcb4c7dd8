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

// Uniform direction towards a rectangle, i.e. by solid angle (Urena, Fajardo and King, "An
// Area-Preserving Parametrization for Spherical Rectangles", EGSR 2013): p(w) = 1 / Omega, with
// Omega the solid angle the rectangle subtends at o. Seen from o, the rectangle is a spherical
// quadrilateral; in a frame with the rectangle's edges along x and y and its plane at z = z0 < 0,
// its solid angle is the excess of its four interior angles, Omega = g0 + g1 + g2 + g3 - 2 pi,
// each g the angle between two of the planes through o and one edge. A first number picks the
// sub-area [x0, xu] of solid angle u.x Omega (solved for xu in closed form), a second a height
// along that column uniform in solid angle. Compared with a point uniform by area (p_A d^2 /
// cos(theta_l)), the estimate f L cos / p loses the factor 1 / d^2 cos(theta_l), which is
// unbounded for points close to the light's plane.
class SphericalRectangle {
public:
    // The rectangle corner + a edge_u + b edge_v, a and b in [0, 1], with edge_u orthogonal to
    // edge_v, seen from o.
    SphericalRectangle(const Vec3& o, const Vec3& corner, const Vec3& edge_u, const Vec3& edge_v) {
        const float length_u = glm::length(edge_u), length_v = glm::length(edge_v);
        const Vec3 x = edge_u / length_u, y = edge_v / length_v;
        const Vec3 d = corner - o;
        z0_ = -std::fabs(glm::dot(d, glm::cross(x, y)));  // the side of o is the frame's +z
        x0_ = glm::dot(d, x);
        y0_ = glm::dot(d, y);
        x1_ = x0_ + length_u;
        y1_ = y0_ + length_v;
        length_u_ = length_u;
        length_v_ = length_v;
        // Unit normals of the planes through o and each edge; their z components give the
        // angles between neighbouring planes (the other components meet zeros).
        auto z_of = [](float a, float b) { return b / std::sqrt(a * a + b * b); };
        const float n0z = z_of(z0_, -y0_), n1z = z_of(z0_, x1_);
        const float n2z = z_of(z0_, y1_), n3z = z_of(z0_, -x0_);
        const float g0 = std::acos(std::clamp(-n0z * n1z, -1.0f, 1.0f));
        const float g1 = std::acos(std::clamp(-n1z * n2z, -1.0f, 1.0f));
        const float g2 = std::acos(std::clamp(-n2z * n3z, -1.0f, 1.0f));
        const float g3 = std::acos(std::clamp(-n3z * n0z, -1.0f, 1.0f));
        b0_ = n0z;
        b1_ = n2z;
        k_ = 2.0f * kPi - g2 - g3;
        solid_angle_ = g0 + g1 - k_;
    }

    float solid_angle() const { return solid_angle_; }
    // Whether sampling by solid angle is accurate here: not for a tiny solid angle (the excess
    // above cancels) nor for nearly a hemisphere (o almost in the rectangle), where callers
    // sample by area instead (the thresholds are pbrt-v4's).
    bool well_conditioned() const {
        return solid_angle_ > 3e-4f && solid_angle_ < 6.22f && std::isfinite(solid_angle_);
    }

    // The point where a direction uniform in solid angle meets the rectangle, as its edge
    // coordinates (a, b) in [0, 1]^2.
    Vec2 sample(const Vec2& u) const {
        // The column xu whose left part [x0, xu] subtends u.x Omega.
        const float au = u.x * solid_angle_ + k_;
        const float fu = (std::cos(au) * b0_ - b1_) / std::sin(au);
        const float cu =
            std::clamp(std::copysign(1.0f, fu) / std::sqrt(fu * fu + b0_ * b0_), -1.0f, 1.0f);
        const float sin_u = std::sqrt(std::max(0.0f, 1.0f - cu * cu));
        const float xu =
            sin_u > 0.0f ? std::clamp(-cu * z0_ / sin_u, x0_, x1_) : (cu * z0_ > 0.0f ? x0_ : x1_);
        // Along the column, h = y / |(xu, y, z0)| is uniform in solid angle.
        const float dist = std::sqrt(xu * xu + z0_ * z0_);
        const float h0 = y0_ / std::sqrt(dist * dist + y0_ * y0_);
        const float h1 = y1_ / std::sqrt(dist * dist + y1_ * y1_);
        const float hv = h0 + u.y * (h1 - h0);
        const float hv2 = hv * hv;
        const float yv = hv2 < 1.0f - 1e-6f ? hv * dist / std::sqrt(1.0f - hv2) : y1_;
        return {std::clamp((xu - x0_) / length_u_, 0.0f, 1.0f),
                std::clamp((yv - y0_) / length_v_, 0.0f, 1.0f)};
    }

private:
    float x0_, x1_, y0_, y1_, z0_, length_u_, length_v_;
    float b0_, b1_, k_, solid_angle_;
};
inline float spherical_rectangle_pdf(const SphericalRectangle& r) {
    return 1.0f / r.solid_angle();
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
