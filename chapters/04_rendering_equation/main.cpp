// Lesson 4: the rendering equation by path tracing. The model is in rendering_equation.cpp.
#include <CLI/CLI.hpp>
#include <memory>

#include "rendering_equation.h"

int main(int argc, char** argv) {
    using namespace lessons;
    PathOptions options;
    bool plain = false;
    std::unique_ptr<LightSampler> lights;
    Lesson lesson;
    lesson.name = "04_rendering_equation";
    lesson.description =
        "Lesson 4, the rendering equation: global illumination by Monte Carlo path tracing";
    lesson.default_spp = 64;
    lesson.add_options = [&](CLI::App& app) {
        app.add_flag("--plain", plain,
                     "Plain estimator: BSDF sampling only, no next-event estimation or MIS");
        add_path_length_options(app, options.max_depth, options.roulette_after);
        app.add_option("--bounces", options.bounce_layers,
                       "Also write the light of each bounce count 0 .. N-1 (E, KE, K^2E, ...) "
                       "and of N or more as images PREFIX_bounceK, and print each one's share")
            ->check(CLI::Range(0, 64))
            ->capture_default_str();
    };
    lesson.make_model = [&](const Scene& scene) {
        options.next_event = !plain;
        lights = std::make_unique<LightSampler>(scene);
        return make_path_tracing_model(scene, *lights, options);
    };
    return run_lesson(argc, argv, lesson);
}
