// Lesson 5: bidirectional path tracing, as a lesson: its flags (path length, strategy images,
// light tracing alone), and the model.
#include "driver/lesson.h"

#include <CLI/CLI.hpp>

#include "04_rendering_equation/path_length_flags.h"
#include "05_bidirectional/bidirectional.h"
#include "io/input_error.h"

namespace lessons {

namespace {

struct BidirectionalFlags {
    BidirOptions options;

    void bind(CLI::App& app) {
        add_path_length_flags(app, options.max_depth, options.roulette_after);
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
    }
    std::unique_ptr<Model> make_model(const Scene& scene) const {
        if (options.unweighted_layers && options.strategy_layers == 0)
            throw InputError("command line", 0, "--unweighted", "needs --strategies N");
        return std::make_unique<BidirectionalModel>(scene, options);
    }
};

}  // namespace

Lesson bidirectional_lesson() {
    return lesson_with_flags<BidirectionalFlags>(
        "05_bidirectional",
        "Lesson 5, both ends of the path: bidirectional path tracing, camera and light subpaths "
        "joined by every strategy and weighted by MIS",
        16);
}

}  // namespace lessons
