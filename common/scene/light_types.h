// The lights a scene holds, as plain data: point and spot lights, directional lights, area
// lights (emissive primitives), and the kinds that name them (LightKind, LightRef). The scene
// (scene.h) stores them; the light sampler (lights/lights.h) chooses and samples them.
#pragma once

#include <cstdint>
#include <optional>

#include "geometry/interaction.h"
#include "geometry/math.h"

namespace lessons {

// A point light: radiant intensity I (W/sr) from one point, the same in every direction; or, with
// a cone, a spot light: I along its axis, fading to nothing at the cone's edge.
struct SpotCone {
    Vec3 axis;        // unit, the direction the spot points
    float cos_outer;  // cos of the half-angle to the cone's edge: no light beyond it
    float cos_inner;  // cos of the half-angle within which the full intensity leaves (>= cos_outer)
    // The fraction of the intensity that leaves along unit direction w: 1 within the inner cone,
    // 0 beyond the outer, and between them smoothstep(t) = t^2 (3 - 2 t) of
    // t = (cos - cos_outer) / (cos_inner - cos_outer), as Blender's spot blend fades.
    float falloff(const Vec3& w) const {
        const float c = glm::dot(axis, w);
        if (c <= cos_outer) return 0.0f;
        if (c >= cos_inner) return 1.0f;
        const float t = (c - cos_outer) / (cos_inner - cos_outer);
        return t * t * (3.0f - 2.0f * t);
    }
    // The integral of falloff over the sphere, sr: 2 pi times the integral over cos theta, the
    // full part (1 - cos_inner) plus the fade's, where smoothstep averages 1/2.
    float solid_angle() const {
        return 2.0f * kPi * ((1.0f - cos_inner) + 0.5f * (cos_inner - cos_outer));
    }
};

struct PointLight {
    Vec3 position;
    Color intensity;  // radiant intensity, W/sr (a spot's: along its axis)
    std::optional<SpotCone> cone = std::nullopt;  // a spot light's; none: the same everywhere
    // The intensity leaving along unit direction w.
    Color intensity_towards(const Vec3& w) const {
        return cone ? intensity * cone->falloff(w) : intensity;
    }
    // Power, W per channel: 4 pi I, or I times the spot's solid_angle.
    Color power() const { return intensity * (cone ? cone->solid_angle() : 4.0f * kPi); }
};

// A directional light (the sun, as a renderer models it): parallel light from infinitely far
// away, the same irradiance E on every surface facing it, E cos(theta) on one tilted by theta.
struct DirectionalLight {
    Vec3 direction;    // unit, the way the light travels
    Color irradiance;  // E, W/m^2 per channel, on a surface facing the light
};

// An emissive surface. Its radiance comes from its material; the geometry summary here is
// what every lesson needs to treat it as a light.
struct AreaLight {
    PrimRef prim;
    uint32_t material;
    Color radiance;  // emitted radiance L_e, W / (sr m^2)
    bool two_sided;
    float area;              // m^2
    Vec3 center;             // centroid (sphere: its center)
    Vec3 center_error;       // rounding-error bound of center (for shadow rays ending on it)
    Vec3 normal;             // unit emitting normal (zero for spheres, which emit all around)
    bool rectangle = false;  // a quad with orthogonal edges: sampled by solid angle (lights.h)
};

// The kinds of light. Code that treats every light alike goes through Scene::lights(); code
// that must tell them apart switches on the kind, once per purpose (docs/architecture.md lists
// where: "A light").
enum class LightKind {
    Point,        // a PointLight (and spot lights)
    Directional,  // a DirectionalLight
    Area,         // an AreaLight: an emissive primitive
    Environment,  // the background: a uniform sky or an environment map
};

// One light of a scene: its kind, and its index into Scene::point_lights(),
// directional_lights() or area_lights() (0 for the environment, of which a scene has at most one).
struct LightRef {
    LightKind kind;
    uint32_t index;
};

}  // namespace lessons
