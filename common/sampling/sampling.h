// Sampling routines, each beside its density (they come in pairs: sample_X beside X_pdf).
//
// Every routine maps uniform numbers u in [0, 1)^2 to a point of its domain; the matching
// *_pdf gives the density of that point with respect to the domain's natural measure: solid
// angle for directions (per steradian), area for points on shapes. Local directions have the
// surface normal along +z. All outputs are finite for u at 0 and at 1 - 2^-24.
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/math.h"

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

// A rectangle in the form SphericalRectangle reads: a corner, the unit directions of its two
// orthogonal edges, their lengths, and the unit normal z = x cross y. Lights keep one each, so
// that a light sample does not normalise the edges again.
struct Rectangle {
    Vec3 corner, x, y, z;
    float length_x, length_y;
    float inverse_length_x, inverse_length_y;
    Rectangle(const Vec3& corner_, const Vec3& edge_u, const Vec3& edge_v)
        : corner(corner_), length_x(glm::length(edge_u)), length_y(glm::length(edge_v)) {
        inverse_length_x = 1.0f / length_x;
        inverse_length_y = 1.0f / length_y;
        x = edge_u * inverse_length_x;
        y = edge_v * inverse_length_y;
        z = glm::cross(x, y);
    }
};

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
// The angles are added as complex numbers, cos g + i sin g, multiplied: the argument of the
// product of the four is Omega (the 2 pi drops out), found by one atan2 instead of four acos.
class SphericalRectangle {
public:
    SphericalRectangle(const Vec3& o, const Rectangle& r) {
        const Vec3 d = r.corner - o;
        z0_ = -std::fabs(glm::dot(d, r.z));  // the side of o is the frame's +z
        x0_ = glm::dot(d, r.x);
        y0_ = glm::dot(d, r.y);
        x1_ = x0_ + r.length_x;
        y1_ = y0_ + r.length_y;
        // The planes through o and each edge have unit normals n0 .. n3 (n0 through the edge at
        // y0, then around), whose z components b = n.z give the interior angles:
        // cos g0 = -n0.z n1.z, and so on around. With l and r the distances from o to an edge's
        // line and to a corner, cos g0 = y0 x1 / (l0 l1) and sin g0 = |z0| r(x1, y0) / (l0 l1);
        // the positive factors 1 / (l l) change no angle and are left out. Angles do not change
        // with scale either: the coordinates are divided by the largest, so that the product of
        // four cannot overflow.
        const float scale = 1.0f / std::max({std::fabs(x0_), std::fabs(x1_), std::fabs(y0_),
                                             std::fabs(y1_), std::fabs(z0_)});
        const float x0 = x0_ * scale, x1 = x1_ * scale, y0 = y0_ * scale, y1 = y1_ * scale;
        const float z = z0_ * scale;
        auto corner_distance = [z](float x, float y) { return std::sqrt(x * x + y * y + z * z); };
        const Complex w0{y0 * x1, -z * corner_distance(x1, y0)};
        const Complex w1{-x1 * y1, -z * corner_distance(x1, y1)};
        const Complex w2{x0 * y1, -z * corner_distance(x0, y1)};
        const Complex w3{-x0 * y0, -z * corner_distance(x0, y0)};
        const Complex g23 = w2 * w3;  // g2 + g3
        const Complex all = (w0 * w1) * g23;
        // Omega lies in (0, 2 pi). Within rounding of 0 (a tiny rectangle, or o almost in its
        // plane) atan2 may give either side of 0, hence a value near 0 or near 2 pi: both are
        // outside what well_conditioned() accepts.
        solid_angle_ = std::atan2(all.im, all.re);
        if (solid_angle_ <= 0.0f) solid_angle_ += 2.0f * kPi;
        // k = 2 pi - g2 - g3, the angle where the columns start, as cos k + i sin k.
        const float g23_length = std::sqrt(g23.re * g23.re + g23.im * g23.im);
        const float inverse_g23_length = 1.0f / g23_length;
        cos_k_ = g23.re * inverse_g23_length;
        sin_k_ = -g23.im * inverse_g23_length;
        // o in the rectangle's plane sees no solid angle; g2 + g3 is undefined when o lies on
        // the line of an edge there.
        if (!(z < 0.0f) || !(g23_length > 0.0f)) solid_angle_ = 0.0f;
        // b0 = n0.z and b1 = n2.z, and 1 - b0^2 (for sample(), without its cancellation).
        const float inverse_l0 = 1.0f / std::sqrt(z * z + y0 * y0);
        b0_ = -y0 * inverse_l0;
        b1_ = y1 / std::sqrt(z * z + y1 * y1);
        one_minus_b0_squared_ = z * z * inverse_l0 * inverse_l0;
        inverse_length_x_ = r.inverse_length_x;
        inverse_length_y_ = r.inverse_length_y;
    }
    // The same for a rectangle given by a corner and two orthogonal edges.
    SphericalRectangle(const Vec3& o, const Vec3& corner, const Vec3& edge_u, const Vec3& edge_v)
        : SphericalRectangle(o, Rectangle(corner, edge_u, edge_v)) {}

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
        // The column xu whose left part [x0, xu] subtends u.x Omega: at angle au = u.x Omega + k,
        // turned from k by u.x Omega.
        const float phi = u.x * solid_angle_;
        const float cos_phi = std::cos(phi), sin_phi = std::sin(phi);
        const float cos_au = cos_phi * cos_k_ - sin_phi * sin_k_;
        const float sin_au = sin_phi * cos_k_ + cos_phi * sin_k_;
        const float fu = (cos_au * b0_ - b1_) / sin_au;
        // The column's plane has normal z component cu = sign(fu) / sqrt(fu^2 + b0^2), and
        // xu = -cu z0 / sqrt(1 - cu^2) = sign(fu) |z0| / sqrt(fu^2 - (1 - b0^2)): one square root
        // and one division. Where the root's argument is not positive (|cu| >= 1), the column
        // is an edge of the rectangle.
        const float root2 = fu * fu - one_minus_b0_squared_;
        const float xu = root2 > 0.0f
                             ? std::clamp(std::copysign(z0_, fu) / std::sqrt(root2), x0_, x1_)
                             : (std::signbit(fu) ? x0_ : x1_);
        // Along the column, h = y / |(xu, y, z0)| is uniform in solid angle; y = h d / sqrt(1 -
        // h^2), with d = |(xu, z0)|.
        const float d2 = xu * xu + z0_ * z0_;
        const float h0 = y0_ / std::sqrt(d2 + y0_ * y0_);
        const float h1 = y1_ / std::sqrt(d2 + y1_ * y1_);
        const float hv = h0 + u.y * (h1 - h0);
        const float hv2 = hv * hv;
        const float yv = hv2 < 1.0f - 1e-6f ? hv * std::sqrt(d2) / std::sqrt(1.0f - hv2) : y1_;
        return {std::clamp((xu - x0_) * inverse_length_x_, 0.0f, 1.0f),
                std::clamp((yv - y0_) * inverse_length_y_, 0.0f, 1.0f)};
    }

private:
    // A plain product: std::complex's operator* also handles infinities and NaNs (C99 Annex G),
    // through a library call when a result is NaN, which this bounded arithmetic never needs.
    struct Complex {
        float re, im;
        Complex operator*(const Complex& o) const {
            return {re * o.re - im * o.im, re * o.im + im * o.re};
        }
    };
    float x0_, x1_, y0_, y1_, z0_;
    float b0_, b1_, one_minus_b0_squared_, cos_k_, sin_k_, solid_angle_;
    float inverse_length_x_, inverse_length_y_;
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
// The same among three strategies, pdf_f^2 / (pdf_f^2 + pdf_g^2 + pdf_h^2), in double: lesson 4
// weighs densities of two path vertices at once (products of two per-area densities), whose
// range is the square of one's.
inline float power_heuristic(double pdf_f, double pdf_g, double pdf_h) {
    if (!(pdf_f > 0.0)) return 0.0f;
    const double g = pdf_g / pdf_f, h = pdf_h / pdf_f;
    return static_cast<float>(1.0 / (1.0 + g * g + h * h));
}

}  // namespace lessons
