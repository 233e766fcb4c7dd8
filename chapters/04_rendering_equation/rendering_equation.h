// Lesson 4: the rendering equation, by Monte Carlo path tracing. It adds to lesson 3 the
// recursion: the light arriving at a point is the light leaving another point, emitted or
// reflected, so a path continues after its first bounce, carrying its throughput beta.
//
//   L_o(p, wo) = L_e(p, wo) + integral over the hemisphere of L_i(p, wi) f(p, wo, wi) cos(theta_i)
//   dwi
//
// with L_i(p, wi) = L_o(p', -wi), the outgoing radiance of the surface p' that the ray from p
// meets first. In operator form L = E + K L, whose solution is the series
//   L = E + K E + K^2 E + K^3 E + ...
// (emission, direct light, light after one indirect bounce, ...). A path tracer estimates the
// whole series with one random path per sample: at each vertex it adds the emission it sees,
// weighted by the path's throughput beta (the product of f cos / p so far), samples a new
// direction from the BSDF, and continues.
//
// Next-event estimation (NEE) adds, at each vertex, lesson 3's light sample; emitters then found
// by BSDF-sampled rays are weighted by multiple importance sampling, so no light is counted
// twice. Russian roulette ends paths at random once their throughput is small, dividing the
// survivors by their survival probability, which keeps the estimate unbiased.
//
// What a path from the camera cannot find: a point light seen through a mirror or glass (a
// delta BSDF meets a delta light: no sampled direction ever hits the point), so point-light
// caustics are missing; and caustics from small lamps come only from BSDF paths that happen to
// hit the lamp, so they are noisy. Lesson 5 traces paths from the lights too.
#pragma once

#include <span>

#include "lights/lights.h"
#include "materials/bsdf.h"
#include "render/model.h"
#include "scene/scene.h"

namespace lessons {

// Paths longer than this are cut even without a depth limit: a path trapped by total internal
// reflection keeps throughput 1, so Russian roulette alone would never end it.
inline constexpr int kLongestPath = 1000;
// The most segments a path may have under --max-depth N (0: no limit but the safety cut).
inline constexpr int longest_path(int max_depth) {
    return max_depth > 0 ? max_depth : kLongestPath;
}

struct PathOptions {
    bool next_event = true;  // false: the plain estimator, BSDF sampling only
    int max_depth = 0;       // 0: unlimited; else at most this many path segments (depth 1:
                             // emitters seen directly; depth 2 adds direct light; ...)
    int roulette_after = 3;  // bounces before Russian roulette may end a path; < 0: never
    int bounce_layers = 0;   // record bounces 0 .. N-1 as separate layers, plus the rest
};

// Russian roulette: the probability of continuing a path of throughput beta, q = min(1, max
// beta). Survivors carry beta / q, so the expected contribution is unchanged (q beta / q = beta).
// (Lesson 5 ends its subpaths the same way.)
float russian_roulette_survival(const Color& beta);

// What the notes say of how long paths may grow and when Russian roulette may end them
// (lesson 4's --max-depth and --roulette-after: path_length_flags.h), which lesson 5 shares for
// its subpaths.
void add_path_length_notes(Model& model, int max_depth, int roulette_after);

// The radiance along a camera ray: one path sample. If `bounces` is not empty, the
// contribution of light that has bounced k times is also added to bounces[k] (the last entry
// collects everything beyond).
Color path_trace(const Scene& scene, const LightSampler& lights, const Ray& ray, Rng& rng,
                 const PathOptions& options, std::span<Color> bounces = {});

// Lesson 4 as a model the render loop runs: path_trace for every pixel sample (into bounce
// layers with options.bounce_layers), with its own light sampler. `scene` must outlive it.
class PathTracingModel final : public Model {
public:
    PathTracingModel(const Scene& scene, const PathOptions& options);
    Color sample(const Ray& ray, Rng& rng, uint32_t pixel, std::span<Color> layers,
                 std::vector<Splat>& splats) const override;

private:
    const Scene& scene_;
    LightSampler lights_;
    PathOptions options_;
};

}  // namespace lessons
