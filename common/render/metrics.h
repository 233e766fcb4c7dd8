// How wrong an image is, against a reference it did not produce (docs/accuracy.md, "Measuring error
// against speed"). d is the per-channel difference image - reference; every mean is over all
// pixels and all three channels.
//   mse    = mean(d^2)                       mean squared error = variance + bias^2
//   rmse   = sqrt(mse)
//   relmse = mean(d^2 / (ref^2 + 0.01))      relative MSE, for HDR scenes: bright pixels do not
//                                            dominate, dark ones are not divided by ~0
//   mae    = mean(|d|)
// An unbiased estimator's MSE falls as 1/samples, so 1 / (MSE x seconds), its efficiency, is a
// constant of the estimator and the scene.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "io/image.h"

namespace lessons {

struct ErrorMetrics {
    double mse = 0.0, rmse = 0.0, relmse = 0.0, mae = 0.0;
};

// Throws InputError (naming `what`) when the sizes differ.
ErrorMetrics compare_images(const Image& image, const Image& reference,
                            const std::string& what = "image");

// Each layer's share of the image's total luminance, as printable lines "NAME: P% of the
// image's energy" (the series of lesson 4, the strategies of lesson 5).
std::vector<std::string> layer_shares(const Image& image, const std::vector<Image>& layers,
                                      const std::vector<std::string>& names);

// The per-pixel error |image - reference|, RMS over the channels (error maps).
std::vector<float> pixel_errors(const Image& image, const Image& reference);
// The top of an error map's colour scale: the 99th percentile of the errors (1 if that is 0).
double error_map_scale(const std::vector<float>& errors);
// Viridis (perceptually uniform, readable in grey and by colour-blind viewers): 0 dark, 1 yellow.
std::array<uint8_t, 3> viridis(float t);

}  // namespace lessons
