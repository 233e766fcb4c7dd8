// Lesson 4: the rendering equation, as a lesson: its flags (plain or NEE, path length, bounce
// layers), and the model.
#include "driver/lesson.h"

#include <CLI/CLI.hpp>

#include "04_rendering_equation/path_length_flags.h"
#include "04_rendering_equation/rendering_equation.h"

namespace lessons {

void add_path_length_flags(CLI::App& app, int& max_depth, int& roulette_after) {
    app.add_option("--max-depth", max_depth,
                   "Longest path in segments (1: emitters seen directly, 2: plus direct light, "
                   "...); 0: unlimited")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    app.add_option("--roulette-after", roulette_after,
                   "Bounces before Russian roulette may end a path; -1: never")
        ->check(CLI::Range(-1, 100000))
        ->capture_default_str();
}

namespace {

struct PathTracingFlags {
    PathOptions options;
    bool plain = false;

    void bind(CLI::App& app) {
        app.add_flag("--plain", plain,
                     "Plain estimator: BSDF sampling only, no next-event estimation or MIS");
        add_path_length_flags(app, options.max_depth, options.roulette_after);
        app.add_option("--bounces", options.bounce_layers,
                       "Also write the light of each bounce count 0 .. N-1 (E, KE, K^2E, ...) "
                       "and of N or more as images PREFIX_bounceK, and print each one's share")
            ->check(CLI::Range(0, 64))
            ->capture_default_str();
    }
    std::unique_ptr<Model> make_model(const Scene& scene) const {
        PathOptions o = options;
        o.next_event = !plain;
        return std::make_unique<PathTracingModel>(scene, o);
    }
};

}  // namespace

Lesson rendering_equation_lesson() {
    return lesson_with_flags<PathTracingFlags>(
        "04_rendering_equation",
        "Lesson 4, the rendering equation: global illumination by Monte Carlo path tracing", 64);
}

}  // namespace lessons
