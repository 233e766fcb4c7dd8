// Lesson 5: bidirectional path tracing (see bidirectional.h).
#include "05_bidirectional/bidirectional.h"

namespace lessons {

int strategy_layer(int s, int t, int max_layer_segments) {
    const int k = s + t - 1;  // segments
    const int N = max_layer_segments;
    return k <= N ? (k - 1) * (k + 2) / 2 + s : N * (N + 3) / 2;
}

void trace_subpaths(const Bidir& b, const Ray& ray, RandomNumbers& rng, const BidirOptions& options,
                    std::vector<Vertex>& camera, std::vector<Vertex>& light) {
    const int longest = longest_path(options.max_depth);
    // Light tracing needs no camera path: the camera is joined to every light vertex.
    camera_subpath(b, ray, rng, options.light_tracing ? 1 : longest + 1, options.roulette_after,
                   camera);
    light_subpath(b, rng, longest, options.roulette_after, light);
}

Color bidirectional(const Bidir& b, const Ray& ray, RandomNumbers& rng, const BidirOptions& options,
                    std::span<Color> layers, std::vector<Splat>& splats) {
    thread_local std::vector<Vertex> camera, light;
    trace_subpaths(b, ray, rng, options, camera, light);
    Color L(0.0f);
    for_each_strategy(
        b, camera, light, rng, options, nullptr,
        [&](int s, int t, const StrategySample& c, const Color& contribution) {
            const Color layer_share = options.unweighted_layers ? c.L : contribution;
            const int layer =
                options.strategy_layers > 0 ? strategy_layer(s, t, options.strategy_layers) : -1;
            if (t == 1) {  // light tracing: onto the pixel the light vertex is seen in
                splats.push_back({*c.pixel, 0, contribution});
                if (layer >= 0)
                    splats.push_back({*c.pixel, static_cast<uint32_t>(1 + layer), layer_share});
            } else {
                L += contribution;
                if (layer >= 0) layers[layer] += layer_share;
            }
        });
    return L;
}

std::optional<std::string> strategies_miss(const SceneContents& contents) {
    if ((contents.point_lights || contents.directional_lights) && contents.delta_materials)
        return "a point or directional light seen in a mirror or through glass is missing, and so "
               "is its caustic seen that way: a delta BSDF next to each end of the path leaves no "
               "strategy to join them (the caustic seen directly is found)";
    return std::nullopt;
}

BidirectionalModel::BidirectionalModel(const Scene& scene, const BidirOptions& options)
    : lights_(scene),
      b_{scene, lights_, scene.camera, scene.width, scene.height},
      options_(options) {
    passes = true;  // a pass's splats land in a fixed order (render/render.h)
    splats = true;
    if (options.strategy_layers > 0) {
        const int N = options.strategy_layers;
        for (int k = 1; k <= N; ++k)
            for (int s = 0; s <= k; ++s)
                layer_names.push_back("s" + std::to_string(s) + "_t" + std::to_string(k + 1 - s));
        layer_names.push_back("segments" + std::to_string(N + 1) + "plus");
    }
    const SceneContents contents = scene.contents();
    if (options.light_tracing) {
        notes.push_back(
            "estimator: light tracing alone (the t = 1 strategies, unweighted): light subpaths "
            "joined to the camera and splatted onto the film");
        if (contents.delta_materials)
            biased_because.push_back(
                "light tracing cannot show mirrors and glass: a light vertex on them cannot be "
                "joined to the camera (use the full estimator)");
        if (contents.environment)
            biased_because.push_back(
                "light tracing cannot show the sky's light: no light subpath starts from it");
    } else {
        notes.push_back(
            "estimator: bidirectional path tracing, every strategy (s, t) weighted by MIS (power "
            "heuristic)");
    }
    if (options.strategy_layers > 0)
        notes.push_back(std::string("strategy layers s{S}_t{T}") +
                        (options.unweighted_layers
                             ? ", unweighted: each alone estimates every path it can make "
                               "(they do not add up to the image)"
                             : ", weighted: they add up to the image"));
    if (contents.environment && !options.light_tracing)
        notes.push_back(
            "the sky starts no light subpaths: its light is found by camera paths that escape "
            "(s = 0) and by light samples (s = 1), as in lesson 4");
    if (std::optional<std::string> missing = strategies_miss(contents))
        biased_because.push_back(*missing);
    add_path_length_notes(*this, options.max_depth, options.roulette_after);  // both subpaths
    if (lights_.empty()) notes.push_back("the scene has no lights: only emission is visible");
}

Color BidirectionalModel::sample(const Ray& ray, Rng& rng, uint32_t, std::span<Color> layers,
                                 std::vector<Splat>& splats) const {
    return bidirectional(b_, ray, rng, options_, layers, splats);
}

}  // namespace lessons
