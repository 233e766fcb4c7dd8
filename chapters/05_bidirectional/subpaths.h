// Lesson 5, section 1: the two subpaths. A camera subpath z_0 z_1 ... starts at the camera, a
// light subpath y_0 y_1 ... at a point of a light; each continues by sampling its BSDFs, as
// lesson 4's path does. Every vertex keeps what the connections and their weights need later:
//   beta      the subpath's throughput up to the vertex (lesson 4's beta; on the light side
//             L_e / p(y_0), then times f cos / p at every bounce: a flux-like "importance")
//   pdf_fwd   the density, per unit area at the vertex, with which its own subpath reached it
//   pdf_rev   the density with which the *other* subpath would have reached it, coming from the
//             next vertex (the literature's p_rev; Veach 1997, ch. 10; pbrt-v3, 16.3)
// Densities per unit area make the two directions comparable: a direction sampled at x with
// density p(w) per steradian lands at y with density p(w) |cos(theta_y)| / d^2 per m^2.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "lights/lights.h"
#include "materials/bsdf.h"
#include "sampling/random_numbers.h"
#include "scene/scene.h"

namespace lessons {

// What lesson 5 asks of the scene, the lights and the camera, in one place.
struct Bidir {
    const Scene& scene;
    const LightSampler& lights;
    const Camera& camera;
    int width, height;
};

enum class VertexType { Camera, Light, Surface };

struct Vertex {
    VertexType type = VertexType::Surface;
    // Position; for the environment and a directional light (lights at infinity), the unit
    // direction towards them.
    Vec3 p{0.0f};
    // Unit geometric normal: of the surface, or of a light's emitting side; zero for points (the
    // camera's pinhole, a point light) and for lights at infinity.
    Vec3 n{0.0f};
    bool infinite = false;     // the environment
    bool point_light = false;  // a point light: a delta position, never hit by a camera path
    bool directional = false;  // a directional light: a delta direction, never hit either;
                               // its light crosses the scene in parallel, so the density
                               // of the next vertex is per m^2 across the beam, times cos
    uint32_t light_index = 0;  // a point or directional light's, into the scene's list of them
    std::optional<PrimRef> emitter;  // a Light vertex on an emissive surface
    SurfaceInteraction si{};         // Surface vertices: the hit (si.wo points back along the
                                     // subpath)
    std::optional<Bsdf> bsdf;        // Surface vertices
    Color beta{0.0f};
    bool delta = false;  // scattered by a mirror or glass: no connection is made here
    float pdf_fwd = 0.0f, pdf_rev = 0.0f;
    // On a light: the density with which a light sample taken at its neighbour on the path (the
    // vertex after it, towards the camera) picks it (light_sample_density), for the weights.
    float pdf_light_sample = 0.0f;

    SurfacePoint surface_point() const { return {p, si.p_error, n}; }
    // The primitive the vertex lies on: a light vertex's emitter (none for a point light or the
    // sky), a surface vertex's hit; none for the camera.
    std::optional<PrimRef> primitive() const {
        if (type == VertexType::Light) return emitter;
        if (type == VertexType::Surface) return si.prim;
        return std::nullopt;
    }
    // Whether a strategy may join a segment to this vertex: not at a mirror or glass, and not at
    // the environment (its light is found by the camera path escaping, s = 0, or by a light
    // sample, s = 1).
    bool connectible() const { return !delta && !infinite && !directional; }
    // A point or directional light: no camera path can reach it.
    bool delta_light() const { return point_light || directional; }
};

// The pixel, as column and row, that a film position (Camera::raster_position) falls in: where
// light tracing splats, and what the lamp's weights (mis.h) ask about.
glm::ivec2 pixel_at(const Bidir& b, const Vec2& raster);

// The unit direction from vertex `from` towards `to` (towards the sky for the environment; a
// directional light's own, from it).
Vec3 direction(const Vertex& from, const Vertex& to);
// A solid-angle density at `from` for the direction towards `to`, as a density per unit area
// at `to` (unchanged for lights at infinity, whose vertices are directions). From a directional
// light, the density is per m^2 across its beam, and becomes per m^2 at `to` by |cos| alone.
float to_area_density(float pdf_solid_angle, const Vertex& from, const Vertex& to);

// The densities of the weights: how likely each strategy was to make a vertex.
// p_A(next) when vertex v samples the direction towards `next`, having been reached from
// `previous` (ignored at the camera and at lights): its BSDF's density, the camera's, or the
// light's emission density.
float density_towards(const Bidir& b, const Vertex& v, const Vertex* previous, const Vertex& next);
// The density with which a light subpath starts at v (which must lie on a light): per unit area
// (the light's choice probability over its area; a point light's choice probability alone), and
// per steradian for the environment.
float light_origin_density(const Bidir& b, const Vertex& v);
// The density per unit area at `next` of a light subpath leaving the light point v towards it.
float light_emission_density(const Bidir& b, const Vertex& v, const Vertex& next);
// The density with which a light sample taken at `from` (lesson 3's, by solid angle where it
// can) picks the light point v: per unit area on an area light; a point light's and the sky's
// are their origin densities (a choice probability; per steradian).
float light_sample_density(const Bidir& b, const Vertex& v, const Vertex& from);

// The camera subpath of the primary ray: z_0 the pinhole, then up to max_vertices - 1 hits (and
// a last vertex at the environment if the path escapes into a sky).
void camera_subpath(const Bidir& b, const Ray& ray, RandomNumbers& rng, int max_vertices,
                    int roulette_after, std::vector<Vertex>& path);
// A light subpath: y_0 on a light chosen by power, then up to max_vertices - 1 hits. Empty when
// the chosen light starts none (the environment).
void light_subpath(const Bidir& b, RandomNumbers& rng, int max_vertices, int roulette_after,
                   std::vector<Vertex>& path);

// Both subpaths of one given path x_0 ... x_{n-1}, made vertex by vertex as the walks above make
// them, but with each direction pointing at the next vertex instead of sampled (with the density
// the BSDF would have sampled it with), so that a strategy's weights can be checked against all
// the others' on the same path (tests/test_bidirectional.cpp). `light` is x_0: a light vertex
// (p and n, its emitting side's normal, and emitter; or point_light and p; or infinite and p,
// the direction towards the sky; or directional and p, the direction towards that light); `points`
// are x_1 .. x_{n-2}, each where a ray from the vertex before meets the scene first; x_{n-1} is the
// camera. The camera subpath goes from the camera to x_0 (to x_1 for a point light, which no camera
// path reaches), the light subpath from x_0 to x_{n-2} (none for the sky; its y_0.pdf_fwd is 0 if
// the light is never chosen). Nothing if some segment is blocked, or a direction has density 0
// (then `why` says which).
struct GivenSubpaths {
    std::vector<Vertex> light, camera;
};
std::optional<GivenSubpaths> subpaths_along(const Bidir& b, const Vertex& light,
                                            std::span<const Vec3> points,
                                            std::string* why = nullptr);

// f |cos| of a light-subpath vertex for light arriving from si.wo and leaving along w (towards
// the camera's side of the path): the BSDF seen from w, as the camera side sees it (the
// shading-normal fallback decided by w: Bsdf::seen_from), with the correction that interpolated
// shading normals need on this side (the adjoint of a shading-normal BSDF is not the same BSDF:
// Veach 1997, 5.3): f |si.wo . n_s| |w . n_g| / |si.wo . n_g|.
Color light_side_scattering(const Bidir& b, const Vertex& v, const Vec3& w);

}  // namespace lessons
