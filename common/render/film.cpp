// Per-pixel accumulation of radiance samples (see film.h).
#include "render/film.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lessons {

namespace {

constexpr double kToFixed = 0x1p48;     // 2^kFixedBits
constexpr double kFromFixed = 0x1p-48;  // its inverse
constexpr float kLargestSample = 0x1p54f;
static_assert(Film::kFixedBits == 48);

bool too_large(const Color& c) {
    return std::fabs(c.x) >= kLargestSample || std::fabs(c.y) >= kLargestSample ||
           std::fabs(c.z) >= kLargestSample;
}

// A channel as an integer count of 2^-48: the product is exact in double (a float times a power
// of two), and an integer whenever |v| >= 2^-25; below, it is rounded to the nearest integer.
__int128 to_fixed(float v) {
    return static_cast<__int128>(std::nearbyint(static_cast<double>(v) * kToFixed));
}

}  // namespace

glm::dvec3 FilmPixel::total() const {
    return glm::dvec3(static_cast<double>(sum[0]), static_cast<double>(sum[1]),
                      static_cast<double>(sum[2])) *
           kFromFixed;
}

void FilmPixel::add(const FilmPixel& o) {
    for (int c = 0; c < 3; ++c) sum[c] += o.sum[c];
    sum_squares += o.sum_squares;
    valid += o.valid;
    nan += o.nan;
    inf += o.inf;
    clamped += o.clamped;
    max_luminance = std::max(max_luminance, o.max_luminance);
}

Film::Film(int width, int height)
    : width_(width), height_(height), pixels_(static_cast<size_t>(width) * height) {}

void Film::add_sample(size_t index, const Color& radiance) {
    FilmPixel& p = pixels_[index];
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
    const bool clamped = clamp_ > 0.0f && lum > clamp_;
    if (clamped) {
        value *= clamp_ / lum;
        lum = clamp_;
    }
    if (too_large(value)) {  // (after the clamp, which may bring it into range)
        ++p.inf;
        return;
    }
    p.clamped += clamped;
    p.max_luminance = std::max(p.max_luminance, lum);
    p.sum[0] += to_fixed(value.x);
    p.sum[1] += to_fixed(value.y);
    p.sum[2] += to_fixed(value.z);
    const glm::dvec3 L(value);
    p.sum_squares += L * L;
    ++p.valid;
}

void Film::reject_sample(size_t index, const Color& radiance) {
    FilmPixel& p = pixels_[index];
    if (std::isnan(radiance.x) || std::isnan(radiance.y) || std::isnan(radiance.z))
        ++p.nan;
    else
        ++p.inf;
}

void Film::add(const Film& other) {
    if (other.width_ != width_ || other.height_ != height_)
        throw std::logic_error("Film::add: films of different sizes");
    for (size_t i = 0; i < pixels_.size(); ++i) pixels_[i].add(other.pixels_[i]);
}

void Film::add_window(const Film& part, int x0, int y0) {
    if (x0 < 0 || y0 < 0 || x0 + part.width_ > width_ || y0 + part.height_ > height_)
        throw std::logic_error("Film::add_window: the part lies outside the film");
    for (int y = 0; y < part.height_; ++y)
        for (int x = 0; x < part.width_; ++x)
            pixels_[static_cast<size_t>(y0 + y) * width_ + (x0 + x)].add(
                part.pixels_[static_cast<size_t>(y) * part.width_ + x]);
}

void Film::clear() { std::fill(pixels_.begin(), pixels_.end(), FilmPixel{}); }

Image Film::mean() const {
    Image image(width_, height_);
    for (size_t i = 0; i < pixels_.size(); ++i) {
        const FilmPixel& p = pixels_[i];
        if (p.valid > 0) image.pixels[i] = Color(p.total() / static_cast<double>(p.valid));
    }
    return image;
}

Image Film::variance_of_mean() const {
    Image image(width_, height_);
    for (size_t i = 0; i < pixels_.size(); ++i) {
        const FilmPixel& p = pixels_[i];
        if (p.valid < 2) continue;
        const double n = p.valid;
        const glm::dvec3 mean = p.total() / n;
        // Unbiased sample variance s^2 = (sum L^2 - n mean^2) / (n - 1); of the mean: s^2 / n.
        const glm::dvec3 s2 = glm::max(p.sum_squares - n * mean * mean, glm::dvec3(0.0)) / (n - 1);
        image.pixels[i] = Color(s2 / n);
    }
    return image;
}

int Film::firefly_pixels() const {
    int n = 0;
    for (const FilmPixel& p : pixels_) {
        // The luminance of the sum is the sum of the (clamped) samples' luminances.
        const glm::dvec3 t = p.total();
        const double sum_luminance = 0.2126 * t.x + 0.7152 * t.y + 0.0722 * t.z;
        n += p.valid >= 8 && sum_luminance > 0.0 && p.max_luminance > 0.5 * sum_luminance;
    }
    return n;
}

uint64_t Film::clamped_samples() const {
    uint64_t n = 0;
    for (const FilmPixel& p : pixels_) n += p.clamped;
    return n;
}

uint64_t Film::nan_samples() const {
    uint64_t n = 0;
    for (const FilmPixel& p : pixels_) n += p.nan;
    return n;
}
uint64_t Film::inf_samples() const {
    uint64_t n = 0;
    for (const FilmPixel& p : pixels_) n += p.inf;
    return n;
}
int Film::nan_pixels() const {
    int n = 0;
    for (const FilmPixel& p : pixels_) n += p.nan > 0;
    return n;
}
int Film::inf_pixels() const {
    int n = 0;
    for (const FilmPixel& p : pixels_) n += p.inf > 0;
    return n;
}

}  // namespace lessons
