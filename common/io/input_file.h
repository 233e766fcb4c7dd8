// Reading the files a scene names (the scene file itself, meshes, textures), defensively: only
// regular files (never a device, a FIFO or a socket, which could be endless: /dev/zero), never
// more than a cap (a scene file is text of a few kilobytes; a mesh may be large, but not larger
// than the user allows), each refusal an InputError naming the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace lessons {

struct InputLimits {
    double scene_mb = 16.0;   // a scene file (TOML), in MiB (--max-scene-mb)
    double file_mb = 4096.0;  // a mesh or image file it names, in MiB (--max-file-mb)
    uint64_t scene_bytes() const { return static_cast<uint64_t>(scene_mb * 1048576.0); }
    uint64_t file_bytes() const { return static_cast<uint64_t>(file_mb * 1048576.0); }
};

// Checks that `path` is a regular file of at most `max_bytes`; `what` names it in messages
// ("scene file", "OBJ file") and `flag` the option that raises the cap. Returns its size.
uint64_t check_input_file(const std::string& path, const std::string& what, uint64_t max_bytes,
                          const std::string& flag);
// Throws InputError(where, 0, field, ...) when `bytes` is more than half of this machine's
// physical memory: `what` says what would need them ("512x512 needs").
void check_fits_in_memory(double bytes, const std::string& what, const std::string& where,
                          const std::string& field);

// 64-bit FNV-1a: fnv1a(h, data, bytes) continues hash h over the bytes, from kFnvStart. The
// start is the suite's own (it differs from FNV's published offset in one digit) and stays:
// the parts of a farmed render carry hashes made with it.
inline constexpr uint64_t kFnvStart = 1469598103934665603ull;
inline uint64_t fnv1a(uint64_t h, const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}
// fnv1a of a file's bytes (0 if it cannot be read): names what a file holds.
uint64_t file_hash(const std::string& path);
// The same, then the whole file's bytes.
std::string read_input_file(const std::string& path, const std::string& what, uint64_t max_bytes,
                            const std::string& flag);

}  // namespace lessons
