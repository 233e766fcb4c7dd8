// Lesson 7: Metropolis light transport, as a lesson: its flags (chains, mutations, the steps,
// the bootstrap, path length) and the model.
#include "driver/lesson.h"

#include <CLI/CLI.hpp>

#include "07_metropolis/metropolis.h"

namespace lessons {

namespace {

struct MetropolisFlags {
    MetropolisOptions options;

    void bind(CLI::App& app) {
        app.add_option("--max-depth", options.max_depth,
                       "The longest path, in segments (0: unlimited, up to a safety cut at 1000)")
            ->check(CLI::Range(0, 1000))
            ->capture_default_str();
        app.add_option("--chains", options.chains,
                       "Markov chains per pass, each started from the pass's bootstrap; fixed, "
                       "whatever the number of threads (which run them side by side)")
            ->check(CLI::Range(1, 1 << 16))
            ->capture_default_str();
        app.add_option("--mutations", options.mutations,
                       "Mutations per pixel in each pass (the chains' length); --spp N renders "
                       "N passes, N x this many mutations per pixel")
            ->check(CLI::Range(1, 1 << 16))
            ->capture_default_str();
        app.add_option("--large-step", options.large_step_probability,
                       "The probability that a proposal is a large step (every random number "
                       "redrawn: an independent path) rather than a small one")
            ->check(CLI::Range(0.0, 1.0))
            ->capture_default_str();
        app.add_option("--sigma", options.sigma,
                       "The small step's standard deviation, in primary sample space ([0, 1) "
                       "per number)")
            ->check(CLI::Range(1e-5, 1.0))
            ->capture_default_str();
        app.add_option("--bootstrap", options.bootstrap,
                       "Independent paths per pass that estimate the image's scale b and start "
                       "the chains (0: a quarter of the pass's mutations, at least 256)")
            ->check(CLI::Range(0, 1 << 24))
            ->capture_default_str();
    }
    std::unique_ptr<Model> make_model(const Scene& scene) const {
        return std::make_unique<MetropolisModel>(scene, options);
    }
};

}  // namespace

Lesson metropolis_lesson() {
    return lesson_with_flags<MetropolisFlags>(
        "07_metropolis",
        "Lesson 7, Metropolis light transport: Markov chains over the random numbers of lesson "
        "5's paths, each state one of its strategies, splatted where the light is",
        4);
}

}  // namespace lessons
