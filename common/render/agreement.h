// Whether two renders of independent samples estimate the same image, within their noise: a
// z-test of each block of pixels, and a chi-square test over all of them. What keeps a shipped
// reference (references/) honest: a low-spp render with today's code must agree with it.
//
// Each render gives per pixel p and channel c the mean m of its samples and the variance of that
// mean, v (a lesson's --variance image: the error of the mean for independent samples). For a
// block B of n pixels, the block mean M = (1/n) sum m is a mean of n x spp samples, nearly normal
// by the central limit theorem, with variance V = (1/n^2) sum v (the pixels' samples are
// independent). If the image and the reference estimate the same expectation,
//   z = (M_image - M_reference) / sqrt(V_image + V_reference)                        (1)
// is standard normal, and over the K blocks and channels
//   T = sum z^2  ~  chi-square with K degrees of freedom.                            (2)
// Wilson and Hilferty (1931): (T / K)^(1/3) is nearly normal with mean 1 - 2/(9K) and variance
// 2/(9K), so
//   z_T = ((T / K)^(1/3) - (1 - 2/(9K))) / sqrt(2/(9K))                               (3)
// is standard normal when the renders agree; a difference in expectation (a bias) adds
// (bias / sd)^2 to each term's mean, so T grows with K and z_T with sqrt(K).
// Blocks rather than single pixels: a pixel's mean of a few samples is far from normal where a
// rare path carries much light (a caustic: most pixels of a low-spp render miss it, and their
// variance estimate misses it too), while a block pools n times the samples. block = 1 is the
// per-pixel test.
// The variance of a mean of few samples is itself a poor estimate where rare paths carry the
// light: a pixel whose 32 samples all missed a rare bright path shows both a low mean and a low
// variance, and its z is too large. When the image has image_spp samples per pixel and the
// reference reference_spp (both of the same estimator, which is what the test asks), the
// reference's variance of one sample, v_reference x reference_spp, estimates the image's too,
// from many more samples; each pixel's variance of the image's mean is then taken as
//   v = max(v_image, v_reference x reference_spp / image_spp)                        (4)
// (the larger of two estimates of one quantity: a test that errs, if at all, towards passing
// agreeing renders, and keeps the image's own variance where today's estimator is noisier).
// A block whose two variances are both 0 (every sample saw the same radiance: a sky, a black
// background) has no noise to compare with: the two means must be equal to float rounding, and
// one that is not is counted apart (exact_mismatches), not in T.
#pragma once

#include "io/image.h"

namespace lessons {

struct Agreement {
    int block = 0;         // side of a block, pixels (edge blocks may be smaller)
    int terms = 0;         // K: blocks x channels with noise
    double chi2 = 0.0;     // T, (2)
    double chi2_z = 0.0;   // z_T, (3): standard normal if the renders agree
    int beyond_3 = 0;      // terms with |z| > 3 (expected about 0.0027 K)
    double worst_z = 0.0;  // the term of largest |z|, with its sign (image above: positive)
    int worst_x = 0, worst_y = 0, worst_channel = 0;  // its block's top-left pixel, its channel
    int exact_terms = 0;       // blocks x channels without noise in either render
    int exact_mismatches = 0;  // of those, the ones whose means differ beyond float rounding
};

// The test above, of `image` (its variance of the mean per pixel: `variance`) against
// `reference` (`reference_variance`), in blocks of block x block pixels; with image_spp and
// reference_spp both > 0, the variance floor (4). Throws InputError (naming `what`) when the
// sizes differ, std::invalid_argument for block < 1.
Agreement agreement(const Image& image, const Image& variance, const Image& reference,
                    const Image& reference_variance, int block, const std::string& what = "image",
                    int image_spp = 0, int reference_spp = 0);

}  // namespace lessons
