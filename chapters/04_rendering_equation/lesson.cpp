// Lesson 4: the rendering equation, as a lesson: its flags (plain or NEE, path length, bounce
// layers), and the model.
#include <CLI/CLI.hpp>
#include <memory>

#include "rendering_equation.h"

namespace lessons {

Lesson rendering_equation_lesson() {
    struct Flags {
        PathOptions options;
        bool plain = false;
    };
    auto flags = std::make_shared<Flags>();
    Lesson lesson;
    lesson.name = "04_rendering_equation";
    lesson.description =
        "Lesson 4, the rendering equation: global illumination by Monte Carlo path tracing";
    lesson.default_spp = 64;
    lesson.add_options = [=](CLI::App& app) {
        app.add_flag("--plain", flags->plain,
                     "Plain estimator: BSDF sampling only, no next-event estimation or MIS");
        add_path_length_options(app, flags->options.max_depth, flags->options.roulette_after);
        app.add_option("--bounces", flags->options.bounce_layers,
                       "Also write the light of each bounce count 0 .. N-1 (E, KE, K^2E, ...) "
                       "and of N or more as images PREFIX_bounceK, and print each one's share")
            ->check(CLI::Range(0, 64))
            ->capture_default_str();
    };
    lesson.make_model = [=](const Scene& scene) {
        PathOptions options = flags->options;
        options.next_event = !flags->plain;
        auto lights = std::make_shared<LightSampler>(scene);
        Model model = make_path_tracing_model(scene, *lights, options);
        model.owned = lights;
        return model;
    };
    return lesson;
}

}  // namespace lessons
