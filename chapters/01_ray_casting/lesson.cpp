// Lesson 1: ray casting, as a lesson: its one flag, and the model it makes for a scene.
#include "driver/lesson.h"

#include <CLI/CLI.hpp>

#include "01_ray_casting/ambient_flag.h"
#include "01_ray_casting/ray_casting.h"
#include "io/input_error.h"

namespace lessons {

void AmbientFlag::bind(CLI::App& app) {
    app.add_option("--ambient", values,
                   "Ambient radiance L_a standing in for indirect light at diffuse hits: one grey "
                   "value or R G B (default: the scene's background radiance)")
        ->expected(1, 3)
        ->check(CLI::NonNegativeNumber);
}

Color AmbientFlag::radiance(const Scene& scene) const {
    if (values.size() == 1) return Color(values[0]);
    if (values.size() == 3) return Color(values[0], values[1], values[2]);
    if (values.size() == 2)
        throw InputError("command line", 0, "--ambient", "give one value or three (R G B)");
    return scene.environment_map ? scene.environment_map->mean() : scene.background;
}

namespace {

struct RayCastingFlags {
    AmbientFlag ambient;

    void bind(CLI::App& app) { ambient.bind(app); }
    std::unique_ptr<Model> make_model(const Scene& scene) const {
        return std::make_unique<RayCastingModel>(scene, RayCastingOptions{ambient.radiance(scene)});
    }
};

}  // namespace

Lesson ray_casting_lesson() {
    return lesson_with_flags<RayCastingFlags>(
        "01_ray_casting",
        "Lesson 1, ray casting: nearest hit, one shadow ray per light, Blinn-Phong local shading",
        4);
}

}  // namespace lessons
