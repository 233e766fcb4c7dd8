// Lesson 3: the reflection equation, solved by Monte Carlo integration.
//
//   L_o(p, wo) = L_e(p, wo) + integral over the hemisphere of f(p, wo, wi) L_i(p, wi) cos(theta_i)
//   dwi
//
// where L_i is the radiance emitted by whatever the ray from p in direction wi reaches first
// (an emissive surface, or the environment): direct illumination, one bounce, no recursion.
// One sample of the integral is f L_i cos(theta_i) / p(wi); the estimators differ only in the
// density p they draw wi from:
//   uniform  p = 1 / (2 pi)                 every direction of the hemisphere alike
//   cosine   p = cos(theta) / pi            more where the cosine is large
//   brdf     p ~ f cos                      where the BRDF sends light
//   light    p ~ the light's solid angle    towards the lights (and point lights)
//   mis      one light and one BRDF sample, each weighted by the heuristic of its densities
#pragma once

#include <string>
#include <utility>

#include "lights/lights.h"
#include "materials/bsdf.h"
#include "render/model.h"
#include "scene/scene.h"

namespace lessons {

enum class Estimator { Uniform, Cosine, Brdf, Light, Mis };
enum class MisHeuristic { Balance, Power };

struct ReflectionOptions {
    Estimator estimator = Estimator::Mis;
    MisHeuristic heuristic = MisHeuristic::Power;
};

// The estimators by name, in the lecture's order (the --estimator flag offers them so).
inline constexpr std::pair<const char*, Estimator> kEstimatorNames[] = {
    {"uniform", Estimator::Uniform},
    {"cosine", Estimator::Cosine},
    {"brdf", Estimator::Brdf},
    {"light", Estimator::Light},
    {"mis", Estimator::Mis}};
const char* estimator_name(Estimator e);

// One light sample of the reflection equation at `si`: f L cos / p_light towards a point chosen
// by the light sampler, 0 if it is occluded or behind the surface; with `mis`, weighted against
// the BSDF's density for the same direction. (Lesson 4 takes the same sample at every path
// vertex: next-event estimation.)
Color light_sample_term(const Scene& scene, const LightSampler& lights,
                        const SurfaceInteraction& si, const Bsdf& bsdf, Rng& rng, bool mis,
                        MisHeuristic heuristic);

// The radiance along a camera ray: emission plus one sample of the reflection equation.
Color reflection_equation(const Scene& scene, const LightSampler& lights, const Ray& ray, Rng& rng,
                          const ReflectionOptions& options);

// Lesson 3 as a model the render loop runs: reflection_equation for every pixel sample, with
// its own light sampler. `scene` must outlive it.
class ReflectionModel final : public Model {
public:
    ReflectionModel(const Scene& scene, const ReflectionOptions& options);
    Color sample(const Ray& ray, Rng& rng, uint32_t pixel, std::span<Color> layers,
                 std::vector<Splat>& splats) const override;

private:
    const Scene& scene_;
    LightSampler lights_;
    ReflectionOptions options_;
};

}  // namespace lessons
