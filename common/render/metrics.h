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

// The error more samples cannot remove, from one render and its per-pixel variance of the mean
// (a lesson's --variance image; renders of independent samples): per channel E[d^2] = bias^2 +
// Var(image) + Var(reference), so per pixel e = d^2 less both variances (the mean over the
// channels) estimates its squared bias, and their mean, bias2, the image's (noise_mse: the mean of
// the variances). bias2_se is its standard error, sd(e) / sqrt(pixels), the pixels taken as
// independent: a bias2 within two of them of 0 is an unbiased run's, of either sign. The images
// must have one size (else std::invalid_argument); reference_variance may be null.
struct ConvergedError {
    double noise_mse = 0.0, bias2 = 0.0, bias2_se = 0.0;
};
ConvergedError converged_error(const Image& image, const Image& reference, const Image& variance,
                               const Image* reference_variance);

// Image means against a reference's, whole and in square blocks: where two renderers (or two
// estimators) differ systematically rather than by noise (scripts/cycles_compare.sh). A mean is
// over a block's pixels and the three channels; a block is compared when the reference's mean
// there is at least 1e-3 of its whole mean (black regions have no ratio). With the second halves
// of both renders (independent renders of the same image; the images are then the means of the
// halves), each ratio's noise is estimated from the halves' differences: a block mean M of two
// halves A, B has relative standard error about |A - B| / (A + B) (one degree of freedom: a
// rough figure for one block, pooled over the blocks as an RMS); the whole mean's is
// sqrt(sum (A - B)^2) / sum (A + B) over every block.
struct MeanComparison {
    int block = 0;                  // side of a block, pixels (edge blocks may be smaller)
    int blocks_x = 0, blocks_y = 0;
    int blocks_compared = 0;        // the others are black in the reference
    double image_mean = 0.0, reference_mean = 0.0;
    double mean_ratio = 0.0;        // image_mean / reference_mean
    double mean_ratio_noise = 0.0;  // its standard error (0 without halves)
    double ratio_min = 0.0, ratio_max = 0.0;
    double block_ratio_noise = 0.0;  // one block ratio's standard error, pooled (0 without halves)
    int worst_x = 0, worst_y = 0;    // the block whose ratio is farthest from 1 (its top-left pixel)
    double worst_ratio = 1.0;
    double worst_ratio_noise = 0.0;  // that block's own standard error (one degree of freedom)
    std::vector<double> ratios;  // row-major over the blocks; NaN where not compared
};
// image_b and reference_b: the second halves, or null. Throws InputError on different sizes.
MeanComparison compare_means(const Image& image, const Image& reference, int block,
                             const Image* image_b = nullptr, const Image* reference_b = nullptr);

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
