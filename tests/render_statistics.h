// Statistics of whole renders, for the lesson tests: image means with their standard errors, and
// the per-pixel z-test of two renders (Mitsuba 3's test_renders), from the variance images.
#pragma once

#include <cmath>
#include <utility>

#include "driver/app.h"
#include "statistics.h"

namespace lessons::test {

// The red channel's image mean and the variance of that mean, from a render's per-pixel
// variances of the mean (pixels are independent).
inline std::pair<double, double> image_mean(const Image& image, const Image& variance) {
    double mean = 0.0, var = 0.0;
    const double n = static_cast<double>(image.pixels.size());
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        mean += image.pixels[i].x / n;
        var += variance.pixels[i].x / (n * n);
    }
    return {mean, var};
}

// How many channels of two renders of one scene agree at 0.01, Sidak-corrected over all of
// them, and how many were tested. A channel with no variance in either must be equal.
inline std::pair<int, int> channels_that_agree(const RenderResult& a, const RenderResult& b) {
    const int tested = static_cast<int>(a.image.pixels.size()) * 3;
    const double z_max = z_quantile(sidak(0.01, tested));
    int passed = 0;
    for (size_t i = 0; i < a.image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const double d = a.image.pixels[i][c] - b.image.pixels[i][c];
            const double v = a.variance.pixels[i][c] + b.variance.pixels[i][c];
            passed += v > 0.0 ? std::fabs(d) / std::sqrt(v) < z_max : std::fabs(d) < 1e-6;
        }
    }
    return {passed, tested};
}

}  // namespace lessons::test
