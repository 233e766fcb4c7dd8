// A glTF file as a whole scene: its first perspective camera (or one framing its bounds), the
// image size by the camera's aspect, no background; and how a scene file's kind is told.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include "io/gltf_file.h"
#include "io/scene_file.h"

namespace lessons {

bool is_gltf_file(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    return ext == ".gltf" || ext == ".glb" || ext == ".GLTF" || ext == ".GLB";
}

SceneDescription gltf_scene_description(const std::string& path, const InputLimits& limits) {
    SceneDescription d;
    d.file = path;
    ShapeDescription s;
    s.type = ShapeDescription::Type::Gltf;
    s.file = path;
    s.where = s.file_where = {path, 0, ""};
    auto loaded = std::make_shared<const GltfScene>(load_gltf(path, limits.file_bytes()));
    const GltfScene& g = *loaded;
    s.gltf = loaded;
    d.shapes.push_back(s);
    d.width = 640;
    d.height = 480;
    if (g.camera) {
        d.camera_position = g.camera->position;
        d.camera_look_at = g.camera->look_at;
        d.camera_up = g.camera->up;
        d.camera_fov = g.camera->fov_y_degrees;
        if (g.camera->aspect > 0.0f)
            d.height = std::clamp(static_cast<int>(std::lround(640.0f / g.camera->aspect)), 1,
                                  kMaxImageSide);
        d.notes.push_back("glTF: the camera is the file's '" + g.camera->name + "' (yfov " +
                          std::to_string(g.camera->fov_y_degrees) + " degrees); the image " +
                          std::to_string(d.width) + "x" + std::to_string(d.height) +
                          " by its aspect, unless --width/--height say otherwise");
    } else {
        // Framing the bounds: looking at their centre along -z, from where a 40-degree view
        // holds their bounding sphere.
        const Vec3 c = 0.5f * (g.bounds.min + g.bounds.max);
        const float radius = std::max(0.5f * glm::length(g.bounds.max - g.bounds.min), 1e-3f);
        d.camera_fov = 40.0f;
        d.camera_position = c + Vec3(0.0f, 0.0f, radius / std::sin(0.5f * 40.0f * kPi / 180.0f));
        d.camera_look_at = c;
        d.camera_up = Vec3(0.0f, 1.0f, 0.0f);
        d.notes.push_back("glTF: the file has no perspective camera: a default one looks along -z "
                          "at the centre of the scene's bounds, framing them in 40 degrees; "
                          "the image 640x480 unless --width/--height say otherwise");
    }
    d.notes.push_back("glTF: no background (black): place the file in a TOML scene for a sky");
    d.files_read = {path};
    d.files_read.insert(d.files_read.end(), g.files.begin(), g.files.end());
    return d;
}

}  // namespace lessons
