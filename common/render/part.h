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

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "io/input_file.h"
#include "render/film.h"
#include "scene/scene.h"

namespace lessons {

struct PartHeader {
    std::string lesson;      // e.g. "04_rendering_equation"
    std::string scene;       // the scene file, as the command line named it
    std::string scene_hash;  // 16 hex digits: FNV-1a of the scene file and every file it names
    std::string options;     // the options that change the image, one "--flag=value" per line
    uint64_t seed = 0;
    int image_width = 0, image_height = 0;
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;    // the crop: pixels [x0, x1) x [y0, y1)
    int sample_begin = 0, sample_end = 0;  // the samples every pixel holds: [begin, end)
    int planned_end = 0;                   // the end the run was asked for
    std::vector<std::string> films;        // "image", then the layers' names
    double seconds = 0.0;                  // rendering time
    uint64_t rays = 0;
    int threads = 0;
    float exposure = 0.0f;  // of the PNG
    std::vector<std::string> notes, bias;
    std::string build, cpu;  // this_build(), this_cpu() of the run that made it

    bool partial() const { return sample_end < planned_end; }  // interrupted
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    // "X0:X1,Y0:Y1" and "A:B", as the command line takes them.
    std::string pixels_text() const;
    std::string samples_text() const;
};

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

// "A<separator>B" as two integers of at most 18 digits each, no sign, no spaces ("0:8", "32x24");
// false if the text is not that.
bool parse_pair(std::string_view text, char separator, long long& a, long long& b);

// Whether two headers are the same in every field.
bool same_header(const PartHeader& a, const PartHeader& b);

}  // namespace lessons
