// Lesson 1: ray casting. The model is in ray_casting.cpp; this reads the lesson's one flag.
#include <CLI/CLI.hpp>

#include "ray_casting.h"

int main(int argc, char** argv) {
    using namespace lessons;
    std::vector<float> ambient;
    Lesson lesson;
    lesson.name = "01_ray_casting";
    lesson.description =
        "Lesson 1, ray casting: nearest hit, one shadow ray per light, Blinn-Phong local shading";
    lesson.default_spp = 4;
    lesson.add_options = [&](CLI::App& app) { add_ambient_option(app, ambient); };
    lesson.make_model = [&](const Scene& scene) {
        RayCastingOptions options;
        options.ambient = ambient_radiance(ambient, scene);
        return make_ray_casting_model(scene, options);
    };
    return run_lesson(argc, argv, lesson);
}
