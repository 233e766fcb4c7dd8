// Lesson 2: Whitted-style recursive ray tracing (Whitted 1980).
//
// At a diffuse or glossy hit: shadow rays and local shading, exactly as lesson 1, then stop.
// At a mirror or glass hit: the ray continues, recursively, along the reflected and the
// refracted directions:
//
//   mirror:  L = L_e + R * L(p, reflect(wo))
//   glass:   L = L_e + F(theta) * L(p, reflect(wo)) + T (1 - F(theta)) / eta^2 * L(p, refract(wo))
//
// with F the Fresnel reflectance (exact, or Schlick's approximation), eta = n_t / n_i, T the
// glass's transmittance (1 for clear glass), and all
// of it (F = 1) reflected past the critical angle. Recursion stops at a maximum depth, or when
// the product of the weights along the path (its attenuation) falls below a threshold; a stopped
// ray contributes nothing.
#pragma once

#include "01_ray_casting/ray_casting.h"
#include "render/model.h"
#include "scene/scene.h"

namespace lessons {

struct WhittedOptions {
    Color ambient{0.0f};            // L_a at diffuse hits, as in lesson 1
    int max_bounces = 12;           // specular bounces after the camera ray
    float min_attenuation = 1e-4f;  // stop when every channel of the path weight is below this
    bool schlick = false;           // Schlick's Fresnel approximation instead of the exact form
};

// The radiance along `ray`, which has already been through `depth` specular bounces and whose
// contribution to the pixel is scaled by `attenuation`.
Color whitted(const Scene& scene, const Ray& ray, const WhittedOptions& options, int depth = 0,
              const Color& attenuation = Color(1.0f));

// Lesson 2 as a model the render loop runs: whitted for every pixel sample, with notes on what
// the recursion shows and what it misses in this scene. `scene` must outlive it.
class WhittedModel final : public Model {
public:
    WhittedModel(const Scene& scene, const WhittedOptions& options);
    Color sample(const Ray& ray, Rng& rng, uint32_t pixel, std::span<Color> layers,
                 std::vector<Splat>& splats) const override;

private:
    const Scene& scene_;
    WhittedOptions options_;
};

}  // namespace lessons
