// An environment map: the radiance arriving from infinitely far away in every direction, as a
// latitude-longitude image of linear radiance (docs/scene-format.md, "[background]"), and its
// importance sampling for lessons 3 to 5.
//
// Directions: theta from the +y axis (the zenith, the image's top row) down to -y (its bottom
// row), phi about +y from +x towards +z (the image's left edge is +x, a quarter across is +z):
//   d = (sin(theta) cos(phi), cos(theta), sin(theta) sin(phi)),  u = phi / 2 pi,  v = theta / pi,
// and `rotate` turns the map about +y by that many degrees as a shape's rotation about +y turns
// the shape (the right-hand rule: +z towards +x): phi of the image = phi + rotate.
// The radiance is piecewise constant: each texel's value over its patch of the sphere.
//
// Sampling: a texel with probability proportional to its luminance times sin(theta) at its
// row's centre (the solid angle its patch covers, up to a constant), then a point uniform in
// (u, v) within it (a row by its weight, then a column of it: no texel of positive weight is
// chosen less often than 2^-48, sampling/discrete.h). A patch of du dv covers 2 pi^2 sin(theta) du
// dv steradians, so the density per unit solid angle is  p = P(texel) W H / (2 pi^2 sin(theta)).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "geometry/math.h"

namespace lessons {

// Real maps' flaws: maps saved by Blender and other tools hold a few slightly negative texels
// (down to about -0.004), left by lossy compression and by conversion between colour spaces.
// Channels from -kNegativeTexelTolerance up to 0 (in the file's values, before `strength`) are
// such flaws: clamp_negative_texels sets them to 0. Clamping them brightens the map's mean
// radiance by at most the tolerance, 0.01 W/(sr m^2), even if every texel were clamped
// (docs/scene-format.md).
inline constexpr float kNegativeTexelTolerance = 0.01f;
struct ClampedTexels {
    size_t texels = 0;      // texels with a channel set to 0
    float minimum = 0.0f;   // the most negative channel among them (0 if none)
};
// texels: width wide, top row first. Sets every channel in [-kNegativeTexelTolerance, 0) to 0.
// Throws std::invalid_argument naming the first texel (column, row) that is not finite or has a
// channel below -kNegativeTexelTolerance (the texels are then unchanged or partly clamped).
ClampedTexels clamp_negative_texels(std::vector<Color>& texels, int width);

class EnvironmentMap {
public:
    // texels: width x height, top row first, linear radiance (W / (sr m^2)) before `strength`.
    // Throws std::invalid_argument if a texel is negative or not finite, or all are black.
    EnvironmentMap(int width, int height, std::vector<Color> texels, float rotate_degrees,
                   float strength);

    Color radiance(const Vec3& dir) const { return texels_[texel_of(dir)]; }
    struct Sample {
        Vec3 dir;
        Color radiance;
        float pdf;  // per steradian
    };
    std::optional<Sample> sample(const Vec2& u) const;
    float pdf(const Vec3& dir) const;

    // The mean radiance over the sphere (what a constant sky of the same power would have).
    Color mean() const { return mean_; }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    size_t texel_of(const Vec3& dir) const;
    Vec3 direction(float u, float v) const;

    int width_, height_;
    float rotate_;  // radians
    std::vector<Color> texels_;
    // Row j's cumulative table of its columns (sampling/discrete.h).
    std::span<float> columns(int j) {
        return {column_cdf_.data() + static_cast<size_t>(j) * width_, static_cast<size_t>(width_)};
    }
    std::span<const float> columns(int j) const {
        return {column_cdf_.data() + static_cast<size_t>(j) * width_, static_cast<size_t>(width_)};
    }

    std::vector<float> row_cdf_;      // height_ entries, the last 1 (sampling/discrete.h)
    std::vector<float> column_cdf_;   // width_ per row, each row's last 1
    std::vector<float> probability_;  // of each texel
    Color mean_{0.0f};
};

}  // namespace lessons
