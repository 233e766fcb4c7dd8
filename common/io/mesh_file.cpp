// OBJ loading: tinyobjloader parses; we validate, de-duplicate vertices and map MTL materials.
//
// MTL mapping (Wavefront illumination models): Ke -> emission; illum 3 or 5 (ray-traced
// reflection) -> mirror with reflectance Ks; illum 4, 6, 7 or 9 or dissolve d < 1 (transparency)
// -> glass with ior Ni; otherwise diffuse with albedo Kd.
#include "io/mesh_file.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <tuple>

#include "io/input_error.h"

namespace lessons {

namespace {

Color clamp_unit(const float c[3]) {
    return glm::clamp(Color(c[0], c[1], c[2]), Color(0.0f), Color(1.0f));
}

Material from_mtl(const tinyobj::material_t& mtl, const std::string& folder) {
    Material m;
    m.name = mtl.name;
    m.emission = glm::max(Color(mtl.emission[0], mtl.emission[1], mtl.emission[2]), Color(0.0f));
    const int illum = mtl.illum;
    if (illum == 4 || illum == 6 || illum == 7 || illum == 9 || mtl.dissolve < 1.0f) {
        m.type = MaterialType::Glass;
        // tinyobjloader reads a missing Ni as 1, which would make the glass invisible.
        m.ior = (mtl.ior > 0.0f && mtl.ior != 1.0f) ? mtl.ior : 1.5f;
    } else if (illum == 3 || illum == 5) {
        m.type = MaterialType::Mirror;
        m.reflectance = clamp_unit(mtl.specular);
    } else {
        m.type = MaterialType::Diffuse;
        m.albedo.value = clamp_unit(mtl.diffuse);
        // map_Kd: the image replaces Kd (read when the scene is built, from the OBJ's folder).
        if (!mtl.diffuse_texname.empty()) {
            const std::filesystem::path tex = mtl.diffuse_texname;
            m.albedo.image_file = (tex.is_absolute() ? tex : std::filesystem::path(folder) / tex)
                                      .lexically_normal()
                                      .string();
        }
    }
    return m;
}

// tinyobjloader reads "nan" or "inf" as 0 without a word; check vertex data ourselves first, so
// a bad value is an error that names its line. Returns the MTL files the OBJ names that exist
// (tinyobjloader reads those).
std::vector<std::string> check_vertex_numbers(const std::string& path, uint64_t max_bytes) {
    std::vector<std::string> mtl_files;
    std::ifstream in(path);
    if (!in) throw InputError(path, 0, "", "cannot open the OBJ file (permissions?)");
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        std::istringstream fields(line);
        std::string keyword;
        fields >> keyword;
        // tinyobjloader opens the MTL library itself: it must be a regular file under the cap
        // too (a missing one is tinyobjloader's warning, as before).
        if (keyword == "mtllib") {
            for (std::string name; fields >> name;) {
                const std::string mtl =
                    (std::filesystem::path(path).parent_path() / name).lexically_normal().string();
                std::error_code ec;
                if (std::filesystem::exists(mtl, ec)) {
                    check_input_file(mtl, "MTL file", max_bytes, "--max-file-mb");
                    mtl_files.push_back(mtl);
                }
            }
            continue;
        }
        if (keyword == "f" || keyword == "l" || keyword == "p") {
            // tinyobjloader keeps an index in an int: one past 2^31 - 1 would wrap to a negative
            // number, and a missing vertex be reported under that.
            for (std::string token; fields >> token;)
                for (size_t start = 0; start <= token.size();) {
                    const size_t slash = std::min(token.find('/', start), token.size());
                    const std::string part = token.substr(start, slash - start);
                    start = slash + 1;
                    if (part.empty()) continue;
                    errno = 0;
                    const long long index = std::strtoll(part.c_str(), nullptr, 10);
                    if (errno == ERANGE || index > INT32_MAX || index < -INT32_MAX)
                        throw InputError(path, number, keyword,
                                         "index '" + part.substr(0, 40) +
                                             "' is out of range (an OBJ index is at most "
                                             "2147483647 in size)");
                }
            continue;
        }
        if (keyword != "v" && keyword != "vn" && keyword != "vt") continue;
        for (std::string token; fields >> token;) {
            char* end = nullptr;
            const double x = std::strtod(token.c_str(), &end);
            const bool number_ok = end != token.c_str() && *end == '\0';
            if (token.size() > 40) token = token.substr(0, 40) + "...";
            if (!number_ok)
                throw InputError(path, number, keyword, "'" + token + "' is not a number");
            if (!std::isfinite(x) || std::fabs(x) > 1e9)
                throw InputError(path, number, keyword,
                                 "'" + token + "' is not a finite coordinate");
        }
    }
    return mtl_files;
}

}  // namespace

namespace {

// Parses the file with tinyobjloader (triangulated, materials from the MTL beside it); its
// warnings go to stderr, its errors become an InputError. Returns the MTL files it read.
std::vector<std::string> parse_obj(const std::string& path, uint64_t max_bytes,
                                   tinyobj::ObjReader& reader) {
    check_input_file(path, "OBJ file", max_bytes, "--max-file-mb");
    std::vector<std::string> mtl_files = check_vertex_numbers(path, max_bytes);
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = std::filesystem::path(path).parent_path().string();
    if (!reader.ParseFromFile(path, config)) {
        std::string err = reader.Error();
        while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
        throw InputError(path, 0, "", "cannot read OBJ: " + (err.empty() ? "unknown error" : err));
    }
    std::istringstream warnings(reader.Warning());
    for (std::string line; std::getline(warnings, line);)
        if (!line.empty()) std::cerr << "warning: " << path << ": " << line << "\n";
    return mtl_files;
}

// The mesh's vertices, one per distinct (position, normal, uv) triple of the file's indices.
class ObjVertices {
public:
    ObjVertices(const std::string& path, const tinyobj::attrib_t& attrib, MeshData& mesh)
        : path_(path), attrib_(attrib), mesh_(mesh) {}
    uint32_t operator()(const tinyobj::index_t& idx) {
        const bool has_normals = !attrib_.normals.empty(), has_uvs = !attrib_.texcoords.empty();
        const int vi = idx.vertex_index;
        const int ni = has_normals ? idx.normal_index : -1;
        const int ti = has_uvs ? idx.texcoord_index : -1;
        if (vi < 0 || 3 * static_cast<size_t>(vi) + 2 >= attrib_.vertices.size())
            throw InputError(
                path_, 0, "f",
                "face refers to vertex " + std::to_string(vi + 1) + ", which does not exist");
        const auto key = std::make_tuple(vi, ni, ti);
        if (auto it = vertex_of_.find(key); it != vertex_of_.end()) return it->second;
        const uint32_t id = static_cast<uint32_t>(mesh_.positions.size());
        const std::vector<float>& v = attrib_.vertices;
        mesh_.positions.emplace_back(v[3 * vi], v[3 * vi + 1], v[3 * vi + 2]);
        if (has_normals) {
            const std::vector<float>& n = attrib_.normals;
            Vec3 normal(0.0f);
            if (ni >= 0 && 3 * static_cast<size_t>(ni) + 2 < n.size())
                normal = Vec3(n[3 * ni], n[3 * ni + 1], n[3 * ni + 2]);
            const float len = glm::length(normal);
            mesh_.normals.push_back(len > 0.0f && std::isfinite(len) ? normal / len : Vec3(0.0f));
        }
        if (has_uvs) {
            Vec2 uv(0.0f);
            if (ti >= 0 && 2 * static_cast<size_t>(ti) + 1 < attrib_.texcoords.size())
                uv = Vec2(attrib_.texcoords[2 * ti], attrib_.texcoords[2 * ti + 1]);
            mesh_.uvs.push_back(uv);
        }
        vertex_of_.emplace(key, id);
        return id;
    }

private:
    const std::string& path_;
    const tinyobj::attrib_t& attrib_;
    MeshData& mesh_;
    std::map<std::tuple<int, int, int>, uint32_t> vertex_of_;
};

}  // namespace

MeshData load_obj(const std::string& path, uint64_t max_bytes) {
    tinyobj::ObjReader reader;
    MeshData mesh;
    mesh.files = {path};
    for (std::string& mtl : parse_obj(path, max_bytes, reader)) mesh.files.push_back(std::move(mtl));
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    for (const tinyobj::material_t& m : reader.GetMaterials())
        mesh.materials.push_back(from_mtl(m, std::filesystem::path(path).parent_path().string()));
    for (size_t i = 0; i < attrib.vertices.size(); ++i)
        if (!std::isfinite(attrib.vertices[i]))
            throw InputError(
                path, 0, "v",
                "vertex " + std::to_string(i / 3 + 1) + " has a non-finite coordinate");

    ObjVertices vertex(path, attrib, mesh);
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const auto& indices = shape.mesh.indices;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            if (shape.mesh.num_face_vertices[f] != 3) continue;  // lines or points
            MeshData::Face face;
            for (int k = 0; k < 3; ++k) face.v[k] = vertex(indices[3 * f + k]);
            const int mat = shape.mesh.material_ids.empty() ? -1 : shape.mesh.material_ids[f];
            face.material = (mat >= 0 && mat < static_cast<int>(mesh.materials.size())) ? mat : -1;
            const Vec3 &a = mesh.positions[face.v[0]], &b = mesh.positions[face.v[1]],
                       &c = mesh.positions[face.v[2]];
            const Vec3 n = glm::cross(b - a, c - a);
            if (!(glm::dot(n, n) > 0.0f)) {
                ++mesh.skipped_degenerate;
                continue;
            }
            mesh.faces.push_back(face);
        }
    }
    if (mesh.faces.empty())
        throw InputError(path, 0, "f", "the OBJ file has no triangles with non-zero area");
    return mesh;
}

}  // namespace lessons
