// Lesson 5: bidirectional path tracing, as a lesson: its flags (path length, strategy images,
// light tracing alone), and the model.
#include <CLI/CLI.hpp>
#include <memory>

#include "bidirectional.h"
#include "io/input_error.h"
#include "rendering_equation.h"

namespace lessons {

Lesson bidirectional_lesson() {
    auto flags = std::make_shared<BidirOptions>();
    Lesson lesson;
    lesson.name = "05_bidirectional";
    lesson.description =
        "Lesson 5, both ends of the path: bidirectional path tracing, camera and light subpaths "
        "joined by every strategy and weighted by MIS";
    lesson.default_spp = 16;
    lesson.add_options = [=](CLI::App& app) {
        add_path_length_options(app, flags->max_depth, flags->roulette_after);
        app.add_option("--strategies", flags->strategy_layers,
                       "Also write one image per strategy (s, t) of paths of 1 .. N segments, "
                       "PREFIX_sS_tT, with its MIS weight applied, and the longer paths as "
                       "PREFIX_segments{N+1}plus")
            ->check(CLI::Range(0, 12))
            ->capture_default_str();
        app.add_flag("--unweighted", flags->unweighted_layers,
                     "With --strategies: the strategy images without their weights, each an "
                     "estimate of all the light its paths carry");
        app.add_flag("--light-tracing", flags->light_tracing,
                     "Light tracing alone: the t = 1 strategies (light subpaths joined to the "
                     "camera), unweighted");
    };
    lesson.make_model = [=](const Scene& scene) {
        if (flags->unweighted_layers && flags->strategy_layers == 0)
            throw InputError("command line", 0, "--unweighted", "needs --strategies N");
        auto lights = std::make_shared<LightSampler>(scene);
        Model model = make_bidirectional_model(scene, *lights, *flags);
        model.owned = lights;
        return model;
    };
    return lesson;
}

}  // namespace lessons
