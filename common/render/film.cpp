// Per-pixel accumulation of radiance samples (see film.h).
#include "render/film.h"

#include <algorithm>
#include <cmath>

namespace lessons {

Film::Film(int width, int height)
    : width_(width), height_(height), pixels_(static_cast<size_t>(width) * height) {}

void Film::add_sample(size_t index, const Color& radiance) {
    Pixel& p = pixels_[index];
    if (std::isnan(radiance.x) || std::isnan(radiance.y) || std::isnan(radiance.z)) {
        ++p.nan;
        return;
    }
    if (!is_finite(radiance)) {
        ++p.inf;
        return;
    }
    Color value = radiance;
    float lum = luminance(value);
    if (clamp_ > 0.0f && lum > clamp_) {
        value *= clamp_ / lum;
        lum = clamp_;
        ++p.clamped;
    }
    p.max_luminance = std::max(p.max_luminance, lum);
    p.sum_luminance += lum;
    const glm::dvec3 L(value);
    p.sum += L;
    p.sum_squares += L * L;
    ++p.valid;
}

void Film::reject_sample(size_t index, const Color& radiance) {
    Pixel& p = pixels_[index];
    if (std::isnan(radiance.x) || std::isnan(radiance.y) || std::isnan(radiance.z))
        ++p.nan;
    else
        ++p.inf;
}

Image Film::mean() const {
    Image image(width_, height_);
    for (size_t i = 0; i < pixels_.size(); ++i) {
        const Pixel& p = pixels_[i];
        if (p.valid > 0) image.pixels[i] = Color(p.sum / static_cast<double>(p.valid));
    }
    return image;
}

Image Film::variance_of_mean() const {
    Image image(width_, height_);
    for (size_t i = 0; i < pixels_.size(); ++i) {
        const Pixel& p = pixels_[i];
        if (p.valid < 2) continue;
        const double n = p.valid;
        const glm::dvec3 mean = p.sum / n;
        // Unbiased sample variance s^2 = (sum L^2 - n mean^2) / (n - 1); of the mean: s^2 / n.
        const glm::dvec3 s2 = glm::max(p.sum_squares - n * mean * mean, glm::dvec3(0.0)) / (n - 1);
        image.pixels[i] = Color(s2 / n);
    }
    return image;
}

int Film::firefly_pixels() const {
    int n = 0;
    for (const Pixel& p : pixels_)
        n += p.valid >= 8 && p.sum_luminance > 0.0 && p.max_luminance > 0.5 * p.sum_luminance;
    return n;
}

uint64_t Film::clamped_samples() const {
    uint64_t n = 0;
    for (const Pixel& p : pixels_) n += p.clamped;
    return n;
}

uint64_t Film::nan_samples() const {
    uint64_t n = 0;
    for (const Pixel& p : pixels_) n += p.nan;
    return n;
}
uint64_t Film::inf_samples() const {
    uint64_t n = 0;
    for (const Pixel& p : pixels_) n += p.inf;
    return n;
}
int Film::nan_pixels() const {
    int n = 0;
    for (const Pixel& p : pixels_) n += p.nan > 0;
    return n;
}
int Film::inf_pixels() const {
    int n = 0;
    for (const Pixel& p : pixels_) n += p.inf > 0;
    return n;
}

}  // namespace lessons
