// Fuzzing the part reader (docs/farm.md): any file given to build/bin/merge must read as a part
// or give an InputError, never crash. The reader opens a file (OpenEXR's two libraries, the
// header check's and the decoder's), so each input is written to this process's scratch file first.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "farm/part.h"
#include "io/input_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace lessons;
    static const std::string path = (std::filesystem::temp_directory_path() /
                                     ("lessons_fuzz_" + std::to_string(getpid()) + ".exr"))
                                        .string();
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
        const PartFile part = read_part(path);
        // The reader's promises: the films are the crop's, the crop lies in the image.
        const PartHeader& h = part.header;
        if (part.films.size() != h.films.size() || h.x1 > h.image_width || h.y1 > h.image_height)
            __builtin_trap();
        for (const Film& f : part.films)
            if (f.width() != h.width() || f.height() != h.height()) __builtin_trap();
    } catch (const InputError&) {
    }
    return 0;
}
