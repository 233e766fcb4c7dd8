// Lesson 1: ray casting, as a lesson: its one flag, and the model it makes for a scene.
#include <CLI/CLI.hpp>
#include <memory>

#include "ray_casting.h"

namespace lessons {

Lesson ray_casting_lesson() {
    auto ambient = std::make_shared<std::vector<float>>();
    Lesson lesson;
    lesson.name = "01_ray_casting";
    lesson.description =
        "Lesson 1, ray casting: nearest hit, one shadow ray per light, Blinn-Phong local shading";
    lesson.default_spp = 4;
    lesson.add_options = [=](CLI::App& app) { add_ambient_option(app, *ambient); };
    lesson.make_model = [=](const Scene& scene) {
        RayCastingOptions options;
        options.ambient = ambient_radiance(*ambient, scene);
        return make_ray_casting_model(scene, options);
    };
    return lesson;
}

}  // namespace lessons
