// Fuzzing the glTF loader (docs/interop.md): any file must load as a scene or give an InputError,
// never crash. tinygltf reads from a file, so each input is written to this process's scratch
// file first: as .glb when it starts with the binary container's magic, else as .gltf.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/gltf_file.h"
#include "io/input_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace lessons;
    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("lessons_fuzz_" + std::to_string(getpid()) +
                               (binary ? ".glb" : ".gltf")))
                                 .string();
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
        const GltfScene scene = load_gltf(path, 1 << 20);  // (files it names: 1 MiB at most)
        // The loader's promises: every index names a vertex, every material exists.
        for (const GltfPrimitive& p : scene.primitives) {
            if (p.material < 0 || p.material >= static_cast<int>(scene.materials.size()))
                __builtin_trap();
            for (const auto& t : p.triangles)
                for (uint32_t v : t)
                    if (v >= p.positions.size()) __builtin_trap();
            if (!p.normals.empty() && p.normals.size() != p.positions.size()) __builtin_trap();
            if (!p.uvs.empty() && p.uvs.size() != p.positions.size()) __builtin_trap();
        }
    } catch (const InputError&) {
    }
    return 0;
}
