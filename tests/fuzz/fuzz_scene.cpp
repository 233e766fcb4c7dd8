// Fuzzing the scene parser and builder: any text must give a scene or an InputError, never a
// crash, a hang or undefined behaviour. Meshes from files are dropped (no file system access);
// whatever is built is then hit by a few camera rays, so the BVH is exercised too.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/input_error.h"
#include "io/scene_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace lessons;
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        SceneDescription d = parse_scene_string(text, "fuzz.toml");
        std::erase_if(d.shapes, [](const ShapeDescription& s) { return !s.file.empty(); });
        if (d.shapes.empty() && d.point_lights.empty() && d.directional_lights.empty()) return 0;
        const Scene scene = build_scene(d, {8, 8});
        for (int y = 0; y < 8; y += 3)
            for (int x = 0; x < 8; x += 3) {
                const Ray ray = scene.camera.generate_ray(x + 0.5f, y + 0.5f, 8, 8);
                if (const auto hit = scene.intersect(ray)) (void)scene.interaction(ray, *hit);
                (void)scene.occluded(ray);
            }
    } catch (const InputError&) {
    }
    return 0;
}
