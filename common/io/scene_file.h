// Scene files (TOML), loaded in two stages, as Mitsuba does:
//   1. parse_scene_file: TOML -> SceneDescription, plain data, every value checked for type and
//      range, every unknown field refused (with a "did you mean"), every error located at
//      file:line and named by its field;
//   2. build_scene: SceneDescription -> Scene: materials resolved by name, OBJ meshes loaded,
//      the BVH built.
// The format is documented field by field, with units, in docs/scene-format.md.
#pragma once

#include <array>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "geometry/transform.h"
#include "io/input_file.h"
#include "materials/material.h"
#include "media/medium.h"
#include "scene/scene.h"

namespace lessons {

// Where a value came from, for error messages.
struct SourceLocation {
    std::string file;
    int line = 0;
    std::string field;  // dotted path, e.g. "materials.red.albedo" or "shapes[2].radius"
};

struct MaterialDescription {
    Material material;  // an image albedo has its file named, not yet read
    SourceLocation where;
    SourceLocation albedo_where;
};

struct MediumDescription {
    Medium medium;
    SourceLocation where;
};

struct ShapeDescription {
    enum class Type { Sphere, Quad, Box, Mesh, Gltf } type = Type::Sphere;
    // may be empty for an OBJ mesh whose faces name MTL materials, and a glTF's (which then keep
    // their own)
    std::string material;
    SourceLocation where;
    SourceLocation material_where;
    // The medium inside the shape (a closed one: sphere, box, closed mesh), or empty.
    std::string interior;
    SourceLocation interior_where;
    // sphere
    Vec3 center{0.0f};
    float radius = 1.0f;
    // quad
    Vec3 corner{0.0f}, edge_u{0.0f}, edge_v{0.0f};
    // box: the axis-aligned box [box_min, box_max], placed by `transform` (its rotate_y and
    // translate fields are a case of it). Kept in double, as written in the file, until box_faces.
    glm::dvec3 box_min{0.0}, box_max{1.0};
    // Where the shape goes (docs/scene-format.md, "Transforms"): applied to spheres and quads
    // when the file is read, to boxes and meshes when the scene is built.
    Transform transform;
    SourceLocation transform_where;
    // mesh: either a file, or inline vertices and polygonal faces; gltf: a file
    std::string file;  // resolved relative to the scene file's folder
    SourceLocation file_where;
    std::vector<Vec3> vertices;
    std::vector<std::vector<uint32_t>> faces;
    // gltf: the file, when it was read already (a whole glTF scene reads it for its camera)
    std::shared_ptr<const struct GltfScene> gltf;
};

// The narrowest spot cone read (its half-angle to the edge, degrees; scene files and glTF): below
// about 0.02 degrees a float's cosine is 1 (a spot of no power), and below half a degree 1 - cos
// loses the precision its fade and power need. Blender's narrowest spot is 1 degree across.
inline constexpr double kNarrowestSpotDegrees = 0.5;

struct PointLightDescription {
    PointLight light;
    SourceLocation where;
};

struct DirectionalLightDescription {
    DirectionalLight light;
    SourceLocation where;
};

struct SceneDescription {
    std::string file;
    std::string description;
    int width = 0, height = 0;
    Vec3 camera_position{0.0f}, camera_look_at{0.0f, 0.0f, 1.0f}, camera_up{0.0f, 1.0f, 0.0f};
    float camera_fov = 45.0f;
    SourceLocation camera_where;
    Color background{0.0f};
    // [background] map: a latitude-longitude EXR (resolved path), turned and scaled.
    std::string background_map;
    float background_rotate = 0.0f, background_strength = 1.0f;
    SourceLocation background_where;
    std::vector<MaterialDescription> materials;
    std::vector<MediumDescription> media;
    // The medium filling all space outside the shapes' interiors (the camera's), or empty.
    std::string medium;
    SourceLocation medium_where;
    std::vector<ShapeDescription> shapes;
    std::vector<PointLightDescription> point_lights;  // point and spot lights
    std::vector<DirectionalLightDescription> directional_lights;
    std::vector<std::string> notes;  // what loading approximated (Scene::notes)
    // The files stage 1 read: the scene file; for a glTF file taken as the whole scene, that
    // file and the buffers and images it names. Stage 2 adds what it reads (Scene::input_files).
    std::vector<std::string> files_read;
};

// A box shape as its six faces, each a quad whose front side, cross(edge_u, edge_v), faces out
// of the box: the faces of [box_min, box_max] placed by the box's transform, computed in double;
// each corner and edge is rounded to single precision once.
std::array<Quad, 6> box_faces(const ShapeDescription& box);

// Stage 1. Throws InputError.
SceneDescription parse_scene_file(const std::string& path, const InputLimits& limits = {});
SceneDescription parse_scene_string(const std::string& toml_text, const std::string& name);

struct BuildOptions {
    BuildOptions(int w = 0, int h = 0, InputLimits l = {}, int t = 0)
        : width(w), height(h), limits(l), threads(t) {}
    int width = 0, height = 0;  // override the file's image size when > 0
    InputLimits limits;         // the largest scene and mesh files read
    int threads = 0;            // that build the BVH (0: every hardware thread; the same tree)
};

// Stage 2. Throws InputError. Warnings (e.g. skipped degenerate triangles) go to stderr. The
// scene's input_files are the description's files_read, then every file stage 2 read.
Scene build_scene(const SceneDescription& description, const BuildOptions& options = {});

// Stage 1 for any scene file: a TOML scene, or a glTF/GLB file as a whole scene (its camera,
// or a default one framing it). The one place that tells the two apart.
SceneDescription describe_scene_file(const std::string& path, const InputLimits& limits = {});

// Both stages.
Scene load_scene(const std::string& path, const BuildOptions& options = {});

// Limits on what a scene may ask for (images larger would not fit in memory here).
inline constexpr int kMaxImageSide = 16384;
// Largest coordinate or radius: single-precision cross products of edges this long still fit.
inline constexpr double kMaxCoordinate = 1e9;

}  // namespace lessons
