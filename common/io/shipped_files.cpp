// The files the suite ships beside its programs (see shipped_files.h).
#include "io/shipped_files.h"

#include <vector>

#include "io/input_error.h"

namespace lessons {

namespace fs = std::filesystem;

fs::path program_dir() {
    std::error_code ec;
    const fs::path program = fs::read_symlink("/proc/self/exe", ec);
    if (ec || program.empty()) return {};
    return program.parent_path();
}

fs::path shipped_files_dir() {
    // LESSONS_BIN_TO_SHIPPED is the install's relative path from bin/ to
    // share/illumination-lessons (the top-level CMakeLists.txt, from GNUInstallDirs).
    const fs::path bin = program_dir();
    if (bin.empty()) return {};
    return (bin / LESSONS_BIN_TO_SHIPPED).lexically_normal();
}

namespace {

// Written as a path to a file rather than as a name: absolute, or starting with ./ or ../, or
// climbing out of the folder it names (a shipped scene is never found through "..").
bool is_explicit_path(const fs::path& path) {
    if (path.is_absolute()) return true;
    for (const fs::path& part : path)
        if (part == "." || part == "..") return true;
    return false;
}

bool exists_here(const fs::path& path) {
    std::error_code ec;
    return fs::exists(path, ec);
}

bool is_file(const fs::path& path) {
    std::error_code ec;
    return fs::is_regular_file(path, ec);
}

}  // namespace

std::string find_scene_file(const std::string& name) {
    const fs::path path(name);
    // What exists here keeps today's meaning, and today's errors (a folder, a device).
    if (name.empty() || exists_here(path) || is_explicit_path(path)) return name;

    // Here first, then the shipped scenes.
    std::vector<fs::path> candidates;
    if (!path.has_extension()) candidates.push_back(name + ".toml");
    const fs::path shipped = shipped_files_dir();
    if (!shipped.empty()) {
        candidates.push_back(shipped / "scenes" / path);
        if (!path.has_extension()) candidates.push_back(shipped / "scenes" / (name + ".toml"));
        if (*path.begin() == "scenes") candidates.push_back(shipped / path);
    }
    for (const fs::path& candidate : candidates)
        if (is_file(candidate)) return candidate.string();

    std::string looked = "./" + name;
    for (const fs::path& candidate : candidates)
        looked += std::string(", ") + (candidate.is_absolute() ? "" : "./") + candidate.string();
    throw InputError(name, 0, "", "scene file not found (looked for " + looked + ")");
}

}  // namespace lessons
