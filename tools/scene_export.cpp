// scene_export: a scene as the lessons see it, once loaded, written as one JSON document.
//
//   build/bin/scene_export SCENE [--out FILE.json]
//
// SCENE is a TOML scene or a glTF/GLB file, loaded by the same code as every lesson (both
// stages: boxes become their six quads, transforms are applied, OBJ and glTF files are read and
// triangulated, MTL and glTF materials mapped). What it writes is therefore what the lessons
// render, in world coordinates: spheres, quads, one triangle mesh (positions, shading normals,
// texture coordinates), the materials with every parameter their type uses, the point lights,
// the camera, the image size and the background. The Blender bridge (scripts/blender/) builds
// Cycles scenes from it and compares scenes through it (docs/interop.md). Numbers are written
// with 9 significant digits, which read back to the same float; files (textures, maps) as
// absolute paths.
//
// Exit status 2 for a bad scene (the lessons' message: file, line, field).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/report.h"
#include "io/scene_file.h"
#include "io/shipped_files.h"

using namespace lessons;

namespace {

std::string number(double x) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.9g", x);
    return buffer;
}

template <class V>
std::string vec(const V& v, int n) {
    std::string s = "[";
    for (int i = 0; i < n; ++i) {
        if (i) s += ", ";
        s += number(v[i]);
    }
    s += "]";
    return s;
}
std::string vec3(const Vec3& v) { return vec(v, 3); }

// Writes "key": value pairs of one JSON object, in order.
class Object {
public:
    void put(const std::string& key, const std::string& json) {
        text_ += text_.empty() ? "{" : ", ";
        text_ += json_quote(key);
        text_ += ": ";
        text_ += json;
    }
    std::string str() const { return text_.empty() ? "{}" : text_ + "}"; }

private:
    std::string text_;
};

// Files as absolute paths: the JSON (and a .blend made from it) may be read from elsewhere.
std::string absolute_path(const std::string& path) {
    std::error_code error;
    const std::filesystem::path p = std::filesystem::absolute(path, error);
    return json_quote(error ? path : p.lexically_normal().string());
}

std::string albedo_json(const ColorTexture& t) {
    Object o;
    if (!t.image_file.empty()) {
        o.put("texture", absolute_path(t.image_file));
        o.put("scale", vec(t.scale, 2));
        o.put("wrap", json_quote(t.repeat ? "repeat" : "clamp"));
        if (t.image) o.put("mean", vec3(t.image->mean));
    } else if (t.checker) {
        o.put("checker", "[" + vec3(t.value) + ", " + vec3(t.odd) + "]");
        o.put("cells", vec(t.cells, 2));
    } else {
        o.put("color", vec3(t.value));
    }
    return o.str();
}

std::string material_json(const Material& m) {
    Object o;
    o.put("name", json_quote(m.name));
    const MaterialTypeFacts type = facts_of(m.type);
    o.put("type", json_quote(type.name));
    // The parameters its type uses (materials/material.h), in the scene format's order.
    if (type.albedo) o.put("albedo", albedo_json(m.albedo));
    if (type.lobe) {
        o.put("specular", vec3(m.specular));
        o.put("roughness", number(m.roughness));
    }
    if (type.reflectance) o.put("reflectance", vec3(m.reflectance));
    if (type.dielectric) {
        o.put("ior", number(m.ior));
        o.put("transmittance", vec3(m.transmittance));
    }
    o.put("emission", vec3(m.emission));
    o.put("two_sided", m.two_sided ? "true" : "false");
    return o.str();
}

// A JSON array of the items f(i) for i < n, one per line when `lines`.
template <class F>
std::string array(size_t n, F f, bool lines = true) {
    std::string s = "[";
    for (size_t i = 0; i < n; ++i) {
        s += i ? (lines ? ",\n  " : ", ") : (lines ? "\n  " : "");
        s += f(i);
    }
    s += "]";
    return s;
}

// The point and spot lights and the directional lights, as two JSON arrays: what Blender gets as
// lights (a spot's cone as the scene file gives it: its axis, the half-angle to its edge in
// degrees, and its blend; a directional light's direction of travel and irradiance). The other
// kinds are written with what they are made of: an area light is a shape with an emissive
// material, the environment is the background.
struct LightsJson {
    std::string points, directionals;
};
LightsJson lights_json(const Scene& scene) {
    std::vector<std::string> points, directionals;
    for (const LightRef& light : scene.lights()) {
        switch (light.kind) {
            case LightKind::Point: {
                const PointLight& l = scene.point_lights()[light.index];
                Object o;
                o.put("position", vec3(l.position));
                o.put("intensity", vec3(l.intensity));
                if (l.cone) {
                    Object spot;
                    spot.put("direction", vec3(l.cone->axis));
                    const double cos_outer = l.cone->cos_outer;
                    spot.put("cone_angle",
                             number(std::acos(cos_outer) * 180.0 / 3.14159265358979323846));
                    const double width = 1.0 - cos_outer;  // > 0: the narrowest cone is 0.5 deg
                    spot.put("cone_blend",
                             number(width > 0.0 ? (l.cone->cos_inner - cos_outer) / width : 0.0));
                    o.put("spot", spot.str());
                }
                points.push_back(o.str());
                break;
            }
            case LightKind::Directional: {
                const DirectionalLight& l = scene.directional_lights()[light.index];
                Object o;
                o.put("direction", vec3(l.direction));
                o.put("irradiance", vec3(l.irradiance));
                directionals.push_back(o.str());
                break;
            }
            case LightKind::Area: break;         // its shapes and material
            case LightKind::Environment: break;  // "background"
        }
    }
    return {array(points.size(), [&](size_t i) { return points[i]; }),
            array(directionals.size(), [&](size_t i) { return directionals[i]; })};
}

std::string export_scene(const SceneDescription& d, const Scene& scene) {
    Object o;
    o.put("format", json_quote("lessons scene export 1"));
    o.put("source", json_quote(d.file));
    o.put("description", json_quote(d.description));
    o.put("width", std::to_string(scene.width));
    o.put("height", std::to_string(scene.height));
    Object camera;
    camera.put("position", vec3(d.camera_position));
    camera.put("look_at", vec3(d.camera_look_at));
    camera.put("up", vec3(d.camera_up));
    camera.put("fov", number(d.camera_fov));
    o.put("camera", camera.str());
    Object background;
    if (!d.background_map.empty()) {
        background.put("map", absolute_path(d.background_map));
        background.put("rotate", number(d.background_rotate));
        background.put("strength", number(d.background_strength));
    } else {
        background.put("radiance", vec3(d.background));
    }
    o.put("background", background.str());
    const auto& materials = scene.materials();
    o.put("materials", array(materials.size(), [&](size_t i) { return material_json(materials[i]); }));
    o.put("spheres", array(scene.spheres().size(), [&](size_t i) {
        const Sphere& s = scene.spheres()[i];
        Object p;
        p.put("center", vec3(s.center));
        p.put("radius", number(s.radius));
        p.put("material", std::to_string(scene.material_of(PrimRef(ShapeKind::Sphere, uint32_t(i)))));
        return p.str();
    }));
    o.put("quads", array(scene.quads().size(), [&](size_t i) {
        const Quad& q = scene.quads()[i];
        Object p;
        p.put("corner", vec3(q.corner));
        p.put("edge_u", vec3(q.edge_u));
        p.put("edge_v", vec3(q.edge_v));
        p.put("material", std::to_string(scene.material_of(PrimRef(ShapeKind::Quad, uint32_t(i)))));
        return p.str();
    }));
    // The mesh: flat arrays (three numbers per position and normal, two per uv; three indices,
    // one material and one smooth flag per triangle).
    const auto& tris = scene.triangles();
    Object mesh;
    const auto flat3 = [](const std::vector<Vec3>& v) {
        return array(3 * v.size(), [&](size_t i) { return number(v[i / 3][i % 3]); }, false);
    };
    mesh.put("positions", flat3(scene.positions()));
    mesh.put("normals", flat3(scene.normals()));
    mesh.put("uvs", array(2 * scene.uvs().size(),
                          [&](size_t i) { return number(scene.uvs()[i / 2][i % 2]); }, false));
    mesh.put("triangles", array(3 * tris.size(),
                                [&](size_t i) { return std::to_string(tris[i / 3].v[i % 3]); }, false));
    mesh.put("materials", array(tris.size(), [&](size_t i) { return std::to_string(tris[i].material); }, false));
    mesh.put("smooth", array(tris.size(), [&](size_t i) { return std::string(tris[i].smooth ? "1" : "0"); }, false));
    o.put("mesh", mesh.str());
    const LightsJson lights = lights_json(scene);
    o.put("point_lights", lights.points);
    o.put("directional_lights", lights.directionals);
    o.put("notes", array(scene.notes.size(), [&](size_t i) { return json_quote(scene.notes[i]); }));
    return o.str() + "\n";
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Writes a scene as the lessons load it (world-space shapes, materials, lights, "
                 "camera) as JSON, for the Blender bridge (docs/interop.md)"};
    std::string scene_file, out;
    app.add_option("SCENE", scene_file,
                   "A TOML scene, or a .gltf/.glb file, or the name of a shipped scene "
                   "(cornell_box)")
        ->required();
    app.add_option("--out", out, "The JSON file to write (default: standard output)");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        const SceneDescription d = describe_scene_file(find_scene_file(scene_file));
        Scene scene = build_scene(d);
        // The export has no media yet: said in its notes and on stderr, never dropped unsaid.
        if (scene.contents().media) {
            scene.notes.push_back("media are not exported (the Blender bridge has none yet): " +
                                  scene.media_summary());
            std::cerr << "scene_export: warning: " << scene.notes.back() << "\n";
        }
        const std::string json = export_scene(d, scene);
        if (out.empty()) {
            std::cout << json;
        } else {
            std::ofstream f(out, std::ios::binary);
            f << json;
            f.close();
            if (!f) throw InputError(out, 0, "--out", "cannot write the file");
        }
        return 0;
    } catch (const InputError& e) {
        std::cerr << "scene_export: error: " << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        std::cerr << "scene_export: error: out of memory\n";
        return 2;
    }
}
