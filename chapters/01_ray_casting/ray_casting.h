// Lesson 1: ray casting. One ray per pixel sample, the nearest hit, one shadow ray to each
// light, and local shading:
//
//   L = L_e + k_d * L_a + sum over lights l of  f(wo, wi_l) * I_l cos(theta_i) / d_l^2 * V_l
//
//   f(wo, wi) = k_d / pi + k_s N(e) (n . h)^e      (Lambert + normalised Blinn-Phong, bsdf.h)
//
// with L_a a constant ambient radiance standing in for all indirect light, I_l the light's
// intensity towards the point, d_l its distance, V_l = 1 if the shadow ray reaches it.
// Area lights are treated as point sources at their centre (hard shadows).
#pragma once

#include <string>
#include <vector>

#include "materials/bsdf.h"
#include "render/app.h"
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

Model make_ray_casting_model(const Scene& scene, const RayCastingOptions& options);

// The lesson as the command line and the studio run it: its name, flags and model (lesson.cpp).
Lesson ray_casting_lesson();

// The --ambient flag of the local models (lessons 1 and 2): one grey value or R G B, stored in
// `values`; ambient_radiance() turns it into L_a, the scene's background radiance by default.
void add_ambient_option(CLI::App& app, std::vector<float>& values);
Color ambient_radiance(const std::vector<float>& values, const Scene& scene);

}  // namespace lessons
