// Lesson 5: bidirectional path tracing. The model is in bidirectional.cpp and its sections.
#include <CLI/CLI.hpp>
#include <memory>

#include "bidirectional.h"
#include "io/input_error.h"
#include "rendering_equation.h"

int main(int argc, char** argv) {
    using namespace lessons;
    BidirOptions options;
    std::unique_ptr<LightSampler> lights;
    Lesson lesson;
    lesson.name = "05_bidirectional";
    lesson.description =
        "Lesson 5, both ends of the path: bidirectional path tracing, camera and light subpaths "
        "joined by every strategy and weighted by MIS";
    lesson.default_spp = 16;
    lesson.add_options = [&](CLI::App& app) {
        add_path_length_options(app, options.max_depth, options.roulette_after);
        app.add_option("--strategies", options.strategy_layers,
                       "Also write one image per strategy (s, t) of paths of 1 .. N segments, "
                       "PREFIX_sS_tT, with its MIS weight applied, and the longer paths as "
                       "PREFIX_segments{N+1}plus")
            ->check(CLI::Range(0, 12))
            ->capture_default_str();
        app.add_flag("--unweighted", options.unweighted_layers,
                     "With --strategies: the strategy images without their weights, each an "
                     "estimate of all the light its paths carry");
        app.add_flag("--light-tracing", options.light_tracing,
                     "Light tracing alone: the t = 1 strategies (light subpaths joined to the "
                     "camera), unweighted");
    };
    lesson.make_model = [&](const Scene& scene) {
        if (options.unweighted_layers && options.strategy_layers == 0)
            throw InputError("command line", 0, "--unweighted", "needs --strategies N");
        lights = std::make_unique<LightSampler>(scene);
        return make_bidirectional_model(scene, *lights, options);
    };
    return run_lesson(argc, argv, lesson);
}
