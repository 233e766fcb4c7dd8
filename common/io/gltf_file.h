// glTF 2.0 scenes (.gltf with external or embedded buffers, and .glb), through Debian's
// tinygltf: triangles with their node transforms, materials mapped onto the suite's
// (docs/interop.md), KHR_lights_punctual point, spot and directional lights, and the first
// perspective camera.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "geometry/bounds.h"
#include "geometry/math.h"
#include "io/input_file.h"
#include "materials/material.h"
#include "scene/scene.h"

namespace lessons {

struct GltfPrimitive {
    std::vector<Vec3> positions;  // in the mesh's own space
    std::vector<Vec3> normals;    // empty, or one unit normal per position
    std::vector<Vec2> uvs;        // empty, or one per position (TEXCOORD_0, v flipped: v = 1 - t)
    std::vector<std::array<uint32_t, 3>> triangles;
    int material = -1;        // index into GltfScene::materials
    glm::dmat4 to_world{1.0};  // the node's transform, parents' included
    std::string where;         // "meshes[m].primitives[p]"
};

struct GltfCamera {
    Vec3 position, look_at, up;
    float fov_y_degrees = 45.0f;
    float aspect = 0.0f;  // 0: not given
    std::string name;
};

struct GltfScene {
    std::vector<GltfPrimitive> primitives;
    std::vector<Material> materials;  // the file's, mapped; the last is the default material
    // In the glTF scene's space; a spot's axis and a directional light's direction are the
    // node's -z in float, not yet normalised (placing the file normalises them).
    std::vector<PointLight> lights;  // point and spot lights
    std::vector<DirectionalLight> directional_lights;
    std::optional<GltfCamera> camera;
    std::vector<std::string> notes;   // what was approximated or ignored
    std::vector<std::string> files;   // the external buffers and images it names
    Bounds3 bounds;                   // of every placed vertex
};

// Reads the file and every file it names (each a regular file of at most max_bytes). Throws
// InputError naming the file and the glTF field ("accessors[3]", "meshes[0].primitives[1]") for
// anything wrong: truncated buffers, accessors out of range, non-finite values, unsupported
// primitive modes, spot cones outside (0, 90] degrees.
GltfScene load_gltf(const std::string& path, uint64_t max_bytes);

// Whether a scene file is glTF (by its extension: .gltf or .glb). (io/gltf_scene.cpp)
bool is_gltf_file(const std::string& path);

// Stage 1 of loading a glTF file as the whole scene (scene_file.h): the file as one glTF shape,
// its camera, or a default one framing its bounds, and the files it read. (io/gltf_scene.cpp)
struct SceneDescription;
SceneDescription gltf_scene_description(const std::string& path, const InputLimits& limits);

}  // namespace lessons
