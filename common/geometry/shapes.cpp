// Ray/shape intersection and surface geometry for spheres, quads and triangles.
#include "geometry/shapes.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <utility>

#include "geometry/spawn.h"

namespace lessons {

namespace {

// Picks the nearest root of a quadratic inside (0, t_max). The smaller root is where the line
// enters the sphere (the outside, front), the larger where it leaves (from inside, back).
bool nearest_root(double t0, double t1, float t_max, ShapeHit& hit) {
    if (t0 > t1) std::swap(t0, t1);
    // A root is usable if it is positive also after rounding to float.
    auto usable = [&](double t) {
        return t > 0.0 && t < static_cast<double>(t_max) && static_cast<float>(t) > 0.0f;
    };
    if (usable(t0)) {
        hit.t = static_cast<float>(t0);
        hit.front = true;
        return true;
    }
    if (usable(t1)) {
        hit.t = static_cast<float>(t1);
        hit.front = false;
        return true;
    }
    return false;
}

}  // namespace

bool intersect_sphere(const Sphere& s, const Ray& ray, ShapeHit& hit) {
    const glm::dvec3 f = glm::dvec3(ray.origin) - glm::dvec3(s.center);
    const glm::dvec3 d(ray.dir);
    const double r = s.radius;
    const double a = glm::dot(d, d);
    const double b = glm::dot(f, d);
    const double c = glm::dot(f, f) - r * r;
    const glm::dvec3 closest_offset = f - (b / a) * d;  // from center to the ray's closest point
    const double discriminant = a * (r * r - glm::dot(closest_offset, closest_offset));
    if (discriminant < 0.0) return false;
    const double q = -(b + std::copysign(std::sqrt(discriminant), b));
    if (q == 0.0) return nearest_root(0.0, 0.0, ray.t_max, hit);  // origin on the sphere, grazing
    return nearest_root(q / a, c / q, ray.t_max, hit);
}

bool intersect_sphere_naive(const Sphere& s, const Ray& ray, ShapeHit& hit) {
    const Vec3 f = ray.origin - s.center;
    const float a = glm::dot(ray.dir, ray.dir);
    const float b = 2.0f * glm::dot(f, ray.dir);
    const float c = glm::dot(f, f) - s.radius * s.radius;
    const float discriminant = b * b - 4.0f * a * c;
    if (discriminant < 0.0f) return false;
    const float root = std::sqrt(discriminant);
    return nearest_root((-b - root) / (2.0f * a), (-b + root) / (2.0f * a), ray.t_max, hit);
}

SurfaceGeometry sphere_surface(const Sphere& s, const Ray& ray, const ShapeHit& hit) {
    // Re-project o + t d onto the sphere (in double) so the point's error is that of the sphere
    // description, not that of a long ray.
    const glm::dvec3 c(s.center);
    const glm::dvec3 on_ray =
        glm::dvec3(ray.origin) + static_cast<double>(hit.t) * glm::dvec3(ray.dir);
    glm::dvec3 radial = on_ray - c;
    const double len = glm::length(radial);
    radial = len > 0.0 ? radial / len : glm::dvec3(0.0, 0.0, 1.0);
    SurfaceGeometry g;
    const glm::dvec3 p = c + static_cast<double>(s.radius) * radial;
    g.p = Vec3(p);
    // Rounding p to float (half an ulp), plus the double arithmetic's error, relative to the
    // largest magnitudes involved.
    const double double_error = 8.0 * 0x1p-53 * (glm::length(c) + s.radius);
    g.p_error = gamma_bound(2) * glm::abs(g.p) + Vec3(static_cast<float>(double_error));
    g.n_geo = Vec3(radial);
    g.n_shading = g.n_geo;
    // Longitude-latitude texture coordinates about the y axis.
    const float phi = std::atan2(g.n_geo.z, g.n_geo.x);
    g.uv = Vec2((phi + kPi) / (2.0f * kPi), std::acos(std::clamp(g.n_geo.y, -1.0f, 1.0f)) * kInvPi);
    return g;
}

Quad::Quad(const Vec3& c, const Vec3& u, const Vec3& v) : corner(c), edge_u(u), edge_v(v) {
    const Vec3 n = glm::cross(u, v);
    const float len2 = glm::dot(n, n);
    area_value = std::sqrt(len2);
    normal = area_value > 0.0f ? n / area_value : Vec3(0.0f);
    dual_u = len2 > 0.0f ? glm::cross(v, n) / len2 : Vec3(0.0f);
    dual_v = len2 > 0.0f ? glm::cross(n, u) / len2 : Vec3(0.0f);
}

Bounds3 Quad::bounds() const {
    Bounds3 b;
    b.expand(corner);
    b.expand(corner + edge_u);
    b.expand(corner + edge_v);
    b.expand(corner + edge_u + edge_v);
    return b;
}

SurfaceGeometry quad_surface(const Quad& q, const ShapeHit& hit) {
    SurfaceGeometry g;
    g.p = q.corner + hit.u * q.edge_u + hit.v * q.edge_v;
    // Two products and two sums: gamma(4) of the magnitudes summed.
    g.p_error = gamma_bound(4) *
                (glm::abs(q.corner) + glm::abs(hit.u * q.edge_u) + glm::abs(hit.v * q.edge_v));
    g.n_geo = q.normal;
    g.n_shading = q.normal;
    g.uv = Vec2(hit.u, hit.v);
    return g;
}

bool intersect_triangle_moller_trumbore(const Ray& ray, const Vec3& p0, const Vec3& p1,
                                        const Vec3& p2, ShapeHit& hit) {
    const Vec3 e1 = p1 - p0, e2 = p2 - p0;
    const Vec3 pv = glm::cross(ray.dir, e2);
    const float det = glm::dot(e1, pv);
    if (det == 0.0f) return false;
    const float inv_det = 1.0f / det;
    const Vec3 tv = ray.origin - p0;
    const float u = glm::dot(tv, pv) * inv_det;
    if (u < 0.0f || u > 1.0f) return false;
    const Vec3 qv = glm::cross(tv, e1);
    const float v = glm::dot(ray.dir, qv) * inv_det;
    if (v < 0.0f || u + v > 1.0f) return false;
    const float t = glm::dot(e2, qv) * inv_det;
    if (!(t > 0.0f && t < ray.t_max)) return false;
    hit.t = t;
    hit.u = u;
    hit.v = v;
    hit.front = det > 0.0f;  // det = -d . cross(e1, e2)
    return true;
}

}  // namespace lessons
