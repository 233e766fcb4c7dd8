// Stage 1 of scene loading: TOML text -> SceneDescription, with every value checked.
#include "io/scene_file.h"

#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "io/gltf_file.h"
#include "io/input_error.h"
#include "io/input_file.h"
#include "io/table_reader.h"

namespace lessons {

using scene_file::as_number;
using scene_file::TableReader;

namespace {

// albedo = { texture = "FILE", wrap = "repeat" | "clamp", scale = s | [su, sv] }: the file
// resolved against the scene file's folder, read when the scene is built.
ColorTexture parse_texture(TableReader& t, const std::string& scene_file) {
    ColorTexture tex;
    const std::filesystem::path rel = t.string("texture");
    if (rel.empty()) t.fail("texture", "must name an image file (PNG, JPEG or EXR)");
    tex.image_file =
        (rel.is_absolute() ? rel : std::filesystem::path(scene_file).parent_path() / rel)
            .lexically_normal()
            .string();
    if (t.has("wrap")) {
        const std::string wrap = t.string("wrap");
        if (wrap != "repeat" && wrap != "clamp")
            t.fail("wrap",
                   "must be \"repeat\" (tile the image) or \"clamp\" (extend its edges), "
                   "got '" +
                       wrap + "'");
        tex.repeat = wrap == "repeat";
    }
    if (t.has("scale")) {
        if (t.require("scale").is_number()) {
            tex.scale = Vec2(static_cast<float>(t.number_in("scale", 0.0, 1e6, true, false)));
        } else {
            const toml::array& a = t.array("scale");
            if (a.size() != 2 || !a.get(0)->is_number() || !a.get(1)->is_number())
                t.fail("scale", "expected a number or [su, sv]");
            for (int i = 0; i < 2; ++i) {
                const double v = as_number(*a.get(static_cast<size_t>(i)));
                if (!(v > 0.0 && v <= 1e6)) t.fail("scale", "must be in (0, 1e6]");
                tex.scale[i] = static_cast<float>(v);
            }
        }
    }
    t.reject_unknown({"texture", "wrap", "scale"}, "an image texture");
    return tex;
}

ColorTexture parse_albedo(TableReader& r, std::string_view key) {
    const toml::node& n = r.require(key);
    ColorTexture tex;
    if (!n.is_table()) {
        tex.value = r.color_of(n, key, true);
        return tex;
    }
    TableReader checker(*n.as_table(), r.where(key).file, r.field(key));
    if (checker.has("texture")) return parse_texture(checker, r.where(key).file);
    const toml::array& colors = checker.array("checker");
    if (colors.size() != 2)
        checker.fail("checker",
                     "expected two colours [[even], [odd]], got " + std::to_string(colors.size()));
    tex.checker = true;
    tex.value = checker.color_of(*colors.get(0), "checker", true);
    tex.odd = checker.color_of(*colors.get(1), "checker", true);
    const toml::array& cells = checker.array("cells");
    if (cells.size() != 2 || !cells.get(0)->is_integer() || !cells.get(1)->is_integer())
        checker.fail("cells", "expected two integers [cells along u, cells along v]");
    for (int i = 0; i < 2; ++i) {
        const int64_t c = *cells.get(static_cast<size_t>(i))->value<int64_t>();
        if (c < 1 || c > 100000) checker.fail("cells", "must be between 1 and 100000");
        tex.cells[i] = static_cast<float>(c);
    }
    checker.reject_unknown({"checker", "cells"}, "a checker albedo (or give texture = FILE)");
    return tex;
}

const std::vector<std::pair<std::string, std::string>> kMaterialFieldOwners = {
    {"albedo", "diffuse and glossy materials"},
    {"specular", "glossy and conductor materials"},
    {"roughness", "glossy and conductor materials"},
    {"reflectance", "mirror materials"},
    {"ior", "glass materials"},
    {"transmittance", "glass materials"}};

MaterialDescription parse_material(const toml::table& t, const std::string& file,
                                   const std::string& name) {
    TableReader r(t, file, "materials." + name);
    MaterialDescription d;
    d.where = {file, r.line(), "materials." + name};
    Material& m = d.material;
    m.name = name;
    const std::string type = r.string("type");
    m.emission = r.color("emission", false, Color(0.0f));
    m.two_sided = r.boolean("two_sided", false);
    std::vector<std::string> allowed = {"type", "emission", "two_sided"};
    if (type == "diffuse") {
        m.type = MaterialType::Diffuse;
        // An emitter may leave its albedo out (it reflects nothing); any other surface must say.
        if (r.has("albedo") || !m.is_emissive()) m.albedo = parse_albedo(r, "albedo");
        d.albedo_where = r.where("albedo");
        allowed.push_back("albedo");
    } else if (type == "glossy") {
        m.type = MaterialType::Glossy;
        if (r.has("albedo")) m.albedo = parse_albedo(r, "albedo");
        d.albedo_where = r.where("albedo");
        m.specular = r.color("specular", true, Color(1.0f));
        m.roughness = static_cast<float>(r.number_in("roughness", 0.0, 1.0, true, false));
        // Energy conservation: the diffuse base and the lobe share what the surface receives.
        const Color base = glm::max(m.albedo.value, m.albedo.checker ? m.albedo.odd : Color(0.0f));
        if (max_component(base + m.specular) > 1.0f)
            r.fail(r.has("specular") ? "specular" : "albedo",
                   "albedo + specular must be at most 1 in every channel (a surface cannot "
                   "reflect more light than it receives); lower specular (default 1)");
        allowed.insert(allowed.end(), {"albedo", "specular", "roughness"});
    } else if (type == "conductor") {
        m.type = MaterialType::Conductor;
        m.specular = r.color("specular", true);
        m.roughness = static_cast<float>(r.number_in("roughness", 0.0, 1.0, true, false));
        allowed.insert(allowed.end(), {"specular", "roughness"});
    } else if (type == "mirror") {
        m.type = MaterialType::Mirror;
        m.reflectance = r.color("reflectance", true, Color(1.0f));
        allowed.push_back("reflectance");
    } else if (type == "glass") {
        m.type = MaterialType::Glass;
        m.ior = static_cast<float>(r.number_in("ior", 0.0, 10.0, true, false, 1.5));
        m.transmittance = r.color("transmittance", true, Color(1.0f));
        allowed.insert(allowed.end(), {"ior", "transmittance"});
    } else {
        const std::vector<std::string> types = {"diffuse", "glossy", "conductor", "mirror",
                                                "glass"};
        r.fail("type", "unknown material type '" + type + "'" + did_you_mean(type, types) +
                           known_names(types));
    }
    r.reject_unknown(allowed, "a " + type + " material", kMaterialFieldOwners);
    return d;
}

// ---- transforms ----

// One step of a `transform` list: { scale = s | [x, y, z] }, { rotate = { axis, angle } } or
// { translate = [x, y, z] }.
Transform read_transform_step(TableReader& step) {
    std::vector<std::string> present;
    for (const std::string k : {"scale", "rotate", "translate"})
        if (step.has(k)) present.push_back(k);
    if (present.size() != 1)
        step.fail(present.empty() ? "scale" : present[1],
                  "each step of a transform is one of scale, rotate or translate, e.g. "
                  "{ scale = 2 }, { rotate = { axis = [0, 1, 0], angle = 30 } }, "
                  "{ translate = [1, 0, 0] }");
    Transform t;
    if (present[0] == "scale") {
        glm::dvec3 s;
        if (step.require("scale").is_number())
            s = glm::dvec3(step.number("scale"));
        else
            s = step.dvec3("scale");
        for (int i = 0; i < 3; ++i)
            if (s[i] == 0.0)
                step.fail("scale",
                          "must not be zero: a zero scale flattens the shape (and its "
                          "normals cannot follow)");
        t = Transform::scaling(s);
    } else if (present[0] == "rotate") {
        TableReader rotate(step.table("rotate"), step.where("rotate").file, step.field("rotate"));
        const glm::dvec3 axis = rotate.dvec3("axis");
        if (glm::dot(axis, axis) == 0.0) rotate.fail("axis", "must not be the zero vector");
        t = Transform::rotation(axis, rotate.number("angle"));
        rotate.reject_unknown({"axis", "angle"}, "a rotation (angle in degrees)");
    } else {
        t = Transform::translation(step.dvec3("translate"));
    }
    step.reject_unknown(present, "a transform step");
    return t;
}

// matrix = [[4 numbers] x 4], row by row (column vectors: x' = m00 x + m01 y + m02 z + m03);
// the last row must be [0, 0, 0, 1].
Transform read_matrix(TableReader& r) {
    const toml::array& rows = r.array("matrix");
    if (rows.size() != 4) r.fail("matrix", "expected 4 rows of 4 numbers");
    double m[4][4];
    for (size_t i = 0; i < 4; ++i) {
        const toml::array* row = rows.get(i)->as_array();
        if (!row || row->size() != 4) r.fail("matrix", "expected 4 rows of 4 numbers");
        for (size_t j = 0; j < 4; ++j) {
            const toml::node& c = *row->get(j);
            if (!c.is_number() || !std::isfinite(as_number(c)))
                r.fail("matrix", "row " + std::to_string(i) + ": expected finite numbers");
            m[i][j] = as_number(c);
        }
    }
    if (m[3][0] != 0.0 || m[3][1] != 0.0 || m[3][2] != 0.0 || m[3][3] != 1.0)
        r.fail("matrix", "the last row must be [0, 0, 0, 1] (an affine transform)");
    Transform t;
    for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) t.linear[col][row] = m[row][col];
        t.offset[row] = m[row][3];
    }
    // Invertible, relative to the size of its columns (a scale of 1e-6 is fine, a flat one not).
    const double size =
        glm::length(t.linear[0]) * glm::length(t.linear[1]) * glm::length(t.linear[2]);
    if (!(std::fabs(t.determinant()) > 1e-12 * size))
        r.fail("matrix", "is not invertible (its determinant is 0): it flattens the shape");
    return t;
}

// The shape's `transform` (a list of steps) or `matrix`, if it has one.
void read_transform(TableReader& r, ShapeDescription& s) {
    if (r.has("transform") && r.has("matrix"))
        r.fail("matrix", "give either transform (a list of steps) or matrix, not both");
    if (r.has("matrix")) {
        s.transform_where = r.where("matrix");
        s.transform = read_matrix(r);
    } else if (r.has("transform")) {
        s.transform_where = r.where("transform");
        const toml::array& steps = r.array("transform");
        for (size_t i = 0; i < steps.size(); ++i) {
            const toml::table* t = steps.get(i)->as_table();
            const std::string field = r.field("transform") + "[" + std::to_string(i) + "]";
            if (!t)
                r.fail("transform", "step " + std::to_string(i) +
                                        ": expected a table, e.g. "
                                        "{ scale = 2 }");
            TableReader step(*t, s.where.file, field);
            s.transform = s.transform.then(read_transform_step(step));
        }
    }
}

// A point after the transform, checked to stay within single precision's reach.
Vec3 placed_point(const ShapeDescription& s, const glm::dvec3& p) {
    const glm::dvec3 q = s.transform.point(p);
    if (!(max_component(glm::abs(q)) <= kMaxCoordinate))
        throw InputError(s.transform_where.file, s.transform_where.line, s.transform_where.field,
                         "moves the shape too far for single precision geometry (|x| must be at "
                         "most 1e9)");
    return Vec3(q);
}

// Spheres and quads are placed as soon as they are read.
void place_sphere(ShapeDescription& s) {
    if (s.transform.is_identity()) return;
    const double scale = s.transform.uniform_scale();
    if (scale == 0.0)
        throw InputError(s.transform_where.file, s.transform_where.line, s.transform_where.field,
                         "a sphere takes rotations, mirrors, translations and a uniform scale "
                         "only; this transform stretches it unevenly (an ellipsoid): use a mesh");
    s.center = placed_point(s, glm::dvec3(s.center));
    s.radius = static_cast<float>(s.radius * scale);
}

void place_quad(ShapeDescription& s) {
    if (s.transform.is_identity()) return;
    const glm::dvec3 corner(s.corner), u(s.edge_u), v(s.edge_v);
    s.corner = placed_point(s, corner);
    s.edge_u = Vec3(s.transform.vector(u));
    s.edge_v = Vec3(s.transform.vector(v));
    placed_point(s, corner + u + v);
    // A mirror reverses cross(u, v): swapping the edges keeps the front side the mirror image
    // of the front side (a one-sided lamp still lights what its image faces).
    if (s.transform.mirrors()) std::swap(s.edge_u, s.edge_v);
    if (!(Quad(s.corner, s.edge_u, s.edge_v).area() > 0.0f))
        throw InputError(s.transform_where.file, s.transform_where.line, s.transform_where.field,
                         "leaves the quad no area in single precision");
}

// The fields of each shape type, read into `s`; each returns the field names it allows.
std::vector<std::string> read_sphere(TableReader& r, ShapeDescription& s) {
    s.type = ShapeDescription::Type::Sphere;
    s.center = r.vec3("center");
    s.radius = static_cast<float>(r.number_in("radius", 0.0, kMaxCoordinate, true, false));
    return {"center", "radius"};
}

std::vector<std::string> read_quad(TableReader& r, ShapeDescription& s) {
    s.type = ShapeDescription::Type::Quad;
    s.corner = r.vec3("corner");
    s.edge_u = r.nonzero_vec3("edge_u");
    s.edge_v = r.nonzero_vec3("edge_v");
    const Vec3 n = glm::cross(s.edge_u, s.edge_v);
    if (!(glm::dot(n, n) > 0.0f)) r.fail("edge_v", "is parallel to edge_u: the quad has no area");
    return {"corner", "edge_u", "edge_v"};
}

std::vector<std::string> read_box(TableReader& r, ShapeDescription& s) {
    s.type = ShapeDescription::Type::Box;
    if ((r.has("rotate_y") || r.has("translate")) && (r.has("transform") || r.has("matrix")))
        r.fail(r.has("rotate_y") ? "rotate_y" : "translate",
               "give either rotate_y and translate, or a transform (which can do both), not both");
    s.box_min = r.dvec3("min");
    s.box_max = r.dvec3("max");
    for (int i = 0; i < 3; ++i)
        if (!(s.box_max[i] > s.box_min[i])) {
            std::ostringstream m;
            m << "must be greater than min on every axis; on "
              << "xyz"[i] << ", max = " << s.box_max[i] << " <= min = " << s.box_min[i];
            r.fail("max", m.str());
        }
    // rotate_y and translate are a transform: about y, then moved (as they always were).
    if (r.has("rotate_y") || r.has("translate")) {
        s.transform_where = r.where(r.has("translate") ? "translate" : "rotate_y");
        s.transform = Transform::rotation_y(r.number("rotate_y", 0.0))
                          .then(Transform::translation(r.dvec3("translate", glm::dvec3(0.0))));
    }
    // The faces as they will be built: still within single-precision reach, and not so thin
    // that an edge rounds to nothing.
    for (const Quad& q : box_faces(s)) {
        for (const Vec3& p :
             {q.corner, q.corner + q.edge_u, q.corner + q.edge_v, q.corner + q.edge_u + q.edge_v})
            if (max_component(glm::abs(p)) > kMaxCoordinate)
                r.fail(r.has("translate") ? "translate" : "max",
                       "the placed box is too large for single precision "
                       "geometry (|x| must be at most 1e9)");
        if (!(q.area() > 0.0f))
            r.fail("max", "the box is too thin for single precision: a face has no area");
    }
    return {"min", "max", "rotate_y", "translate"};
}

// An inline mesh's faces: arrays of at least three indices into its vertices.
void read_inline_faces(TableReader& r, ShapeDescription& s) {
    const toml::array& faces = r.array("faces");
    for (size_t i = 0; i < faces.size(); ++i) {
        const toml::array* f = faces.get(i)->as_array();
        const std::string which = "face " + std::to_string(i);
        if (!f || f->size() < 3)
            r.fail("faces", which + ": expected an array of at least 3 vertex indices");
        std::vector<uint32_t> face;
        for (size_t k = 0; k < f->size(); ++k) {
            const toml::node& v = *f->get(k);
            if (!v.is_integer()) r.fail("faces", which + ": indices must be integers");
            const int64_t idx = *v.value<int64_t>();
            if (idx < 0 || idx >= static_cast<int64_t>(s.vertices.size()))
                r.fail("faces", which + ": index " + std::to_string(idx) + " is outside 0.." +
                                    std::to_string(s.vertices.size() - 1));
            face.push_back(static_cast<uint32_t>(idx));
        }
        s.faces.push_back(std::move(face));
    }
    if (s.faces.empty()) r.fail("faces", "a mesh needs at least one face");
}

std::vector<std::string> read_mesh(TableReader& r, ShapeDescription& s, const std::string& file) {
    s.type = ShapeDescription::Type::Mesh;
    if (r.has("file")) {
        if (r.has("vertices") || r.has("faces"))
            r.fail("file", "give either a file or inline vertices and faces, not both");
        const std::filesystem::path rel = r.string("file");
        s.file_where = r.where("file");
        s.file = (rel.is_absolute() ? rel : std::filesystem::path(file).parent_path() / rel)
                     .lexically_normal()
                     .string();
    } else {
        if (!r.has("vertices") && !r.has("faces"))
            r.fail("file", "missing: a mesh needs a file, or inline vertices and faces");
        const toml::array& vertices = r.array("vertices");
        for (size_t i = 0; i < vertices.size(); ++i)
            s.vertices.push_back(r.vec3_of(*vertices.get(i), "vertices"));
        read_inline_faces(r, s);
        if (s.material.empty()) r.require("material");  // inline meshes have no MTL
    }
    return {"file", "vertices", "faces"};
}

// A glTF 2.0 file (.gltf or .glb) placed as one shape: its triangles, materials (unless
// `material` overrides them) and point lights (docs/interop.md).
std::vector<std::string> read_gltf(TableReader& r, ShapeDescription& s, const std::string& file) {
    s.type = ShapeDescription::Type::Gltf;
    const std::filesystem::path rel = r.string("file");
    s.file_where = r.where("file");
    s.file = (rel.is_absolute() ? rel : std::filesystem::path(file).parent_path() / rel)
                 .lexically_normal()
                 .string();
    if (!is_gltf_file(s.file)) r.fail("file", "must be a .gltf or .glb file");
    return {"file"};
}

ShapeDescription parse_shape(const toml::table& t, const std::string& file, size_t index) {
    const std::string path = "shapes[" + std::to_string(index) + "]";
    TableReader r(t, file, path);
    ShapeDescription s;
    s.where = {file, r.line(), path};
    const std::string type = r.string("type");
    std::vector<std::string> allowed = {"type", "material"};
    if (r.has("material") || (type != "mesh" && type != "gltf")) {
        s.material = r.string("material");
        s.material_where = r.where("material");
        if (s.material.empty()) r.fail("material", "must name a material, got an empty string");
    }
    std::vector<std::string> fields;
    if (type != "box" || !(r.has("rotate_y") || r.has("translate"))) read_transform(r, s);
    allowed.insert(allowed.end(), {"transform", "matrix"});
    if (type == "sphere") {
        fields = read_sphere(r, s);
        place_sphere(s);
    } else if (type == "quad") {
        fields = read_quad(r, s);
        place_quad(s);
    } else if (type == "box") {
        fields = read_box(r, s);
    } else if (type == "mesh") {
        fields = read_mesh(r, s, file);
    } else if (type == "gltf") {
        fields = read_gltf(r, s, file);
    } else {
        const std::vector<std::string> types = {"sphere", "quad", "box", "mesh", "gltf"};
        r.fail("type", "unknown shape type '" + type + "'" + did_you_mean(type, types) +
                           known_names(types));
    }
    allowed.insert(allowed.end(), fields.begin(), fields.end());
    r.reject_unknown(allowed, "a " + type);
    return s;
}

// [background]: a uniform radiance, or a map (an EXR of radiance) with its rotation and strength.
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
    if (rel.extension() != ".exr" && rel.extension() != ".EXR")
        bg.fail("map", "an environment map is an OpenEXR file of linear radiance (.exr)");
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

PointLightDescription parse_light(const toml::table& t, const std::string& file, size_t index) {
    const std::string path = "lights[" + std::to_string(index) + "]";
    TableReader l(t, file, path);
    const std::string type = l.string("type");
    if (type != "point") {
        const std::vector<std::string> types = {"point"};
        l.fail("type", "unknown light type '" + type + "'" + did_you_mean(type, types) +
                           " (known: point; area lights are shapes with an emissive material)");
    }
    PointLightDescription p;
    p.where = {file, l.line(), path};
    p.light.position = l.vec3("position");
    p.light.intensity = l.color("intensity", false);
    l.reject_unknown({"type", "position", "intensity"}, "a point light");
    return p;
}

SceneDescription parse_table(const toml::table& root, const std::string& file) {
    SceneDescription d;
    d.file = file;
    TableReader top(root, file, "");
    if (top.has("description")) d.description = top.string("description");
    read_image_and_camera(top, file, d);
    if (top.has("background")) read_background(top, file, d);
    if (top.has("materials")) {
        for (const auto& [key, node] : top.table("materials")) {
            const std::string name(key.str());
            if (!node.is_table())
                throw InputError(file, static_cast<int>(node.source().begin.line),
                                 "materials." + name,
                                 "expected a table [materials." + name + "] with a type");
            d.materials.push_back(parse_material(*node.as_table(), file, name));
        }
    }
    for_each_table(top, file, "shapes", [&](const toml::table& t, size_t i) {
        d.shapes.push_back(parse_shape(t, file, i));
    });
    for_each_table(top, file, "lights", [&](const toml::table& t, size_t i) {
        d.point_lights.push_back(parse_light(t, file, i));
    });
    top.reject_unknown(
        {"description", "image", "camera", "background", "materials", "shapes", "lights"},
        "the scene");
    if (d.shapes.empty() && d.point_lights.empty())
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
