// The shapes a scene is built from: analytic spheres, parallelograms ("quads") and triangles.
// Each shape intersects itself with a ray and reports its bounds; the BVH knows only the bounds.
//
// An intersection routine answers the smallest t in (0, ray.t_max) and, for later shading, two
// surface parameters (barycentrics for triangles, edge coordinates for quads). The full surface
// description (point, normals, texture coordinates) is computed only for the nearest hit, by
// the surface_* functions, so rejected candidates cost as little as possible.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "bounds.h"
#include "math.h"

namespace lessons {

struct ShapeHit {
    float t = kInfinity;
    float u = 0.0f, v = 0.0f;  // triangle: barycentrics of vertices 1 and 2; quad: edge coords
    // Whether the ray arrived on the side the geometric normal points to. Decided by the
    // intersection test itself (which root of the sphere, the sign of the triangle's determinant
    // or of the quad's d.n), so it never disagrees with the hit, even at grazing angles where a
    // separate sign test on dot(d, n) could flip.
    bool front = true;
};

// Geometry of a hit point, as every lesson needs it.
struct SurfaceGeometry {
    Vec3 p;          // position, recomputed from surface parameters (not o + t d) for accuracy
    Vec3 p_error;    // per-axis bound on the rounding error of p (see spawn.h)
    Vec3 n_geo;      // unit geometric normal, the shape's outward side
    Vec3 n_shading;  // unit shading normal (interpolated on meshes), same side as n_geo
    Vec2 uv;         // texture coordinates in [0, 1]^2
};

// ---------------------------------------------------------------------------------------------
// Sphere: |p - center| = radius. The outward normal points away from the center.
struct Sphere {
    Vec3 center;
    float radius;

    Bounds3 bounds() const { return {center - Vec3(radius), center + Vec3(radius)}; }
    float area() const { return 4.0f * kPi * radius * radius; }
};

// Numerically stable ray/sphere intersection (Haines et al., "Precision Improvements for
// Ray/Sphere Intersection", Ray Tracing Gems ch. 7), evaluated in double precision.
// With f = o - c, the roots of |f + t d|^2 = r^2 are t = (-b +- sqrt(D)) / a with a = d.d,
// b = f.d, D = b^2 - a (f.f - r^2). The textbook D cancels catastrophically when the sphere is
// small and far away; the same D written as a (r^2 - |f - (b/a) d|^2) does not. The two roots
// come from q = -(b + sign(b) sqrt(D)) as q/a and c/q, which avoids a second cancellation.
// Double precision keeps smallpt-style walls (radius 1e5) exact to far below any offset.
bool intersect_sphere(const Sphere& s, const Ray& ray, ShapeHit& hit);
// The textbook quadratic in single precision, kept only to demonstrate its failure.
bool intersect_sphere_naive(const Sphere& s, const Ray& ray, ShapeHit& hit);
SurfaceGeometry sphere_surface(const Sphere& s, const Ray& ray, const ShapeHit& hit);

// ---------------------------------------------------------------------------------------------
// Quad (parallelogram): points corner + a edge_u + b edge_v for a, b in [0, 1]. Its geometric
// normal is normalize(cross(edge_u, edge_v)): the order of the edges picks the front side.
struct Quad {
    Vec3 corner, edge_u, edge_v;
    Vec3 normal;  // unit
    // The dual basis of the edges in the quad's plane: a point corner + rel has edge
    // coordinates a = rel . dual_u, b = rel . dual_v. With N = cross(edge_u, edge_v),
    // dual_u = cross(edge_v, N) / |N|^2 and dual_v = cross(N, edge_u) / |N|^2 (Cramer's rule).
    Vec3 dual_u, dual_v;
    float area_value;  // |cross(edge_u, edge_v)|

    Quad() = default;
    Quad(const Vec3& corner, const Vec3& edge_u, const Vec3& edge_v);
    Bounds3 bounds() const;
    float area() const { return area_value; }
    Vec3 center() const { return corner + 0.5f * (edge_u + edge_v); }
};

// Plane hit, then the edge coordinates a, b of the hit point; edges are included on both sides,
// so two quads sharing an edge leave no crack between them. Written once for one quad (T =
// float) and for four side by side (T = Float4, QuadBlock), so both give the same bits.
template <class T>
struct QuadTerms {
    T denom;  // n . d: zero when the ray runs parallel to the plane
    T t;      // where the ray meets the plane: n . (corner - o) / (n . d)
    T a, b;   // edge coordinates of that point: (o + t d - corner) . dual_u, . dual_v
};
template <class T>
[[gnu::always_inline]] inline QuadTerms<T> quad_terms(const T corner[3], const T normal[3],
                                                      const T dual_u[3], const T dual_v[3],
                                                      const Ray& ray) {
    const Vec3 &o = ray.origin, &d = ray.dir;
    QuadTerms<T> r;
    r.denom = normal[0] * d.x + normal[1] * d.y + normal[2] * d.z;
    r.t = (normal[0] * (corner[0] - o.x) + normal[1] * (corner[1] - o.y) +
           normal[2] * (corner[2] - o.z)) /
          r.denom;
    const T rel[3] = {o.x + r.t * d.x - corner[0], o.y + r.t * d.y - corner[1],
                      o.z + r.t * d.z - corner[2]};
    r.a = rel[0] * dual_u[0] + rel[1] * dual_u[1] + rel[2] * dual_u[2];
    r.b = rel[0] * dual_v[0] + rel[1] * dual_v[1] + rel[2] * dual_v[2];
    return r;
}
inline bool intersect_quad(const Quad& q, const Ray& ray, ShapeHit& hit) {  // inline: hot
    const float c[3] = {q.corner.x, q.corner.y, q.corner.z};
    const float n[3] = {q.normal.x, q.normal.y, q.normal.z};
    const float du[3] = {q.dual_u.x, q.dual_u.y, q.dual_u.z};
    const float dv[3] = {q.dual_v.x, q.dual_v.y, q.dual_v.z};
    const QuadTerms<float> r = quad_terms(c, n, du, dv, ray);
    if (r.denom == 0.0f || !(r.t > 0.0f && r.t < ray.t_max)) return false;
    if (!(r.a >= 0.0f && r.a <= 1.0f && r.b >= 0.0f && r.b <= 1.0f)) return false;
    hit.t = r.t;
    hit.u = r.a;
    hit.v = r.b;
    hit.front = r.denom < 0.0f;  // the ray runs against the normal: it arrives from the front
    return true;
}

// Four quads side by side (structure of arrays), as a BVH leaf stores them, intersected at once
// by quad_terms: lane i gives what intersect_quad gives for quad i, bit for bit. Unused lanes
// hold NaN, which hits nothing.
struct QuadBlock {
    Float4 corner[3], normal[3], dual_u[3], dual_v[3];  // [axis][lane]

    void set(int lane, const Quad& q) {
        for (int axis = 0; axis < 3; ++axis) {
            corner[axis][lane] = q.corner[axis];
            normal[axis][lane] = q.normal[axis];
            dual_u[axis][lane] = q.dual_u[axis];
            dual_v[axis][lane] = q.dual_v[axis];
        }
    }
    // Bit i of the result set: quad i is hit within (0, t_max), at terms.t[i], terms.a[i], ...
    [[gnu::always_inline]] unsigned intersect(const Ray& ray, float t_max,
                                              QuadTerms<Float4>& terms) const {
        terms = quad_terms(corner, normal, dual_u, dual_v, ray);
        const auto hit = (terms.denom != 0.0f) & (terms.t > 0.0f) & (terms.t < t_max) &
                         (terms.a >= 0.0f) & (terms.a <= 1.0f) & (terms.b >= 0.0f) &
                         (terms.b <= 1.0f);
        return (hit[0] & 1u) | (hit[1] & 2u) | (hit[2] & 4u) | (hit[3] & 8u);
    }
};
static_assert(sizeof(QuadBlock) == 192);
SurfaceGeometry quad_surface(const Quad& q, const ShapeHit& hit);

// ---------------------------------------------------------------------------------------------
// Triangles use the watertight test of Woop, Benthin and Wald (JCGT 2013): the ray is turned
// into a shear frame where it runs along +z from the origin; the triangle's projected vertices
// then decide the hit by three 2D edge functions whose signs are exact on shared edges, so a ray
// through an edge or vertex of a closed mesh hits at least one of the triangles around it.
// The per-ray shear is computed once per ray, not once per triangle.
struct WatertightRay {
    Vec3 origin;
    int kx, ky, kz;             // permutation that makes the largest direction component z
    float sx, sy, sz;           // shear coefficients
    WatertightRay() = default;  // unset: for scenes without triangles
    explicit WatertightRay(const Ray& ray);
};

// Inline: it is the innermost test of every triangle scene (docs/performance.md).
inline bool intersect_triangle(const WatertightRay& wr, const Vec3& p0, const Vec3& p1,
                               const Vec3& p2, float t_max, ShapeHit& hit) {
    // Vertices relative to the ray origin, sheared so the ray runs along +z.
    const Vec3 a = p0 - wr.origin, b = p1 - wr.origin, c = p2 - wr.origin;
    const float ax = a[wr.kx] - wr.sx * a[wr.kz], ay = a[wr.ky] - wr.sy * a[wr.kz];
    const float bx = b[wr.kx] - wr.sx * b[wr.kz], by = b[wr.ky] - wr.sy * b[wr.kz];
    const float cx = c[wr.kx] - wr.sx * c[wr.kz], cy = c[wr.ky] - wr.sy * c[wr.kz];

    // Edge functions: twice the signed areas of the sub-triangles opposite each vertex.
    float e0 = cx * by - cy * bx;
    float e1 = ax * cy - ay * cx;
    float e2 = bx * ay - by * ax;
    // An exact zero in float may be a rounding artefact: decide the sign in double.
    if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) {
        e0 = static_cast<float>(double(cx) * double(by) - double(cy) * double(bx));
        e1 = static_cast<float>(double(ax) * double(cy) - double(ay) * double(cx));
        e2 = static_cast<float>(double(bx) * double(ay) - double(by) * double(ax));
    }
    if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f))
        return false;  // the ray passes outside one edge
    const float det = e0 + e1 + e2;
    if (det == 0.0f) return false;  // degenerate, or seen exactly edge-on

    // Scaled hit distance; compared against t_max * det so no division is needed to reject.
    const float az = wr.sz * a[wr.kz], bz = wr.sz * b[wr.kz], cz = wr.sz * c[wr.kz];
    const float t_scaled = e0 * az + e1 * bz + e2 * cz;
    if (det < 0.0f && (t_scaled >= 0.0f || t_scaled <= t_max * det)) return false;
    if (det > 0.0f && (t_scaled <= 0.0f || t_scaled >= t_max * det)) return false;

    const float inv_det = 1.0f / det;
    const float t = t_scaled * inv_det;
    // Only accept t if it is positive beyond its own rounding error, so a ray spawned from this
    // triangle (offset by less than that error) cannot re-hit it. Bound from pbrt-v4 (sec. 6.8.7).
    const float max_z = std::max({std::fabs(az), std::fabs(bz), std::fabs(cz)});
    const float max_x = std::max({std::fabs(ax), std::fabs(bx), std::fabs(cx)});
    const float max_y = std::max({std::fabs(ay), std::fabs(by), std::fabs(cy)});
    const float delta_z = gamma_bound(3) * max_z;
    const float delta_x = gamma_bound(5) * (max_x + max_z);
    const float delta_y = gamma_bound(5) * (max_y + max_z);
    const float delta_e =
        2.0f * (gamma_bound(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    const float max_e = std::max({std::fabs(e0), std::fabs(e1), std::fabs(e2)});
    const float delta_t = 3.0f *
                          (gamma_bound(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) *
                          std::fabs(inv_det);
    if (!(t > delta_t)) return false;
    hit.t = t;
    hit.u = e1 * inv_det;
    hit.v = e2 * inv_det;
    // det is twice the triangle's signed area seen along the ray: positive when its vertices
    // run counter-clockwise, i.e. when cross(p1 - p0, p2 - p0) faces the ray.
    hit.front = det > 0.0f;
    return true;
}
// Four triangles side by side (structure of arrays), as a BVH leaf stores them. candidates()
// runs the watertight test's edge functions and distance bounds on all four at once. It is a
// filter: it computes the values intersect_triangle computes, with the same operations in the
// same order (no fused multiply-adds: -ffp-contract=off), so every lane it rejects would be
// rejected there too; the few lanes that pass are then decided by intersect_triangle itself.
// Lanes with an edge function of exactly zero, which the scalar test re-evaluates in double,
// always pass. Unused lanes hold NaN, which passes nothing.
struct TriangleBlock {
    Float4 p[3][3];  // p[vertex][axis][lane]

    Vec3 vertex(int lane, int v) const { return {p[v][0][lane], p[v][1][lane], p[v][2][lane]}; }
    void set(int lane, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
        const Vec3* v[3] = {&p0, &p1, &p2};
        for (int k = 0; k < 3; ++k)
            for (int axis = 0; axis < 3; ++axis) p[k][axis][lane] = (*v[k])[axis];
    }

    // Bit i set: triangle i may be hit within (0, t_max).
    [[gnu::always_inline]] unsigned candidates(const WatertightRay& wr, float t_max) const {
        Float4 x[3], y[3], z[3];  // the vertices relative to the origin, in the shear frame
        for (int k = 0; k < 3; ++k) {
            const Float4 dx = p[k][wr.kx] - wr.origin[wr.kx];
            const Float4 dy = p[k][wr.ky] - wr.origin[wr.ky];
            const Float4 dz = p[k][wr.kz] - wr.origin[wr.kz];
            x[k] = dx - wr.sx * dz;
            y[k] = dy - wr.sy * dz;
            z[k] = wr.sz * dz;
        }
        const Float4 e0 = x[2] * y[1] - y[2] * x[1];
        const Float4 e1 = x[0] * y[2] - y[0] * x[2];
        const Float4 e2 = x[1] * y[0] - y[1] * x[0];
        const auto exact_zero = (e0 == 0.0f) | (e1 == 0.0f) | (e2 == 0.0f);
        const auto outside =
            ((e0 < 0.0f) | (e1 < 0.0f) | (e2 < 0.0f)) & ((e0 > 0.0f) | (e1 > 0.0f) | (e2 > 0.0f));
        const Float4 det = e0 + e1 + e2;
        const Float4 t_scaled = e0 * z[0] + e1 * z[1] + e2 * z[2];
        const Float4 t_det = t_max * det;
        const auto in_range = ((det < 0.0f) & (t_scaled < 0.0f) & (t_scaled > t_det)) |
                              ((det > 0.0f) & (t_scaled > 0.0f) & (t_scaled < t_det));
        const auto pass = exact_zero | (~outside & in_range);
        return (pass[0] & 1u) | (pass[1] & 2u) | (pass[2] & 4u) | (pass[3] & 8u);
    }
};
static_assert(sizeof(TriangleBlock) == 144);

// Moller-Trumbore without watertightness, kept only to demonstrate cracks along edges.
bool intersect_triangle_moller_trumbore(const Ray& ray, const Vec3& p0, const Vec3& p1,
                                        const Vec3& p2, ShapeHit& hit);

}  // namespace lessons
