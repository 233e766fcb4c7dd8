// Lesson 3: the reflection equation by Monte Carlo. The model is in reflection_equation.cpp.
#include <CLI/CLI.hpp>
#include <memory>

#include "reflection_equation.h"

int main(int argc, char** argv) {
    using namespace lessons;
    std::string estimator = "mis", heuristic = "power";
    std::unique_ptr<LightSampler> lights;
    Lesson lesson;
    lesson.name = "03_reflection_equation";
    lesson.description =
        "Lesson 3, the reflection equation: direct light from emitters, by Monte Carlo with a "
        "choice of estimators";
    lesson.default_spp = 16;
    lesson.add_options = [&](CLI::App& app) {
        app.add_option("--estimator", estimator,
                       "How directions are sampled: uniform (hemisphere), cosine, brdf, light, or "
                       "mis (light and BRDF samples combined)")
            ->check(CLI::IsMember({"uniform", "cosine", "brdf", "light", "mis"}))
            ->capture_default_str();
        app.add_option("--mis-heuristic", heuristic, "MIS weights: power or balance")
            ->check(CLI::IsMember({"power", "balance"}))
            ->capture_default_str();
    };
    lesson.make_model = [&](const Scene& scene) {
        ReflectionOptions options;
        options.estimator = parse_estimator(estimator);
        options.heuristic = heuristic == "balance" ? MisHeuristic::Balance : MisHeuristic::Power;
        lights = std::make_unique<LightSampler>(scene);
        return make_reflection_model(scene, *lights, options);
    };
    return run_lesson(argc, argv, lesson);
}
