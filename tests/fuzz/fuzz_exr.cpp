// Fuzzing the EXR image reader (references, environment maps, textures): any file must read as
// an image or give an error naming it, never crash or abort. The reader opens a file (OpenEXR's
// two libraries, the header check's and the decoder's), so each input is written to this
// process's scratch file first. OpenEXR is not built with the fuzzer's instrumentation: inside
// it the mutations are blind.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "io/image.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace lessons;
    static const std::string path = (std::filesystem::temp_directory_path() /
                                     ("lessons_fuzz_" + std::to_string(getpid()) + "_image.exr"))
                                        .string();
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
        const Image image = read_exr(path);
        // The reader's promise: the pixels are the image's size.
        if (image.width <= 0 || image.height <= 0 ||
            image.pixels.size() != static_cast<size_t>(image.width) * image.height)
            __builtin_trap();
    } catch (const std::runtime_error&) {
    }
    return 0;
}
