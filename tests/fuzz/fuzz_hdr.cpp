// Fuzzing the Radiance .hdr reader (environment maps, textures): any file must read as an image
// or give an error naming it, never crash, hang or allocate for a size the file cannot hold.
// stb_image 2.27 reads zeros past the end of a file and loops for ever on a run of length 0:
// io/image_hdr.cpp's walk of the file must keep it from both (libFuzzer's -timeout catches a
// hang, -rss_limit_mb an allocation).
#include <unistd.h>

#include <cmath>
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
                                     ("lessons_fuzz_" + std::to_string(getpid()) + "_image.hdr"))
                                        .string();
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
        const Image image = read_hdr(path);
        // The reader's promises: the pixels are the image's size, no more than 16 a byte of the
        // file, and every one finite and non-negative (RGBE holds no other value).
        if (image.width <= 0 || image.height <= 0 ||
            image.pixels.size() != static_cast<size_t>(image.width) * image.height ||
            image.pixels.size() > 16 * size)
            __builtin_trap();
        for (const Color& c : image.pixels)
            if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) ||
                min_component(c) < 0.0f)
                __builtin_trap();
    } catch (const std::runtime_error&) {
    }
    return 0;
}
