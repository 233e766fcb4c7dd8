// The film: per-pixel accumulation of radiance samples into a mean and its variance.
//
// A pixel's value is the Monte Carlo estimate (1/N) sum_k L_k of the radiance through it. Sums
// are kept in double so that very long renders (references) do not lose small samples. Samples
// that are NaN or infinite are never averaged in: they are counted, reported, and left out.
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "geometry/math.h"
#include "io/image.h"

namespace lessons {

class Film {
public:
    Film() = default;
    Film(int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }

    // Adds one radiance sample to pixel `index` (row-major). Called by one thread per pixel.
    void add_sample(size_t index, const Color& radiance);

    // Counts a NaN or infinite sample for pixel `index` without adding anything (render_splatting
    // leaves such splats out; they are reported like any other invalid sample).
    void reject_sample(size_t index, const Color& radiance);

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
    // The factor the clamp scales a sample by (1 when it is not clamped): the render loop scales
    // a sample's layers by it too, so that clamped layers still add up to the clamped image.
    float clamp_scale(const Color& radiance) const {
        const float lum = luminance(radiance);
        return clamp_ > 0.0f && lum > clamp_ && std::isfinite(lum) ? clamp_ / lum : 1.0f;
    }
    uint64_t clamped_samples() const;
    int inf_pixels() const;  // pixels that received at least one infinite sample

private:
    struct Pixel {
        glm::dvec3 sum{0.0};
        glm::dvec3 sum_squares{0.0};
        uint32_t valid = 0;
        uint32_t nan = 0;
        uint32_t inf = 0;
        uint32_t clamped = 0;
        float max_luminance = 0.0f;  // of a single sample
        double sum_luminance = 0.0;
    };
    float clamp_ = 0.0f;
    int width_ = 0, height_ = 0;
    std::vector<Pixel> pixels_;
};

}  // namespace lessons
