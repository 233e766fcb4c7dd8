// What a ray's hit produces, below every floor that uses it: the primitive it hit (PrimRef, by
// kind and index), the hit itself (Hit) and the full description of the surface there
// (SurfaceInteraction), which the materials shade and the lessons spawn rays from. The scene
// (scene/scene.h) computes them; the BSDFs (materials/) read them without knowing the scene.
#pragma once

#include <cstdint>

#include "geometry/math.h"
#include "geometry/shapes.h"
#include "geometry/spawn.h"

namespace lessons {

enum class ShapeKind : uint32_t { Sphere = 0, Quad = 1, Triangle = 2 };

// A primitive: its kind in the top two bits, its index in that kind's array below.
struct PrimRef {
    uint32_t bits = 0;
    PrimRef() = default;
    PrimRef(ShapeKind kind, uint32_t index) : bits((static_cast<uint32_t>(kind) << 30) | index) {}
    ShapeKind kind() const { return static_cast<ShapeKind>(bits >> 30); }
    uint32_t index() const { return bits & 0x3fffffffu; }
    bool operator==(const PrimRef&) const = default;
};

struct Hit {
    ShapeHit shape;  // t and surface parameters
    PrimRef prim;
};

// Everything a lesson needs to shade a hit point.
struct SurfaceInteraction {
    Vec3 p;          // position
    Vec3 p_error;    // per-axis bound on the rounding error of p (for spawning rays)
    Vec3 n_geo;      // unit geometric normal, the shape's outward (front) side
    Vec3 n_shading;  // unit shading normal, same side as n_geo
    Vec2 uv;         // texture coordinates
    Vec3 wo;         // unit direction back along the incoming ray (points away from the surface)
    float t;         // ray parameter of the hit
    uint32_t material;
    PrimRef prim;
    bool front = true;  // the ray arrived on n_geo's side (decided by the intersection test)
    bool shading_fallback = true;  // false only under --naive shading-normals

    bool front_face() const { return front; }
    SurfacePoint surface_point() const { return {p, p_error, n_geo}; }
};

}  // namespace lessons
