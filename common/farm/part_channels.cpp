// A part's merge channels: each film's exact per-pixel state (FilmPixel) as 32-bit words, the
// 128-bit sums as four words per colour, the sums of squares as the two words of a double, and
// the counts; read back, each pixel is checked against the samples the part holds.
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "farm/part_format.h"
#include "io/input_error.h"

namespace lessons::part_format {

namespace {

void to_words(const FilmPixel& p, uint32_t* w) {
    for (int c = 0; c < 3; ++c) {
        const unsigned __int128 s = static_cast<unsigned __int128>(p.sum[c]);
        for (int k = 0; k < 4; ++k) w[4 * c + k] = static_cast<uint32_t>(s >> (32 * k));
    }
    for (int c = 0; c < 3; ++c) {
        uint64_t bits;
        std::memcpy(&bits, &p.sum_squares[c], sizeof bits);
        w[12 + 2 * c] = static_cast<uint32_t>(bits);
        w[13 + 2 * c] = static_cast<uint32_t>(bits >> 32);
    }
    w[18] = p.valid;
    w[19] = p.nan;
    w[20] = p.inf;
    w[21] = p.clamped;
    std::memcpy(&w[22], &p.max_luminance, sizeof(float));
}

FilmPixel from_words(const uint32_t* w) {
    FilmPixel p;
    for (int c = 0; c < 3; ++c) {
        unsigned __int128 s = 0;
        for (int k = 0; k < 4; ++k) s |= static_cast<unsigned __int128>(w[4 * c + k]) << (32 * k);
        p.sum[c] = static_cast<__int128>(s);
    }
    for (int c = 0; c < 3; ++c) {
        const uint64_t bits = w[12 + 2 * c] | (static_cast<uint64_t>(w[13 + 2 * c]) << 32);
        std::memcpy(&p.sum_squares[c], &bits, sizeof bits);
    }
    p.valid = w[18];
    p.nan = w[19];
    p.inf = w[20];
    p.clamped = w[21];
    std::memcpy(&p.max_luminance, &w[22], sizeof(float));
    return p;
}

}  // namespace

ChannelWords merge_channels(const PartHeader& h, std::span<const Film> films) {
    const size_t n = static_cast<size_t>(h.width()) * h.height();
    ChannelWords words;
    for (size_t f = 0; f < films.size(); ++f) {
        std::vector<std::vector<uint32_t>*> field(kFieldCount);
        for (int k = 0; k < kFieldCount; ++k) {
            field[k] = &words[h.films[f] + "." + kFields[k]];
            field[k]->resize(n);
        }
        uint32_t pixel_words[kFieldCount];
        const std::span<const FilmPixel> pixels = films[f].pixels();
        for (size_t i = 0; i < n; ++i) {
            to_words(pixels[i], pixel_words);
            for (int k = 0; k < kFieldCount; ++k) (*field[k])[i] = pixel_words[k];
        }
    }
    return words;
}

std::vector<Film> films_from_words(const std::string& path, const PartHeader& h,
                                   const ChannelWords& words) {
    const size_t n = static_cast<size_t>(h.width()) * h.height();
    const uint32_t samples = static_cast<uint32_t>(h.sample_end - h.sample_begin);
    std::vector<Film> films;
    for (const std::string& film : h.films) {
        Film f(h.width(), h.height());
        std::vector<const uint32_t*> src(kFieldCount);
        for (int k = 0; k < kFieldCount; ++k) src[k] = words.at(film + "." + kFields[k]).data();
        uint32_t pixel_words[kFieldCount];
        const std::span<FilmPixel> pixels = f.pixels();
        for (size_t i = 0; i < n; ++i) {
            for (int k = 0; k < kFieldCount; ++k) pixel_words[k] = src[k][i];
            pixels[i] = from_words(pixel_words);
            // Each valid sample's channel is below 2^54, i.e. 2^102 units of 2^-48.
            const FilmPixel& p = pixels[i];
            const __int128 bound = static_cast<__int128>(p.valid) << 102;
            bool sound = p.valid <= samples;
            for (int c = 0; c < 3; ++c) sound = sound && p.sum[c] <= bound && -p.sum[c] <= bound;
            if (!sound)
                throw InputError(path, 0, film + ".valid",
                                 "pixel " + std::to_string(i) + " holds more than its " +
                                     std::to_string(samples) + " samples can: the part is damaged");
        }
        films.push_back(std::move(f));
    }
    return films;
}

}  // namespace lessons::part_format
