// Lesson 1: ray casting. One ray per pixel sample, the nearest hit, one shadow ray to each
// light, and local shading:
//
//   L = L_e + k_d * L_a + sum over lights l of  f(wo, wi_l) * I_l cos(theta_i) / d_l^2 * V_l
//
//   f(wo, wi) = k_d / pi + k_s N(e) (n . h)^e      (Lambert + normalised Blinn-Phong, bsdf.h)
//
// with L_a a constant ambient radiance standing in for all indirect light, I_l the light's
// intensity towards the point, d_l its distance, V_l = 1 if the shadow ray reaches it. A
// directional light gives every point facing it the same irradiance E in place of I_l / d_l^2.
// Area lights are treated as point sources at their centre (hard shadows).
#pragma once

#include <string>
#include <vector>

#include "materials/bsdf.h"
#include "render/model.h"
#include "scene/scene.h"

namespace lessons {

// A material as the local model sees it: a diffuse and a Blinn-Phong reflectance.
struct LocalMaterial {
    Color k_d{0.0f};        // diffuse reflectance (albedo)
    Color k_s{0.0f};        // specular reflectance of the highlight
    float exponent = 1.0f;  // Blinn-Phong exponent e
};

// How the local model reads each material type; appends a note for each approximation.
LocalMaterial local_material(const Material& m, const Vec2& uv);
std::vector<std::string> local_material_notes(const Scene& scene);
// The notes lesson 2 shares, as it shares the shading they describe.
std::string glossy_as_highlight_note(const Material& m);
std::string area_lights_as_points_note(const Scene& scene);
std::string ambient_note(const Color& ambient);
// What lessons 1 and 2 make of an environment map (empty without one).
std::string environment_map_note(const Scene& scene);

// Direct light from every light in the scene, each treated as a point source, with one shadow
// ray each: the sum over lights of f * I cos / d^2 * V.
Color direct_local(const Scene& scene, const SurfaceInteraction& si, const LocalMaterial& m,
                   const Vec3& n);

struct RayCastingOptions {
    Color ambient{0.0f};  // L_a, radiance
};

// The radiance along a camera ray in the ray-casting model.
Color ray_cast(const Scene& scene, const Ray& ray, const RayCastingOptions& options);

// Lesson 1 as a model the render loop runs: ray_cast for every pixel sample, with notes on
// what the local model makes of this scene's materials and lights. `scene` must outlive it.
class RayCastingModel final : public Model {
public:
    RayCastingModel(const Scene& scene, const RayCastingOptions& options);
    Color sample(const Ray& ray, Rng& rng, uint32_t pixel, std::span<Color> layers,
                 std::vector<Splat>& splats) const override;

private:
    const Scene& scene_;
    RayCastingOptions options_;
};

}  // namespace lessons
