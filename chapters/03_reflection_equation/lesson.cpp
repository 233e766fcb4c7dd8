// Lesson 3: the reflection equation, as a lesson: its flags (the estimator), and the model.
#include "driver/lesson.h"

#include <CLI/CLI.hpp>

#include "03_reflection_equation/reflection_equation.h"
#include "driver/choice_flag.h"

namespace lessons {

namespace {

struct ReflectionFlags {
    ReflectionOptions options;

    void bind(CLI::App& app) {
        add_choice_flag(app, "--estimator", options.estimator,
                        Choices<Estimator>(std::begin(kEstimatorNames), std::end(kEstimatorNames)),
                        "How directions are sampled: uniform (hemisphere), cosine, brdf, light, "
                        "or mis (light and BRDF samples combined)");
        add_choice_flag<MisHeuristic>(
            app, "--mis-heuristic", options.heuristic,
            {{"power", MisHeuristic::Power}, {"balance", MisHeuristic::Balance}},
            "MIS weights: power or balance");
    }
    std::unique_ptr<Model> make_model(const Scene& scene) const {
        return std::make_unique<ReflectionModel>(scene, options);
    }
};

}  // namespace

Lesson reflection_equation_lesson() {
    return lesson_with_flags<ReflectionFlags>(
        "03_reflection_equation",
        "Lesson 3, the reflection equation: direct light from emitters, by Monte Carlo with a "
        "choice of estimators",
        16);
}

}  // namespace lessons
