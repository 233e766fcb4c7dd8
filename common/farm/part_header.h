// Where a part of a render belongs (docs/farm.md): the fields of its header, which a merge
// compares between parts before it adds their films. Written and read as "lessons.*" attributes
// by part_header.cpp (farm/part_format.h).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

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

// "A<separator>B" as two integers of at most 18 digits each, no sign, no spaces ("0:8", "32x24");
// false if the text is not that.
bool parse_pair(std::string_view text, char separator, long long& a, long long& b);

// Whether two headers are the same in every field.
bool same_header(const PartHeader& a, const PartHeader& b);

}  // namespace lessons
