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
#include <utility>

#include "geometry/bounds.h"
#include "geometry/math.h"
#include "geometry/simd.h"
#include "geometry/spawn.h"

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
    // The point of the sphere in unit direction n from its centre, with the bound on its
    // rounding error (five operations per coordinate) that rays leaving or reaching it need.
    SurfacePoint point_at(const Vec3& n) const {
        return {center + radius * n, gamma_bound(5) * (glm::abs(center) + Vec3(radius)), n};
    }
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
        return lane_bits(hit);
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
    float ox, oy, oz;           // the origin's coordinates along axes kx, ky, kz (kept permuted,
                                // so that no test indexes a vector by a runtime axis)
    int kx, ky, kz;             // permutation that makes the largest direction component z
    float sx, sy, sz;           // shear coefficients
    WatertightRay() = default;  // unset: for scenes without triangles
    explicit WatertightRay(const Ray& ray) {
        // Plain arrays: indexing a glm vector by a runtime axis compiles to a switch.
        const float d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
        const float o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
        const float ax = std::fabs(d[0]), ay = std::fabs(d[1]), az = std::fabs(d[2]);
        // The axis of the largest component, and the swap below, by arithmetic on comparison
        // results instead of branches: for incoherent rays both are random, and a mispredicted
        // branch costs more than these few integer operations (docs/performance.md, item 12).
        const int y_over_x = !(ax > ay);  // kz = 0 or 1, before z is considered
        const float larger = y_over_x ? ay : ax;
        const int z_largest = !(larger > az);
        kz = y_over_x + z_largest * (2 - y_over_x);
        const int next = kz == 2 ? 0 : kz + 1, after = 3 - kz - next;
        const int flip = -static_cast<int>(d[kz] < 0.0f);  // keep the winding of the edge functions
        kx = next ^ ((next ^ after) & flip);
        ky = after ^ ((next ^ after) & flip);
        sx = d[kx] / d[kz];
        sy = d[ky] / d[kz];
        sz = 1.0f / d[kz];
        ox = o[kx];
        oy = o[ky];
        oz = o[kz];
    }
};

// The watertight test's arithmetic, written once for one triangle (T = float) and for four side
// by side (T = Float4, TriangleBlock), so both give the same bits (no fused multiply-adds:
// -ffp-contract=off). p[vertex][axis] holds the triangle's vertices.
template <class T>
struct WatertightTerms {
    // The vertices relative to the ray origin, sheared so that the ray runs along +z from the
    // origin (z scaled by sz, so that z is the hit distance at a vertex).
    T x[3], y[3], z[3];
    // Edge functions: twice the signed areas of the sub-triangles opposite each vertex.
    T e0, e1, e2;
};
template <class T>
[[gnu::always_inline]] inline WatertightTerms<T> watertight_terms(const WatertightRay& wr,
                                                                  const T (&p)[3][3]) {
    WatertightTerms<T> w;
    for (int k = 0; k < 3; ++k) {
        const T dx = p[k][wr.kx] - wr.ox;
        const T dy = p[k][wr.ky] - wr.oy;
        const T dz = p[k][wr.kz] - wr.oz;
        w.x[k] = dx - wr.sx * dz;
        w.y[k] = dy - wr.sy * dz;
        w.z[k] = wr.sz * dz;
    }
    w.e0 = w.x[2] * w.y[1] - w.y[2] * w.x[1];
    w.e1 = w.x[0] * w.y[2] - w.y[0] * w.x[2];
    w.e2 = w.x[1] * w.y[0] - w.y[1] * w.x[0];
    return w;
}
inline float max_of(float a, float b) {
    return a < b ? b : a;
}
inline Float4 max_of(Float4 a, Float4 b) {
    return a < b ? b : a;
}
inline Float4 min_of(Float4 a, Float4 b) {
    return a < b ? a : b;
}
// A Float4's bits, for operations on the sign bit.
using Bits4 = uint32_t __attribute__((vector_size(16)));
// x negated (its sign bit flipped) in the lanes where s's sign bit is set: exact.
inline Float4 without_sign_of(Float4 x, Float4 s) {
    return reinterpret_cast<Float4>(reinterpret_cast<Bits4>(x) ^
                                    (reinterpret_cast<Bits4>(s) & 0x80000000u));
}
inline float abs_of(float a) {
    return std::fabs(a);
}
inline Float4 abs_of(Float4 a) {  // clears the sign bits, as fabs does
    return reinterpret_cast<Float4>(reinterpret_cast<Bits4>(a) & 0x7fffffffu);
}
// How far the computed t = t_scaled / det may lie from the true distance, at most: a hit is
// accepted only beyond it, so a ray spawned from this triangle (offset by less than that error)
// cannot hit it again. Bound from pbrt-v4 (sec. 6.8.7).
template <class T>
[[gnu::always_inline]] inline T watertight_t_error(const WatertightTerms<T>& w, T inv_det) {
    const T max_z = max_of(max_of(abs_of(w.z[0]), abs_of(w.z[1])), abs_of(w.z[2]));
    const T max_x = max_of(max_of(abs_of(w.x[0]), abs_of(w.x[1])), abs_of(w.x[2]));
    const T max_y = max_of(max_of(abs_of(w.y[0]), abs_of(w.y[1])), abs_of(w.y[2]));
    const T delta_z = gamma_bound(3) * max_z;
    const T delta_x = gamma_bound(5) * (max_x + max_z);
    const T delta_y = gamma_bound(5) * (max_y + max_z);
    const T delta_e = 2.0f * (gamma_bound(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    const T max_e = max_of(max_of(abs_of(w.e0), abs_of(w.e1)), abs_of(w.e2));
    return 3.0f * (gamma_bound(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) *
           abs_of(inv_det);
}

// Inline: it is the innermost test of every triangle scene (docs/performance.md).
inline bool intersect_triangle(const WatertightRay& wr, const Vec3& p0, const Vec3& p1,
                               const Vec3& p2, float t_max, ShapeHit& hit) {
    const float p[3][3] = {{p0.x, p0.y, p0.z}, {p1.x, p1.y, p1.z}, {p2.x, p2.y, p2.z}};
    const WatertightTerms<float> w = watertight_terms(wr, p);
    float e0 = w.e0, e1 = w.e1, e2 = w.e2;
    // An exact zero in float may be a rounding artefact: decide the sign in double.
    if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) {
        auto edge = [&](int i, int j) {
            return static_cast<float>(double(w.x[i]) * double(w.y[j]) -
                                      double(w.y[i]) * double(w.x[j]));
        };
        e0 = edge(2, 1);
        e1 = edge(0, 2);
        e2 = edge(1, 0);
    }
    if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f))
        return false;  // the ray passes outside one edge
    const float det = e0 + e1 + e2;
    if (det == 0.0f) return false;  // degenerate, or seen exactly edge-on

    // Scaled hit distance; compared against t_max * det so no division is needed to reject.
    const float t_scaled = e0 * w.z[0] + e1 * w.z[1] + e2 * w.z[2];
    if (det < 0.0f && (t_scaled >= 0.0f || t_scaled <= t_max * det)) return false;
    if (det > 0.0f && (t_scaled <= 0.0f || t_scaled >= t_max * det)) return false;

    const float inv_det = 1.0f / det;
    const float t = t_scaled * inv_det;
    WatertightTerms<float> exact = w;  // the error bound reads the edge functions as decided
    exact.e0 = e0;
    exact.e1 = e1;
    exact.e2 = e2;
    if (!(t > watertight_t_error(exact, inv_det))) return false;
    hit.t = t;
    hit.u = e1 * inv_det;
    hit.v = e2 * inv_det;
    // det is twice the triangle's signed area seen along the ray: positive when its vertices
    // run counter-clockwise, i.e. when cross(p1 - p0, p2 - p0) faces the ray.
    hit.front = det > 0.0f;
    return true;
}

// Four triangles side by side (structure of arrays), as a BVH leaf stores them, intersected at
// once by the same arithmetic: lane i gives what intersect_triangle gives for triangle i, bit for
// bit, except in lanes with an edge function of exactly zero, which the scalar test re-evaluates
// in double: those lanes are left to it (`recheck`). Unused lanes hold NaN, which hits nothing.
struct TriangleHits4 {
    Float4 t, u, v, det;  // distance, barycentrics of vertices 1 and 2; det > 0: the front side
};
struct TriangleBlock {
    Float4 p[3][3];  // p[vertex][axis][lane]

    Vec3 vertex(int lane, int v) const { return {p[v][0][lane], p[v][1][lane], p[v][2][lane]}; }
    void set(int lane, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
        const Vec3* v[3] = {&p0, &p1, &p2};
        for (int k = 0; k < 3; ++k)
            for (int axis = 0; axis < 3; ++axis) p[k][axis][lane] = (*v[k])[axis];
    }

    // Bit i of the result set: triangle i is hit within (0, t_max), as `hits` says. Bit i of
    // `recheck` set: lane i is for intersect_triangle to decide.
    [[gnu::always_inline]] unsigned intersect(const WatertightRay& wr, float t_max,
                                              TriangleHits4& hits, unsigned& recheck) const {
        const WatertightTerms<Float4> w = watertight_terms(wr, p);
        const auto exact_zero = (w.e0 == 0.0f) | (w.e1 == 0.0f) | (w.e2 == 0.0f);
        // The scalar test's conditions, in fewer operations with the same candidates: some edge
        // function is negative and some positive exactly when their minimum is negative and
        // their maximum positive; and t_scaled lies strictly between 0 and t_max det (on det's
        // side of 0) exactly when, with det's sign taken off both (an exact negation), it lies
        // strictly between 0 and t_max |det|. Only where an edge function is NaN may `outside`
        // differ (a minimum or maximum drops a NaN or keeps it, by its place), but there det is
        // NaN too and `in_range` false: `outside` means nothing without it.
        const auto outside =
            (min_of(min_of(w.e0, w.e1), w.e2) < 0.0f) & (max_of(max_of(w.e0, w.e1), w.e2) > 0.0f);
        const Float4 det = w.e0 + w.e1 + w.e2;
        const Float4 t_scaled = w.e0 * w.z[0] + w.e1 * w.z[1] + w.e2 * w.z[2];
        const Float4 t_det = t_max * det;
        const Float4 t_unsigned = without_sign_of(t_scaled, det);
        const auto in_range = (t_unsigned > 0.0f) & (t_unsigned < without_sign_of(t_det, det));
        recheck = lane_bits(exact_zero);
        const unsigned candidates = lane_bits(~exact_zero & ~outside & in_range);
        if (candidates == 0) return 0;  // the common case: finish only the lanes still in play
        const Float4 inv_det = 1.0f / det;
        hits.t = t_scaled * inv_det;
        hits.u = w.e1 * inv_det;
        hits.v = w.e2 * inv_det;
        hits.det = det;
        return candidates & lane_bits(hits.t > watertight_t_error(w, inv_det));
    }
};
static_assert(sizeof(TriangleBlock) == 144);

// Moller-Trumbore without watertightness, kept only to demonstrate cracks along edges.
bool intersect_triangle_moller_trumbore(const Ray& ray, const Vec3& p0, const Vec3& p1,
                                        const Vec3& p2, ShapeHit& hit);

}  // namespace lessons
