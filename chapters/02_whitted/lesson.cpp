// Lesson 2: Whitted-style ray tracing, as a lesson: its flags, and the model it makes.
#include "driver/lesson.h"

#include <CLI/CLI.hpp>

#include "01_ray_casting/ambient_flag.h"
#include "02_whitted/whitted.h"
#include "driver/choice_flag.h"

namespace lessons {

namespace {

struct WhittedFlags {
    AmbientFlag ambient;
    WhittedOptions options;

    void bind(CLI::App& app) {
        ambient.bind(app);
        app.add_option("--max-bounces", options.max_bounces,
                       "Maximum number of specular bounces after the camera ray (0: none; lessons "
                       "4 and 5 count path segments with --max-depth instead)")
            ->check(CLI::Range(0, 1000))
            ->capture_default_str();
        app.add_option("--min-attenuation", options.min_attenuation,
                       "Stop a branch when its path weight falls below this in every channel")
            ->check(CLI::Range(0.0, 1.0))
            ->capture_default_str();
        add_choice_flag<bool>(app, "--fresnel", options.schlick,
                              {{"exact", false}, {"schlick", true}},
                              "Fresnel reflectance of glass: exact or schlick");
    }
    std::unique_ptr<Model> make_model(const Scene& scene) const {
        WhittedOptions o = options;
        o.ambient = ambient.radiance(scene);
        return std::make_unique<WhittedModel>(scene, o);
    }
};

}  // namespace

Lesson whitted_lesson() {
    return lesson_with_flags<WhittedFlags>(
        "02_whitted",
        "Lesson 2, Whitted ray tracing: local shading at diffuse hits, recursive reflection and "
        "refraction at mirrors and glass",
        4);
}

}  // namespace lessons
