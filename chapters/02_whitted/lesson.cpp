// Lesson 2: Whitted-style ray tracing, as a lesson: its flags, and the model it makes.
#include <CLI/CLI.hpp>
#include <memory>

#include "whitted.h"

namespace lessons {

Lesson whitted_lesson() {
    struct Flags {
        std::vector<float> ambient;
        WhittedOptions options;
        std::string fresnel = "exact";
    };
    auto flags = std::make_shared<Flags>();
    Lesson lesson;
    lesson.name = "02_whitted";
    lesson.description =
        "Lesson 2, Whitted ray tracing: local shading at diffuse hits, recursive reflection and "
        "refraction at mirrors and glass";
    lesson.default_spp = 4;
    lesson.add_options = [=](CLI::App& app) {
        add_ambient_option(app, flags->ambient);
        app.add_option("--max-bounces", flags->options.max_bounces,
                       "Maximum number of specular bounces after the camera ray (0: none; lessons "
                       "4 and 5 count path segments with --max-depth instead)")
            ->check(CLI::Range(0, 1000))
            ->capture_default_str();
        app.add_option("--min-attenuation", flags->options.min_attenuation,
                       "Stop a branch when its path weight falls below this in every channel")
            ->check(CLI::Range(0.0, 1.0))
            ->capture_default_str();
        app.add_option("--fresnel", flags->fresnel,
                       "Fresnel reflectance of glass: exact or schlick")
            ->check(CLI::IsMember({"exact", "schlick"}))
            ->capture_default_str();
    };
    lesson.make_model = [=](const Scene& scene) {
        WhittedOptions options = flags->options;
        options.ambient = ambient_radiance(flags->ambient, scene);
        options.schlick = flags->fresnel == "schlick";
        return make_whitted_model(scene, options);
    };
    return lesson;
}

}  // namespace lessons
