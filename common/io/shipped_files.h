// The files the suite ships beside its programs (the scenes, the studio's page), found from the
// program's own location, so that an installed suite needs no source tree and no script: a
// program in PREFIX/bin reads PREFIX/share/illumination-lessons/ (docs/architecture.md,
// "Installed"). The build tree has the same layout: build/bin/ beside build/share/
// illumination-lessons/, whose folders are links to the source tree's.
#pragma once

#include <filesystem>
#include <string>

namespace lessons {

// The folder of the running program (read from /proc/self/exe, links resolved): PREFIX/bin
// installed, build/bin built; empty if the program's own path cannot be read.
std::filesystem::path program_dir();

// PREFIX/share/illumination-lessons for the running program PREFIX/bin/NAME (read from
// /proc/self/exe, links resolved), whether or not it exists; empty if the program's own path
// cannot be read.
std::filesystem::path shipped_files_dir();

// The scene file --scene NAME means. NAME itself when it exists (relative to the current
// folder, or absolute), or when it is written as a path (absolute, or with a . or .. in it):
// such a path is never looked up elsewhere. Otherwise the first file among NAME.toml here (NAME
// without an extension), SHIPPED/scenes/NAME, SHIPPED/scenes/NAME.toml (again without an
// extension) and SHIPPED/NAME (NAME starting with scenes/), SHIPPED being shipped_files_dir():
// "cornell_box", "cornell_box.toml", "hard/cornell_tiny" and "scenes/cornell_box.toml" all name a
// shipped scene. Throws InputError(NAME, "scene file not found (looked for ...)"), naming every
// place it looked, when there is none.
std::string find_scene_file(const std::string& name);

}  // namespace lessons
