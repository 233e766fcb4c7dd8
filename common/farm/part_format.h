// What the files of a part share (private to common/farm/): the merge channels, one per field
// of FilmPixel, as 32-bit words (part_channels.cpp), and the header as "lessons.*" attributes
// (part_header.cpp), which part.cpp writes to and reads from an EXR.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "farm/part_header.h"
#include "render/film.h"

namespace lessons::part_format {

// The channels of one film's FilmPixel, each a 32-bit word per pixel.
inline constexpr const char* kFields[] = {"sumR0", "sumR1", "sumR2", "sumR3",   "sumG0", "sumG1",
                                          "sumG2", "sumG3", "sumB0", "sumB1",   "sumB2", "sumB3",
                                          "sqR0",  "sqR1",  "sqG0",  "sqG1",    "sqB0",  "sqB1",
                                          "valid", "nan",   "inf",   "clamped", "maxlum"};
inline constexpr int kFieldCount = sizeof kFields / sizeof kFields[0];

// Every film's FilmPixels as 32-bit words, one channel per field, by channel name
// ("image.sumR0", "bounce1.valid").
using ChannelWords = std::map<std::string, std::vector<uint32_t>>;

// The films' pixels as channels, named after h.films. (part_channels.cpp)
ChannelWords merge_channels(const PartHeader& h, std::span<const Film> films);
// The films back from their channels; each pixel checked against what a run can hold, so that
// sums never overflow, else an InputError naming `path`. (part_channels.cpp)
std::vector<Film> films_from_words(const std::string& path, const PartHeader& h,
                                   const ChannelWords& words);

// The header as name -> text: what is written as attributes, and what the checksum covers.
// (part_header.cpp)
std::map<std::string, std::string> header_fields(const PartHeader& h);
// The header from the "lessons.*" attributes, each checked; an InputError names `path` and the
// field. (part_header.cpp)
PartHeader header_from_fields(const std::string& path,
                              const std::map<std::string, std::string>& fields);

}  // namespace lessons::part_format
