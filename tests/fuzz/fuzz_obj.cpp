// Fuzzing the OBJ path: any file must load as a mesh or give an InputError. tinyobjloader reads
// from a file, so each input is written to this process's scratch file first.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/input_error.h"
#include "io/mesh_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace lessons;
    static const std::string path = (std::filesystem::temp_directory_path() /
                                     ("lessons_fuzz_" + std::to_string(getpid()) + ".obj"))
                                        .string();
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
        const MeshData mesh = load_obj(path);
        for (const MeshData::Face& f : mesh.faces)
            for (uint32_t v : f.v)
                if (v >= mesh.positions.size()) __builtin_trap();  // the loader's promise
    } catch (const InputError&) {
    }
    return 0;
}
