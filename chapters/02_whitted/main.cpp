// Lesson 2: Whitted-style ray tracing. The model is in whitted.cpp; this reads its flags.
#include <CLI/CLI.hpp>

#include "whitted.h"

int main(int argc, char** argv) {
    using namespace lessons;
    std::vector<float> ambient;
    WhittedOptions options;
    std::string fresnel = "exact";
    Lesson lesson;
    lesson.name = "02_whitted";
    lesson.description =
        "Lesson 2, Whitted ray tracing: local shading at diffuse hits, recursive reflection and "
        "refraction at mirrors and glass";
    lesson.default_spp = 4;
    lesson.add_options = [&](CLI::App& app) {
        add_ambient_option(app, ambient);
        app.add_option("--max-bounces", options.max_bounces,
                       "Maximum number of specular bounces after the camera ray (0: none; lessons "
                       "4 and 5 count path segments with --max-depth instead)")
            ->check(CLI::Range(0, 1000))
            ->capture_default_str();
        app.add_option("--min-attenuation", options.min_attenuation,
                       "Stop a branch when its path weight falls below this in every channel")
            ->check(CLI::Range(0.0, 1.0))
            ->capture_default_str();
        app.add_option("--fresnel", fresnel, "Fresnel reflectance of glass: exact or schlick")
            ->check(CLI::IsMember({"exact", "schlick"}))
            ->capture_default_str();
    };
    lesson.make_model = [&](const Scene& scene) {
        options.ambient = ambient_radiance(ambient, scene);
        options.schlick = fresnel == "schlick";
        return make_whitted_model(scene, options);
    };
    return run_lesson(argc, argv, lesson);
}
