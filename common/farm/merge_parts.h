// Joining the parts of a render split across jobs (docs/farm.md): parts that belong together,
// hold no sample twice, and together cover samples 0 .. N-1 of every pixel, summed into the
// films of the whole image. The films' sums are exact and order-free (film.h), so the merged
// image is bit for bit the image of one run with --spp N.
#pragma once

#include <string>
#include <vector>

#include "farm/part.h"

namespace lessons {

// Throws InputError naming a part and the field where it differs from the first part (lesson,
// scene files, options, seed, image size, films): parts of different renders do not merge.
void check_parts_agree(const std::vector<PartFile>& parts);
// Throws InputError naming two parts that hold the same samples of the same pixels.
void check_parts_disjoint(const std::vector<PartFile>& parts);

// What the parts cover, against the samples 0 .. target-1 of every pixel.
struct Coverage {
    int target = 0;                    // N
    int spp_min = 0, spp_max = 0;      // samples the pixels hold, fewest and most
    double fraction = 0.0;             // of the target's samples, over the image
    std::vector<std::string> missing;  // "samples A:B of pixels X0:X1,Y0:Y1", none if complete
    std::vector<std::string> beyond;   // parts holding samples at or past the target
    bool complete() const { return missing.empty() && beyond.empty(); }
};
// target 0: the largest end any part was asked for (an interrupted part's planned end).
Coverage part_coverage(const std::vector<PartFile>& parts, int target = 0);

// Whether the parts were made by one build on one kind of CPU (the bit-for-bit guarantee
// needs both; other parts still merge into a correct render): a line saying what differs, or "".
std::string mixed_builds(const std::vector<PartFile>& parts);

// The whole image's films: the sum of every part's films, each in its place. Parts read with
// their pixels are added as they are; those read without (headers only, as a merge checks them
// first) are read again, one at a time, so that memory holds one part besides the whole image.
// Throws InputError for a part that changed since its header was read.
std::vector<Film> merge_parts(const std::vector<PartFile>& parts);

}  // namespace lessons
