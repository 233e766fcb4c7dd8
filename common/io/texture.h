// Image textures for reflectances: read from PNG or JPEG (8 or 16 bits, sRGB-decoded) or EXR
// (linear), checked (every texel finite and in [0, 1]: a surface cannot reflect more than it
// receives), and shared by every material that names the same file.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "materials/material.h"

namespace lessons {

// Reads `path` (a regular file of at most max_bytes); what reading approximated (a multi-part
// EXR's other parts ignored) is added to `notes`, if given. Throws InputError naming the file,
// and the texel for a bad value.
std::shared_ptr<const ImageTexture> read_texture(const std::string& path, uint64_t max_bytes,
                                                 std::vector<std::string>* notes = nullptr);

// Textures read so far while building one scene, by path.
using TextureCache = std::map<std::string, std::shared_ptr<const ImageTexture>>;

}  // namespace lessons
