// Lesson 5: bidirectional path tracing, the rendering equation solved from both ends (Veach
// 1997, ch. 10). It adds to lesson 4 the paths that start at the lights.
//
// Lesson 4's camera paths find light in two ways: by hitting an emitter, or by a light sample
// at a vertex. Neither finds light that leaves a point light, meets a mirror or glass and then a
// diffuse surface: the glass scatters into one direction only, which never points at the
// light's single point (a delta BSDF meets a delta light), so point-light caustics are missing;
// and a small lamp behind glass is found only when a BSDF-sampled direction happens to hit it.
// A light subpath y_0 y_1 ... follows the light itself; joining any prefix of it to any prefix
// of a camera subpath z_0 z_1 ... gives a family of strategies (s, t) for the same paths:
//   subpaths.h  the two random walks and the densities each vertex keeps;
//   connect.h   the four kinds of join (s = 0, s = 1, t = 1: light tracing, splatted onto the
//               film, and the general shadow ray);
//   mis.h       the weights that make the strategies one estimator (ratio_walk.h: the
//               densities and the walk over their ratios they are computed by).
// Every strategy alone is an unbiased estimator of the paths it can make; weighted by MIS they
// add up to one that keeps each strategy's strengths.
#pragma once

#include <algorithm>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "04_rendering_equation/rendering_equation.h"
#include "05_bidirectional/connect.h"
#include "lights/lights.h"
#include "render/model.h"
#include "scene/scene.h"

namespace lessons {

struct BidirOptions {
    int max_depth = 0;        // 0: unlimited; else at most this many path segments
    int roulette_after = 3;   // bounces before Russian roulette may end a subpath; < 0: never
    int strategy_layers = 0;  // N > 0: a layer per strategy (s, t) of paths of 1 .. N segments
    bool unweighted_layers = false;  // those layers without their MIS weights
    bool light_tracing = false;      // the t = 1 strategies alone, unweighted
};

// The layer of strategy (s, t) when layers are kept for paths of up to N segments: paths of k
// segments have the k + 1 strategies s = 0 .. k, in order of k; any longer path goes to the
// last layer, number N (N + 3) / 2.
int strategy_layer(int s, int t, int max_layer_segments);

// The two subpaths of one pixel sample: the camera subpath of `ray` and a light subpath, as long
// as the options allow (light tracing alone needs no camera path beyond the camera).
void trace_subpaths(const Bidir& b, const Ray& ray, RandomNumbers& rng, const BidirOptions& options,
                    std::vector<Vertex>& camera, std::vector<Vertex>& light);

// Every strategy (s, t) that joins the two subpaths into a path of at most the options' length:
// calls add(s, t, sample, contribution) for each that carries light, with its contribution
// weighted by MIS (unless light tracing alone, which is unweighted). `extra` (if not null) is
// another technique counted among those of the weights (mis.h); this lesson has none.
template <class Add>
void for_each_strategy(const Bidir& b, std::span<const Vertex> camera,
                       std::span<const Vertex> light, RandomNumbers& rng,
                       const BidirOptions& options, const ExtraTechnique* extra, Add&& add);

// One sample of the pixel of camera ray `ray`: the returned radiance (strategies with t >= 2),
// each layer's share, and the light of t = 1 strategies appended to `splats` for the pixels it
// lands on.
Color bidirectional(const Bidir& b, const Ray& ray, RandomNumbers& rng, const BidirOptions& options,
                    std::span<Color> layers, std::vector<Splat>& splats);

// What no strategy of this lesson can find in a scene of these contents, as the report's bias
// (lesson 7, whose states are these strategies, misses it too); nothing if it finds everything.
std::optional<std::string> strategies_miss(const SceneContents& contents);

// Lesson 5 as a model the render loop runs: bidirectional for every pixel sample (splatting
// its light tracing), with its own light sampler. `scene` must outlive it.
class BidirectionalModel final : public Model {
public:
    BidirectionalModel(const Scene& scene, const BidirOptions& options);
    Color sample(const Ray& ray, Rng& rng, uint32_t pixel, std::span<Color> layers,
                 std::vector<Splat>& splats) const override;

private:
    LightSampler lights_;
    Bidir b_;  // refers to lights_
    BidirOptions options_;
};

template <class Add>
void for_each_strategy(const Bidir& b, std::span<const Vertex> camera,
                       std::span<const Vertex> light, RandomNumbers& rng,
                       const BidirOptions& options, const ExtraTechnique* extra, Add&& add) {
    const int longest = longest_path(options.max_depth);
    const int light_vertices = static_cast<int>(light.size());
    const bool weighted = !options.light_tracing;
    for (int t = 1; t <= static_cast<int>(camera.size()); ++t) {
        for (int s = options.light_tracing ? 1 : 0; s <= std::max(light_vertices, 1); ++s) {
            const int segments = s + t - 1;
            if (segments < 1 || segments > longest) continue;
            // A light sample (s = 1, t >= 2) is drawn afresh; every other s needs its vertices.
            if (s > light_vertices && !(s == 1 && t >= 2)) continue;
            const StrategySample c = connect(b, light, s, camera, t, rng, weighted, extra);
            if (is_black(c.L)) continue;
            add(s, t, c, weighted ? c.weight * c.L : c.L);
        }
    }
}

}  // namespace lessons
