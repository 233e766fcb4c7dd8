// Lesson 1: ray casting. The model is in ray_casting.cpp; this reads the lesson's one flag.
#include <CLI/CLI.hpp>

#include "input_error.h"
#include "ray_casting.h"

int main(int argc, char** argv) {
    using namespace lessons;
    std::vector<float> ambient;
    Lesson lesson;
    lesson.name = "01_ray_casting";
    lesson.description =
        "Lesson 1, ray casting: nearest hit, one shadow ray per light, Blinn-Phong local shading";
    lesson.default_spp = 4;
    lesson.add_options = [&](CLI::App& app) {
        app.add_option("--ambient", ambient,
                       "Ambient radiance L_a standing in for indirect light: one grey value or "
                       "R G B (default: the scene's background radiance)")
            ->expected(1, 3)
            ->check(CLI::NonNegativeNumber);
    };
    lesson.make_model = [&](const Scene& scene) {
        RayCastingOptions options;
        options.ambient = scene.background;
        if (ambient.size() == 1) options.ambient = Color(ambient[0]);
        if (ambient.size() == 3) options.ambient = Color(ambient[0], ambient[1], ambient[2]);
        if (ambient.size() == 2)
            throw InputError("command line", 0, "--ambient", "give one value or three (R G B)");
        return make_ray_casting_model(scene, options);
    };
    return run_lesson(argc, argv, lesson);
}
