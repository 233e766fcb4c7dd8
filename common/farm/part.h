// A part of a render split across jobs (docs/farm.md): a crop of the image and a range of
// sample indices, saved as an EXR that a merge joins back, exactly, into the whole render.
//
// The EXR shows the part's mean image (R, G, B) to any viewer, and carries what a merge needs:
// in its header, as string attributes "lessons.*", where the part belongs (lesson, scene and
// the hash of its files, image size, crop, samples, seed, the options that change the image);
// and in channels of 32-bit unsigned integers, every film's exact per-pixel state (FilmPixel):
// the 128-bit sums as four words per colour, the sums of squares as the two words of a double,
// and the counts. A checksum over all of it refuses a damaged or truncated file.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "farm/part_header.h"
#include "io/input_file.h"
#include "render/film.h"
#include "scene/scene.h"

namespace lessons {

struct PartFile {
    std::string path;
    PartHeader header;
    std::vector<Film> films;  // header.films.size() films of the crop's size
};

// Writes a part (atomically). Throws std::runtime_error on failure.
void write_part(const std::string& path, const PartHeader& header, std::span<const Film> films);
// Reads a part, or only its header (films left empty, the checksum not checked). Throws
// InputError naming the file and the field for anything wrong with it.
PartFile read_part(const std::string& path, bool with_pixels = true);

// The hash of the files a scene was made of (Scene::input_files, read again under `limits`), as
// 16 hex digits. Throws InputError if one cannot be read.
std::string scene_files_hash(const Scene& scene, const InputLimits& limits);
// What made a part: the hash of this executable's file, and this CPU's model name. Parts made
// by other builds or CPUs still merge, but their bits may differ (docs/farm.md).
std::string this_build();
std::string this_cpu();

}  // namespace lessons
