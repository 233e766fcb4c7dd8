// Triangle meshes from Wavefront OBJ files (and their MTL materials), through tinyobjloader.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "io/input_file.h"
#include "materials/material.h"

namespace lessons {

struct MeshData {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  // empty, or one per position
    std::vector<Vec2> uvs;      // empty, or one per position
    struct Face {
        uint32_t v[3];
        int material;  // index into `materials`, or -1 when the face names none
    };
    std::vector<Face> faces;
    std::vector<Material> materials;  // from the MTL file, mapped onto our material types
    int skipped_degenerate = 0;       // zero-area triangles dropped
    std::vector<std::string> files;   // the files read: the OBJ, then each MTL it loaded (the
                                      // images an MTL names are read with the materials)
};

// Loads and triangulates an OBJ file. Vertices are de-duplicated per (position, normal, uv)
// triple. Non-finite coordinates and out-of-range indices are errors (InputError naming the
// file and the field); zero-area triangles are skipped and counted.
// The file must be a regular file of at most max_bytes (input_file.h).
MeshData load_obj(const std::string& path, uint64_t max_bytes = InputLimits{}.file_bytes());

}  // namespace lessons
