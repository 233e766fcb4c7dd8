// What made a part, as its header records it: the hash of the files the scene was made of, this
// executable's build and this CPU's model.
#include <cstdio>
#include <fstream>
#include <string>

#include "farm/part.h"
#include "io/input_error.h"
#include "io/input_file.h"

namespace lessons {

std::string scene_files_hash(const Scene& scene, const InputLimits& limits) {
    uint64_t h = kFnvStart;
    for (const std::string& f : scene.input_files) {
        check_input_file(f, "file the scene names", limits.file_bytes(), "--max-file-mb");
        std::ifstream in(f, std::ios::binary);
        if (!in) throw InputError(f, 0, "", "cannot be read (permissions?)");
        const uint64_t fh = file_hash(f);
        h = fnv1a(h, &fh, sizeof fh);
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

std::string this_build() {
    const uint64_t h = file_hash("/proc/self/exe");
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

std::string this_cpu() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) {
            const size_t colon = line.find(':');
            return colon == std::string::npos ? line
                                              : line.substr(line.find_first_not_of(" ", colon + 1));
        }
    return "unknown";
}

}  // namespace lessons
