// Stage 1 of scene loading: TOML text -> SceneDescription, with every value checked: the top
// level and its small tables ([image], [camera], [background], [[lights]], `medium`) here, each
// material, medium and shape by its own file (scene_tables.h).
#include "io/scene_file.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "io/gltf_file.h"
#include "io/input_error.h"
#include "io/input_file.h"
#include "io/scene_tables.h"

namespace lessons {

using scene_file::TableReader;

namespace {

// [background]: a uniform radiance, or a map (an EXR or .hdr of radiance) with its rotation and
// strength.
void read_background(TableReader& top, const std::string& file, SceneDescription& d) {
    TableReader bg(top.table("background"), file, "background");
    if (bg.has("radiance") == bg.has("map"))
        bg.fail(bg.has("map") ? "map" : "radiance",
                "give either radiance = [r, g, b] (a uniform sky) or map = \"FILE.exr\" (an "
                "environment map), one of the two");
    if (bg.has("radiance")) {
        d.background = bg.color("radiance", false);
        bg.reject_unknown({"radiance"}, "[background] with a uniform radiance");
        return;
    }
    const std::filesystem::path rel = bg.string("map");
    d.background_where = bg.where("map");
    std::string ext = rel.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext != ".exr" && ext != ".hdr")
        bg.fail("map", "an environment map is an OpenEXR file (.exr) or a Radiance HDR file "
                       "(.hdr) of linear radiance");
    d.background_map = (rel.is_absolute() ? rel : std::filesystem::path(file).parent_path() / rel)
                           .lexically_normal()
                           .string();
    d.background_rotate = static_cast<float>(bg.number("rotate", 0.0));
    d.background_strength =
        static_cast<float>(bg.number_in("strength", 0.0, 1e9, true, false, 1.0));
    bg.reject_unknown({"map", "rotate", "strength"}, "[background] with a map");
}

// [image] and [camera], into d.
void read_image_and_camera(TableReader& top, const std::string& file, SceneDescription& d) {
    TableReader image(top.table("image"), file, "image");
    d.width = image.integer_in("width", 1, kMaxImageSide);
    d.height = image.integer_in("height", 1, kMaxImageSide);
    image.reject_unknown({"width", "height"}, "[image]");

    TableReader camera(top.table("camera"), file, "camera");
    d.camera_where = {file, camera.line(), "camera"};
    d.camera_position = camera.vec3("position");
    d.camera_look_at = camera.vec3("look_at");
    d.camera_up = camera.has("up") ? camera.nonzero_vec3("up") : Vec3(0.0f, 1.0f, 0.0f);
    d.camera_fov = static_cast<float>(camera.number_in("fov", 0.0, 180.0, true, true));
    const Vec3 forward = d.camera_look_at - d.camera_position;
    if (glm::dot(forward, forward) == 0.0f)
        camera.fail("look_at", "equals position: the camera looks nowhere");
    const Vec3 side = glm::cross(glm::normalize(forward), glm::normalize(d.camera_up));
    if (glm::dot(side, side) < 1e-10f)
        camera.fail("up", "is parallel to the viewing direction (look_at - position)");
    camera.reject_unknown({"position", "look_at", "up", "fov"}, "[camera]");
}

// Every table of an array of tables ([[shapes]], [[lights]]), with its index; an element that is
// not a table is an error naming it.
template <class ReadFn>
void for_each_table(TableReader& top, const std::string& file, const std::string& key,
                    ReadFn&& read) {
    if (!top.has(key)) return;
    const toml::array& tables = top.array(key);
    for (size_t i = 0; i < tables.size(); ++i) {
        const toml::table* t = tables.get(i)->as_table();
        if (!t)
            throw InputError(file, static_cast<int>(tables.get(i)->source().begin.line),
                             key + "[" + std::to_string(i) + "]",
                             "expected a table ([[" + key + "]])");
        read(*t, i);
    }
}

// Every table of a table of named tables ([materials.NAME], [media.NAME]), with its name; an
// entry that is not a table is an error naming it.
template <class ReadFn>
void for_each_named_table(TableReader& top, const std::string& file, const std::string& key,
                          ReadFn&& read) {
    if (!top.has(key)) return;
    for (const auto& [name_key, node] : top.table(key)) {
        const std::string name(name_key.str());
        if (!node.is_table())
            throw InputError(file, static_cast<int>(node.source().begin.line), key + "." + name,
                             "expected a table [" + key + "." + name + "] with a type");
        read(*node.as_table(), name);
    }
}

// A spot's cone from its half-angle to the edge (degrees) and its blend: the fraction of the
// cone's 1 - cos over which it fades to nothing (Blender's spot blend; SpotCone::falloff).
SpotCone spot_cone(TableReader& l, const Vec3& direction) {
    const double angle = l.number_in("cone_angle", kNarrowestSpotDegrees, 90.0, false, false);
    const double blend = l.number_in("cone_blend", 0.0, 1.0, false, false, 0.0);
    const double cos_outer = std::cos(angle * 3.14159265358979323846 / 180.0);
    const double cos_inner = cos_outer + blend * (1.0 - cos_outer);
    return {glm::normalize(direction), static_cast<float>(cos_outer),
            static_cast<float>(cos_inner)};
}

void parse_light(const toml::table& t, const std::string& file, size_t index,
                 SceneDescription& d) {
    const std::string path = "lights[" + std::to_string(index) + "]";
    TableReader l(t, file, path);
    const std::string type = l.string("type");
    const std::vector<std::string> types = {"point", "spot", "directional"};
    if (std::find(types.begin(), types.end(), type) == types.end())
        l.fail("type", "unknown light type '" + type + "'" + did_you_mean(type, types) +
                           " (known: point, spot, directional; area lights are shapes with an "
                           "emissive material)");
    if (type == "directional") {
        DirectionalLightDescription dl;
        dl.where = {file, l.line(), path};
        dl.light.direction = glm::normalize(l.nonzero_vec3("direction"));
        dl.light.irradiance = l.color("irradiance", false);
        l.reject_unknown({"type", "direction", "irradiance"}, "a directional light");
        d.directional_lights.push_back(dl);
        return;
    }
    PointLightDescription p;
    p.where = {file, l.line(), path};
    p.light.position = l.vec3("position");
    p.light.intensity = l.color("intensity", false);
    if (type == "spot") {
        p.light.cone = spot_cone(l, l.nonzero_vec3("direction"));
        l.reject_unknown({"type", "position", "intensity", "direction", "cone_angle", "cone_blend"},
                         "a spot light");
    } else {
        l.reject_unknown({"type", "position", "intensity"}, "a point light");
    }
    d.point_lights.push_back(p);
}

// A medium's name, as the top-level `medium` or a shape's `interior` gives it: one of the
// [media.NAME] tables.
void check_medium_name(const std::string& name, const SourceLocation& where,
                       const SceneDescription& d) {
    std::vector<std::string> names;
    for (const MediumDescription& m : d.media) names.push_back(m.medium.name);
    if (std::find(names.begin(), names.end(), name) != names.end()) return;
    throw InputError(where.file, where.line, where.field,
                     "unknown medium '" + name + "'" + did_you_mean(name, names) +
                         (names.empty() ? " (the scene defines no [media.*])"
                                        : known_names(names)));
}

SceneDescription parse_table(const toml::table& root, const std::string& file) {
    SceneDescription d;
    d.file = file;
    TableReader top(root, file, "");
    if (top.has("description")) d.description = top.string("description");
    read_image_and_camera(top, file, d);
    if (top.has("background")) read_background(top, file, d);
    for_each_named_table(top, file, "materials",
                         [&](const toml::table& t, const std::string& name) {
                             d.materials.push_back(scene_file::parse_material(t, file, name));
                         });
    for_each_named_table(top, file, "media", [&](const toml::table& t, const std::string& name) {
        d.media.push_back(scene_file::parse_medium(t, file, name));
    });
    if (top.has("medium")) {
        d.medium = top.string("medium");
        d.medium_where = top.where("medium");
        check_medium_name(d.medium, d.medium_where, d);
    }
    for_each_table(top, file, "shapes", [&](const toml::table& t, size_t i) {
        d.shapes.push_back(scene_file::parse_shape(t, file, i));
        const ShapeDescription& s = d.shapes.back();
        if (!s.interior.empty()) check_medium_name(s.interior, s.interior_where, d);
    });
    for_each_table(top, file, "lights", [&](const toml::table& t, size_t i) {
        parse_light(t, file, i, d);
    });
    top.reject_unknown(
        {"description", "image", "camera", "background", "materials", "media", "medium", "shapes",
         "lights"},
        "the scene");
    if (d.shapes.empty() && d.point_lights.empty() && d.directional_lights.empty())
        throw InputError(file, 0, "shapes", "the scene is empty: no shapes and no lights");
    return d;
}

}  // namespace

SceneDescription parse_scene_string(const std::string& text, const std::string& name) {
    toml::table root;
    try {
        root = toml::parse(text, name);
    } catch (const toml::parse_error& e) {
        throw InputError(name, static_cast<int>(e.source().begin.line), "",
                         "TOML syntax error: " + std::string(e.description()));
    }
    return parse_table(root, name);
}

SceneDescription parse_scene_file(const std::string& path, const InputLimits& limits) {
    SceneDescription d = parse_scene_string(
        read_input_file(path, "scene file", limits.scene_bytes(), "--max-scene-mb"), path);
    d.files_read = {path};
    return d;
}

SceneDescription describe_scene_file(const std::string& path, const InputLimits& limits) {
    return is_gltf_file(path) ? gltf_scene_description(path, limits)
                              : parse_scene_file(path, limits);
}

Scene load_scene(const std::string& path, const BuildOptions& options) {
    return build_scene(describe_scene_file(path, options.limits), options);
}

}  // namespace lessons
