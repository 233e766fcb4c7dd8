// Environment maps (see environment.h).
#include "scene/environment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "sampling/discrete.h"

namespace lessons {

namespace {
constexpr double kPiD = 3.14159265358979323846;
}  // namespace

ClampedTexels clamp_negative_texels(std::vector<Color>& texels, int width) {
    ClampedTexels clamped;
    for (size_t k = 0; k < texels.size(); ++k) {
        Color& c = texels[k];
        const auto fail = [&](const char* what) {
            char msg[320];
            std::snprintf(msg, sizeof msg, "texel (%d, %d) is (%g, %g, %g): %s",
                          static_cast<int>(k % width), static_cast<int>(k / width), c.x, c.y, c.z,
                          what);
            throw std::invalid_argument(msg);
        };
        if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)))
            fail("not finite (radiance is finite and >= 0)");
        const float lowest = min_component(c);
        if (lowest >= 0.0f) continue;
        if (lowest < -kNegativeTexelTolerance)
            fail("negative beyond the tolerance of -0.01 for flaws of compression and colour "
                 "conversion (radiance is finite and >= 0)");
        ++clamped.texels;
        clamped.minimum = std::min(clamped.minimum, lowest);
        c = glm::max(c, Color(0.0f));
    }
    return clamped;
}

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<Color> texels,
                               float rotate_degrees, float strength)
    : width_(width),
      height_(height),
      rotate_(static_cast<float>(rotate_degrees * kPiD / 180.0)),
      texels_(std::move(texels)) {
    if (width_ < 1 || height_ < 1 || texels_.size() != static_cast<size_t>(width_) * height_)
        throw std::invalid_argument("the map has no pixels");
    std::vector<double> weight(texels_.size());
    glm::dvec3 integral(0.0);
    double total = 0.0;
    for (int j = 0; j < height_; ++j) {
        const double theta0 = kPiD * j / height_, theta1 = kPiD * (j + 1) / height_;
        const double sin_centre = std::sin(0.5 * (theta0 + theta1));
        const double solid_angle = 2.0 * kPiD / width_ * (std::cos(theta0) - std::cos(theta1));
        for (int i = 0; i < width_; ++i) {
            Color& c = texels_[static_cast<size_t>(j) * width_ + i];
            c *= strength;  // checked after scaling: a huge texel times the strength may overflow
            if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) ||
                min_component(c) < 0.0f)
                throw std::invalid_argument("texel (" + std::to_string(i) + ", " +
                                            std::to_string(j) +
                                            ") times the strength is negative or not finite: "
                                            "radiance is finite and >= 0");
            weight[static_cast<size_t>(j) * width_ + i] = luminance(c) * sin_centre;
            total += weight[static_cast<size_t>(j) * width_ + i];
            integral += glm::dvec3(c) * solid_angle;
        }
    }
    if (!std::isfinite(total))
        throw std::invalid_argument("the map's total power is not finite (texels too bright)");
    if (!(total > 0.0))
        throw std::invalid_argument(
            "the map sends no light (every texel is black): its total "
            "power is zero");
    mean_ = Color(integral / (4.0 * kPiD));
    // A row by its weight, then a column of it (sampling/discrete.h: every texel of positive
    // weight keeps a positive probability, however bright a sun beside it).
    probability_.resize(texels_.size());
    column_cdf_.resize(texels_.size());
    std::vector<double> rows(height_);
    for (int j = 0; j < height_; ++j) {
        const std::span<const double> row(weight.data() + static_cast<size_t>(j) * width_,
                                          static_cast<size_t>(width_));
        for (double w : row) rows[j] += w;
        build_choice_cdf(row, columns(j));
    }
    row_cdf_ = choice_cdf(rows);
    // Each texel's probability as the sampler realises it: from the same CDFs.
    for (int j = 0; j < height_; ++j) {
        const float row = entry_probability(row_cdf_, j);
        for (int i = 0; i < width_; ++i)
            probability_[static_cast<size_t>(j) * width_ + i] =
                row * entry_probability(columns(j), i);
    }
}

Vec3 EnvironmentMap::direction(float u, float v) const {
    const float theta = static_cast<float>(kPiD) * v;
    const float phi = 2.0f * static_cast<float>(kPiD) * u - rotate_;
    const float s = std::sin(theta);
    return {s * std::cos(phi), std::cos(theta), s * std::sin(phi)};
}

size_t EnvironmentMap::texel_of(const Vec3& d) const {
    // (A NaN direction, which no lesson should make, reads texel 0 rather than undefined.)
    if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z))) return 0;
    const double theta = std::acos(std::clamp(static_cast<double>(d.y), -1.0, 1.0));
    double phi = std::atan2(static_cast<double>(d.z), static_cast<double>(d.x)) + rotate_;
    phi -= 2.0 * kPiD * std::floor(phi / (2.0 * kPiD));
    const int i = std::min(width_ - 1, static_cast<int>(phi / (2.0 * kPiD) * width_));
    const int j = std::min(height_ - 1, static_cast<int>(theta / kPiD * height_));
    return static_cast<size_t>(std::max(j, 0)) * width_ + static_cast<size_t>(std::max(i, 0));
}

std::optional<EnvironmentMap::Sample> EnvironmentMap::sample(const Vec2& u) const {
    float du = 0.0f, dv = 0.0f;
    const size_t j = choose_entry(row_cdf_, u.y, &dv);
    const size_t i = choose_entry(columns(static_cast<int>(j)), u.x, &du);
    const Vec3 dir =
        direction((static_cast<float>(i) + du) / width_, (static_cast<float>(j) + dv) / height_);
    // The density and radiance of the direction as made (rounding may put it across a texel's
    // edge): the same numbers pdf() and radiance() give it, as MIS needs.
    const float p = pdf(dir);
    if (!(p > 0.0f)) return std::nullopt;
    return Sample{dir, radiance(dir), p};
}

float EnvironmentMap::pdf(const Vec3& dir) const {
    // sin(theta) from the horizontal components: accurate near the poles, where 1 - y^2 is not.
    const float sin_theta = std::sqrt(dir.x * dir.x + dir.z * dir.z);
    if (!(sin_theta > 0.0f)) return 0.0f;
    return probability_[texel_of(dir)] * width_ * height_ /
           (2.0f * static_cast<float>(kPiD * kPiD) * sin_theta);
}

}  // namespace lessons
