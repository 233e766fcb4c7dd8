// The film: per-pixel accumulation of radiance samples into a mean and its variance.
//
// A pixel's value is the Monte Carlo estimate (1/N) sum_k L_k of the radiance through it. The
// sums of the samples are exact and do not depend on the order they are added in: each channel
// of a sample is counted as an integer number of 2^-48 (exact for every value of 2^-25 or more,
// rounded to the nearest 2^-48 below that) and summed in a 128-bit integer. So a film made by
// adding up the films of any split of the samples (passes, parts rendered on other machines,
// crops) holds the very same sums, and the mean it gives is the same bit for bit (docs/farm.md).
// The sums of squares, for the variance, are kept in double: a split changes their last bits.
// Samples that are NaN or infinite are never averaged in: they are counted, reported, and left
// out; so is a sample with a channel of 2^54 (about 1.8e16) or more, counted as infinite (a sum
// of up to 2^24 of them could not be kept exactly).
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "geometry/math.h"
#include "io/image.h"

namespace lessons {

// What a film holds for one pixel.
struct FilmPixel {
    __int128 sum[3] = {0, 0, 0};  // each channel's sum, in units of 2^-48 (Film::kFixedBits)
    glm::dvec3 sum_squares{0.0};
    uint32_t valid = 0;  // samples averaged in
    uint32_t nan = 0;
    uint32_t inf = 0;  // infinite, or too large to sum exactly
    uint32_t clamped = 0;
    float max_luminance = 0.0f;  // of a single sample

    // The sum of the valid samples, as doubles.
    glm::dvec3 total() const;
    // Adds another pixel's samples (a disjoint set of samples of the same pixel).
    void add(const FilmPixel& other);
};

class Film {
public:
    static constexpr int kFixedBits = 48;

    Film() = default;
    Film(int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }

    // Adds one radiance sample to pixel `index` (row-major). Called by one thread per pixel.
    void add_sample(size_t index, const Color& radiance);

    // Counts a NaN or infinite sample for pixel `index` without adding anything (the pass-by-pass
    // render loop leaves such splats out; they are reported like any other invalid sample).
    void reject_sample(size_t index, const Color& radiance);

    // Adds the samples of `other`, a film of the same pixels holding other samples of them.
    void add(const Film& other);
    // Adds `part`, a film of the pixels [x0, x0 + part.width()) x [y0, y0 + part.height()).
    void add_window(const Film& part, int x0, int y0);
    // Forgets every sample (keeps the size and the clamp).
    void clear();

    // What the film holds, pixel by pixel (row-major): for saving and loading parts.
    std::span<const FilmPixel> pixels() const { return pixels_; }
    std::span<FilmPixel> pixels() { return pixels_; }

    // The per-pixel mean of the valid samples.
    Image mean() const;
    // The per-pixel sample variance of the mean, s^2 / N (zero with fewer than two samples).
    Image variance_of_mean() const;

    uint64_t nan_samples() const;
    uint64_t inf_samples() const;
    int nan_pixels() const;  // pixels that received at least one NaN sample
    // Fireflies: pixels with at least 8 samples where a single sample carries more than half
    // of the pixel's total luminance (the rare, very bright path the eye sees as a speck).
    int firefly_pixels() const;
    // Optional, biased: scale down every sample whose luminance exceeds `max_luminance`.
    void set_clamp(float max_luminance) { clamp_ = max_luminance; }
    float clamp() const { return clamp_; }
    // The factor the clamp scales a sample by (1 when it is not clamped): the render loop scales
    // a sample's layers by it too, so that clamped layers still add up to the clamped image.
    float clamp_scale(const Color& radiance) const {
        const float lum = luminance(radiance);
        return clamp_ > 0.0f && lum > clamp_ && std::isfinite(lum) ? clamp_ / lum : 1.0f;
    }
    uint64_t clamped_samples() const;
    int inf_pixels() const;  // pixels that received at least one infinite sample

private:
    float clamp_ = 0.0f;
    int width_ = 0, height_ = 0;
    std::vector<FilmPixel> pixels_;
};

}  // namespace lessons
