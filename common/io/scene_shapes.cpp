// The [[shapes]] tables of a scene file: each shape type's fields (sphere, quad, box, mesh,
// glTF), read and checked, with its material, its interior medium and its transform
// (docs/scene-format.md).
#include <toml++/toml.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "io/gltf_file.h"
#include "io/input_error.h"
#include "io/scene_tables.h"

namespace lessons::scene_file {

namespace {

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

}  // namespace

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
    if (r.has("interior")) {
        // Only a closed surface has an inside (a mesh's closure is checked when it is built).
        if (type == "gltf")
            r.fail("interior", "is not read for a glTF shape: give the medium to a sphere, a box "
                               "or a closed mesh (type = \"mesh\", an OBJ file or inline faces)");
        if (type != "sphere" && type != "box" && type != "mesh")
            r.fail("interior", "a " + type + " is not a closed surface and has no inside: give "
                               "the medium to a sphere, a box or a closed mesh");
        s.interior = r.string("interior");
        s.interior_where = r.where("interior");
        if (s.interior.empty()) r.fail("interior", "must name a medium, got an empty string");
    }
    allowed.push_back("interior");
    r.reject_unknown(allowed, "a " + type,
                     {{"medium", "the top level: write medium = \"NAME\" before the first table"}});
    return s;
}

}  // namespace lessons::scene_file
