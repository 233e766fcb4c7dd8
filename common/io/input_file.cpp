// Defensive reading of input files (see input_file.h).
#include "io/input_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>

#include <fstream>
#include <sstream>

#include "io/input_error.h"

namespace lessons {

namespace {
// "a scene file", "an OBJ file", "an MTL file" (an acronym's letters are read by name).
std::string a(const std::string& what) {
    const bool acronym = what.size() > 1 && std::isupper(static_cast<unsigned char>(what[1]));
    const std::string vowel_sounds = acronym ? "AEFHILMNORSX" : "AEIOUaeiou";
    return (what.find_first_of(vowel_sounds) == 0 ? "an " : "a ") + what;
}
}  // namespace

uint64_t check_input_file(const std::string& path, const std::string& what, uint64_t max_bytes,
                          const std::string& flag) {
    struct stat st {};
    // stat, not lstat: a symbolic link to a regular file is fine, one to a device is not.
    if (stat(path.c_str(), &st) != 0) throw InputError(path, 0, "", what + " not found");
    if (S_ISDIR(st.st_mode)) throw InputError(path, 0, "", "is a directory, not " + a(what));
    if (!S_ISREG(st.st_mode))
        throw InputError(path, 0, "",
                         "is not a regular file (a device, a FIFO or a socket), not " + a(what));
    const uint64_t size = static_cast<uint64_t>(st.st_size);
    if (size > max_bytes) {
        throw InputError(path, 0, "",
                         "is " + std::to_string(size) + " bytes, more than the " +
                             std::to_string(max_bytes) + " bytes allowed for " + a(what) +
                             " (raise " + flag + ")");
    }
    return size;
}

std::string read_input_file(const std::string& path, const std::string& what, uint64_t max_bytes,
                            const std::string& flag) {
    const uint64_t size = check_input_file(path, what, max_bytes, flag);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, 0, "", "cannot open the " + what + " (permissions?)");
    std::string bytes;
    bytes.resize(size);
    in.read(bytes.data(), static_cast<std::streamsize>(size));
    // A file that changed size since stat: keep what was read, never more than the cap.
    bytes.resize(static_cast<size_t>(in.gcount()));
    return bytes;
}

void check_fits_in_memory(double bytes, const std::string& what, const std::string& where,
                          const std::string& field) {
    const double physical =
        static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
    if (physical > 0 && bytes > 0.5 * physical) {
        char msg[240];
        std::snprintf(msg, sizeof msg, "%s %.1f GiB, more than half of this machine's %.1f GiB",
                      what.c_str(), bytes / (1 << 30), physical / (1 << 30));
        throw InputError(where, 0, field, msg);
    }
}

uint64_t file_hash(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return 0;
    uint64_t h = kFnvStart;
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0)
        h = fnv1a(h, buffer, static_cast<size_t>(in.gcount()));
    return h;
}

}  // namespace lessons
