// The scene parser's files (private to common/io/): scene_file.cpp reads the top level of a
// scene file and hands each [materials.NAME] table to scene_materials.cpp, each [media.NAME]
// table to scene_media.cpp and each [[shapes]] table to scene_shapes.cpp, which places spheres
// and quads with scene_transforms.cpp. Each reads its table with a TableReader (table_reader.h):
// every failure an InputError at file:line:field.
#pragma once

#include <toml++/toml.h>

#include <cstddef>
#include <string>

#include "io/scene_file.h"
#include "io/table_reader.h"

namespace lessons::scene_file {

// [materials.NAME]: the material's type and the fields that type owns; a field of another type
// is refused naming its owner. (scene_materials.cpp)
MaterialDescription parse_material(const toml::table& t, const std::string& file,
                                   const std::string& name);

// [media.NAME]: the medium's type and coefficients. (scene_media.cpp)
MediumDescription parse_medium(const toml::table& t, const std::string& file,
                               const std::string& name);

// The index-th [[shapes]] table: its type's fields, its material and its transform; spheres and
// quads come placed. (scene_shapes.cpp)
ShapeDescription parse_shape(const toml::table& t, const std::string& file, size_t index);

// The shape's `transform` (a list of steps) or `matrix`, if it has one, into s.transform.
// (scene_transforms.cpp)
void read_transform(TableReader& r, ShapeDescription& s);

// Spheres and quads are placed as soon as they are read: their centre and radius, or corner
// and edges, moved by s.transform (a sphere takes a uniform scale only). (scene_transforms.cpp)
void place_sphere(ShapeDescription& s);
void place_quad(ShapeDescription& s);

}  // namespace lessons::scene_file
