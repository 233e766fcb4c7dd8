// Lesson 2: Whitted-style ray tracing. The model is in whitted.cpp; this reads its flags.
#include <CLI/CLI.hpp>

#include "input_error.h"
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
        app.add_option("--ambient", ambient,
                       "Ambient radiance L_a at diffuse hits: one grey value or R G B (default: "
                       "the scene's background radiance)")
            ->expected(1, 3)
            ->check(CLI::NonNegativeNumber);
        app.add_option("--max-depth", options.max_depth,
                       "Maximum number of specular bounces after the camera ray")
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
        options.ambient = scene.background;
        if (ambient.size() == 1) options.ambient = Color(ambient[0]);
        if (ambient.size() == 3) options.ambient = Color(ambient[0], ambient[1], ambient[2]);
        if (ambient.size() == 2)
            throw InputError("command line", 0, "--ambient", "give one value or three (R G B)");
        options.schlick = fresnel == "schlick";
        return make_whitted_model(scene, options);
    };
    return run_lesson(argc, argv, lesson);
}
