// What the glTF reader's files share (private to common/io/). load_gltf (gltf_file.cpp) reads
// the file and the files it names through tinygltf, maps its materials (gltf_material.cpp), then
// walks its node hierarchy (gltf_nodes.cpp), reading each mesh's primitives (gltf_mesh.cpp).
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "io/gltf_file.h"
#include "io/input_error.h"
#include "materials/material.h"

namespace lessons::gltf_reader {

// The model tinygltf read and the file it came from: every refusal an InputError naming the
// file and the glTF field ("accessors[3]", "meshes[0].primitives[1]").
class Reader {
public:
    Reader(const tinygltf::Model& m, std::string path) : model_(m), path_(std::move(path)) {}

    [[noreturn]] void fail(const std::string& field, const std::string& message) const {
        throw InputError(path_, 0, field, message);
    }

    const tinygltf::Model& model() const { return model_; }
    const std::string& path() const { return path_; }

private:
    const tinygltf::Model& model_;
    std::string path_;
};

// An RGB triple of the file, or `fallback` if it has fewer than three numbers.
inline Color rgb(const std::vector<double>& v, Color fallback) {
    if (v.size() < 3) return fallback;
    return Color(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
}

// A number as the notes print it.
inline std::string fixed(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

// A relative URI as a path beside the glTF file, %XX escapes decoded (a bad one kept as it is).
// (gltf_file.cpp)
std::string resolve_uri(const std::string& gltf_path, const std::string& uri);

// A glTF material as the suite's, with a note of what was mapped and what ignored added to
// `notes`; `field` names it in messages ("materials[2]"). (gltf_material.cpp)
Material map_material(const Reader& r, const tinygltf::Material& g, const std::string& field,
                      std::vector<std::string>& notes);

// A primitive's positions, normals, texture coordinates and triangles, in the mesh's own space,
// into `out`; zero-area triangles are left out and counted in `degenerate`. (gltf_mesh.cpp)
void read_primitive(const Reader& r, const tinygltf::Primitive& p, const std::string& field,
                    GltfPrimitive& out, int& degenerate);

// The nodes the scene places: the default scene's, the first scene's, or (no scenes) every node
// that is no node's child. (gltf_nodes.cpp)
std::vector<int> root_nodes(const Reader& r);

// Places every node under `roots`, with its parents' transforms: its meshes' primitives (each
// read once), the first perspective camera and the point lights, into `scene`. Returns how many
// zero-area triangles were left out. (gltf_nodes.cpp)
int place_nodes(const Reader& r, const std::vector<int>& roots, GltfScene& scene);

}  // namespace lessons::gltf_reader
