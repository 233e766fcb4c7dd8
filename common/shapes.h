// The shapes a scene is built from: analytic spheres, parallelograms ("quads") and triangles.
// Each shape intersects itself with a ray and reports its bounds; the BVH knows only the bounds.
//
// An intersection routine answers the smallest t in (0, ray.t_max) and, for later shading, two
// surface parameters (barycentrics for triangles, edge coordinates for quads). The full surface
// description (point, normals, texture coordinates) is computed only for the nearest hit, by
// the surface_* functions, so rejected candidates cost as little as possible.
#pragma once

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
    Vec3 normal;       // unit
    Vec3 inv_cross;    // cross(edge_u, edge_v) / |cross(edge_u, edge_v)|^2, for edge coordinates
    float area_value;  // |cross(edge_u, edge_v)|

    Quad() = default;
    Quad(const Vec3& corner, const Vec3& edge_u, const Vec3& edge_v);
    Bounds3 bounds() const;
    float area() const { return area_value; }
    Vec3 center() const { return corner + 0.5f * (edge_u + edge_v); }
};

// Plane hit, then the edge coordinates a, b of the hit point; edges are included on both sides,
// so two quads sharing an edge leave no crack between them.
bool intersect_quad(const Quad& q, const Ray& ray, ShapeHit& hit);
SurfaceGeometry quad_surface(const Quad& q, const ShapeHit& hit);

// ---------------------------------------------------------------------------------------------
// Triangles use the watertight test of Woop, Benthin and Wald (JCGT 2013): the ray is turned
// into a shear frame where it runs along +z from the origin; the triangle's projected vertices
// then decide the hit by three 2D edge functions whose signs are exact on shared edges, so a ray
// through an edge or vertex of a closed mesh hits at least one of the triangles around it.
// The per-ray shear is computed once per ray, not once per triangle.
struct WatertightRay {
    Vec3 origin;
    int kx, ky, kz;    // permutation that makes the largest direction component z
    float sx, sy, sz;  // shear coefficients
    explicit WatertightRay(const Ray& ray);
};

bool intersect_triangle(const WatertightRay& wr, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                        float t_max, ShapeHit& hit);
// Moller-Trumbore without watertightness, kept only to demonstrate cracks along edges.
bool intersect_triangle_moller_trumbore(const Ray& ray, const Vec3& p0, const Vec3& p1,
                                        const Vec3& p2, ShapeHit& hit);

}  // namespace lessons
