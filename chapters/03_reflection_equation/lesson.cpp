// Lesson 3: the reflection equation, as a lesson: its flags (the estimator), and the model.
#include <CLI/CLI.hpp>
#include <memory>

#include "reflection_equation.h"

namespace lessons {

Lesson reflection_equation_lesson() {
    struct Flags {
        std::string estimator = "mis", heuristic = "power";
    };
    auto flags = std::make_shared<Flags>();
    Lesson lesson;
    lesson.name = "03_reflection_equation";
    lesson.description =
        "Lesson 3, the reflection equation: direct light from emitters, by Monte Carlo with a "
        "choice of estimators";
    lesson.default_spp = 16;
    lesson.add_options = [=](CLI::App& app) {
        app.add_option("--estimator", flags->estimator,
                       "How directions are sampled: uniform (hemisphere), cosine, brdf, light, or "
                       "mis (light and BRDF samples combined)")
            ->check(CLI::IsMember({"uniform", "cosine", "brdf", "light", "mis"}))
            ->capture_default_str();
        app.add_option("--mis-heuristic", flags->heuristic, "MIS weights: power or balance")
            ->check(CLI::IsMember({"power", "balance"}))
            ->capture_default_str();
    };
    lesson.make_model = [=](const Scene& scene) {
        ReflectionOptions options;
        options.estimator = parse_estimator(flags->estimator);
        options.heuristic =
            flags->heuristic == "balance" ? MisHeuristic::Balance : MisHeuristic::Power;
        auto lights = std::make_shared<LightSampler>(scene);
        Model model = make_reflection_model(scene, *lights, options);
        model.owned = lights;
        return model;
    };
    return lesson;
}

}  // namespace lessons
