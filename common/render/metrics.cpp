// Error metrics of an image against a reference (see metrics.h).
#include "render/metrics.h"

#include <cstdio>

#include <algorithm>
#include <cmath>

#include "io/input_error.h"

namespace lessons {

ErrorMetrics compare_images(const Image& image, const Image& reference, const std::string& what) {
    if (image.width != reference.width || image.height != reference.height)
        throw InputError(what, 0, "",
                         "size " + std::to_string(image.width) + "x" +
                             std::to_string(image.height) + " does not match the reference's " +
                             std::to_string(reference.width) + "x" +
                             std::to_string(reference.height));
    double squared = 0.0, relative = 0.0, absolute = 0.0;
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double ref = reference.pixels[i][c];
            const double d = static_cast<double>(image.pixels[i][c]) - ref;
            squared += d * d;
            relative += d * d / (ref * ref + 0.01);
            absolute += std::fabs(d);
        }
    const double n = 3.0 * static_cast<double>(image.pixels.size());
    ErrorMetrics m;
    if (n == 0.0) return m;
    m.mse = squared / n;
    m.rmse = std::sqrt(m.mse);
    m.relmse = relative / n;
    m.mae = absolute / n;
    return m;
}

namespace {

// Viridis (van der Walt and Smith, matplotlib): perceptually uniform and ordered, readable in
// grey and by colour-blind viewers. Sampled at 0, 0.1, ..., 1.
constexpr std::array<std::array<uint8_t, 3>, 11> kViridis = {{{0x44, 0x01, 0x54},
                                                              {0x48, 0x24, 0x75},
                                                              {0x41, 0x44, 0x87},
                                                              {0x35, 0x5F, 0x8D},
                                                              {0x2A, 0x78, 0x8E},
                                                              {0x21, 0x91, 0x8C},
                                                              {0x22, 0xA8, 0x84},
                                                              {0x44, 0xBF, 0x70},
                                                              {0x7A, 0xD1, 0x51},
                                                              {0xBD, 0xDF, 0x26},
                                                              {0xFD, 0xE7, 0x25}}};

}  // namespace

std::array<uint8_t, 3> viridis(float t) {
    t = std::isfinite(t) ? std::clamp(t, 0.0f, 1.0f) : 1.0f;
    const float x = t * 10.0f;
    const int i = std::min(9, static_cast<int>(x));
    const float f = x - i;
    std::array<uint8_t, 3> c;
    for (int k = 0; k < 3; ++k)
        c[k] = static_cast<uint8_t>(std::lround((1 - f) * kViridis[i][k] + f * kViridis[i + 1][k]));
    return c;
}

std::vector<float> pixel_errors(const Image& image, const Image& reference) {
    std::vector<float> error(image.pixels.size());
    for (size_t i = 0; i < error.size() && i < reference.pixels.size(); ++i) {
        const Color d = image.pixels[i] - reference.pixels[i];
        error[i] = std::sqrt(glm::dot(d, d) / 3.0f);
    }
    return error;
}

double error_map_scale(const std::vector<float>& errors) {
    std::vector<float> sorted(errors);
    std::sort(sorted.begin(), sorted.end());
    const double scale =
        sorted.empty() ? 1.0 : sorted[static_cast<size_t>(0.99 * (sorted.size() - 1))];
    return scale > 0.0 ? scale : 1.0;
}

std::vector<std::string> layer_shares(const Image& image, const std::vector<Image>& layers,
                                      const std::vector<std::string>& names) {
    std::vector<std::string> shares;
    double total_luminance = 0.0;
    for (const Color& c : image.pixels) total_luminance += luminance(c);
    for (size_t k = 0; k < layers.size(); ++k) {
        double layer_luminance = 0.0;
        for (const Color& c : layers[k].pixels) layer_luminance += luminance(c);
        const double share = total_luminance > 0.0 ? layer_luminance / total_luminance : 0.0;
        char line[160];
        std::snprintf(line, sizeof line, "%s: %.2f%% of the image's energy", names[k].c_str(),
                      100.0 * share);
        shares.push_back(line);
    }
    return shares;
}

}  // namespace lessons
