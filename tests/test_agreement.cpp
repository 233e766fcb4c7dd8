// The agreement test of two renders (common/render/agreement.h) on renders simulated with a
// known expectation: skewed samples (exponential, as path tracing's are: most small, a few
// large), whose means agree pass, a mean 5% too high fails, and noiseless pixels must be equal.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "io/input_error.h"
#include "render/agreement.h"
#include "sampling/rng.h"

using namespace lessons;

namespace {

// A render of `spp` exponential samples per pixel and channel, of mean expected(x, y) * scale:
// the image is each pixel's sample mean, the variance its sample variance / spp (the variance of
// the mean, as a lesson's --variance writes it).
struct Simulated {
    Image image, variance;
};
Simulated simulate(int w, int h, int spp, double scale, uint64_t seed) {
    Simulated s{Image(w, h), Image(w, h)};
    Rng rng(seed);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const double mu = scale * (0.2 + 0.8 * (x + y + c) / double(w + h + 2));
                double sum = 0.0, sum2 = 0.0;
                for (int k = 0; k < spp; ++k) {
                    const double v = -mu * std::log(1.0 - double(rng.uniform()));
                    sum += v;
                    sum2 += v * v;
                }
                const double mean = sum / spp;
                const double sample_variance = (sum2 - spp * mean * mean) / (spp - 1);
                s.image.pixels[size_t(y) * w + x][c] = static_cast<float>(mean);
                s.variance.pixels[size_t(y) * w + x][c] = static_cast<float>(sample_variance / spp);
            }
    return s;
}

}  // namespace

TEST(Agreement, TwoRendersOfOneExpectationAgreeAndABiasedOneIsRejected) {
    // 128 x 128 pixels in blocks of 8: K = 16 x 16 blocks x 3 channels = 768 terms. The image
    // 16 spp, the reference 64. A block's relative standard deviation is then
    // sqrt(1/(16 x 64) + 1/(64 x 64)) = 0.035 (an exponential's sd is its mean), so a mean 5%
    // too high adds (0.05 / 0.035)^2 = 2 to each term's expectation: T / K about 3, z_T (3)
    // about 26, where agreeing renders give z_T within a few units of 0.
    const int w = 128, h = 128;
    const Simulated reference = simulate(w, h, 64, 1.0, 11);
    const Simulated image = simulate(w, h, 16, 1.0, 12);
    const Simulated biased = simulate(w, h, 16, 1.05, 12);
    const Agreement same =
        agreement(image.image, image.variance, reference.image, reference.variance, 8);
    EXPECT_EQ(same.terms, 768);
    EXPECT_EQ(same.exact_terms, 0);
    EXPECT_LT(std::fabs(same.chi2_z), 4.0) << "T = " << same.chi2 << " over " << same.terms;
    EXPECT_NEAR(same.chi2 / same.terms, 1.0, 4.0 * std::sqrt(2.0 / same.terms));
    const Agreement off =
        agreement(biased.image, biased.variance, reference.image, reference.variance, 8);
    EXPECT_GT(off.chi2_z, 10.0) << "T = " << off.chi2 << " over " << off.terms;
    EXPECT_GT(off.worst_z, 0.0);  // the image is above the reference
    // Edge blocks: 128 / 24 leaves a column and a row of 8-pixel blocks, counted too.
    EXPECT_EQ(agreement(image.image, image.variance, reference.image, reference.variance, 24).terms,
              6 * 6 * 3);
}

TEST(Agreement, TheReferencesVarianceStandsInForAFewSamplesThatMissedARarePath) {
    // A caustic's pixels: each sample is 50 with probability 1/100 (a rare path that found the
    // light), else 0.5; mean 0.995. At 32 spp most pixels of the image miss the rare path: their
    // mean is 0.5 and their own variance estimate 0, so z comes out far too large. With the
    // reference's variance (1024 spp) scaled to 32 samples as its floor (4), they agree. (Blocks
    // of 4 x 4 pixels, 768 terms.)
    const int w = 64, h = 64;
    auto render = [&](int spp, uint64_t seed) {
        Simulated s{Image(w, h), Image(w, h)};
        Rng rng(seed);
        for (size_t i = 0; i < s.image.pixels.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                double sum = 0.0, sum2 = 0.0;
                for (int k = 0; k < spp; ++k) {
                    const double v = rng.uniform() < 0.01f ? 50.0 : 0.5;
                    sum += v;
                    sum2 += v * v;
                }
                const double mean = sum / spp;
                s.image.pixels[i][c] = static_cast<float>(mean);
                s.variance.pixels[i][c] =
                    static_cast<float>((sum2 - spp * mean * mean) / (spp - 1) / spp);
            }
        return s;
    };
    const Simulated reference = render(1024, 21), image = render(32, 22);
    const Agreement own =
        agreement(image.image, image.variance, reference.image, reference.variance, 4);
    const Agreement floored = agreement(image.image, image.variance, reference.image,
                                        reference.variance, 4, "image", 32, 1024);
    EXPECT_GT(own.chi2_z, 4.0) << "T = " << own.chi2 << " over " << own.terms;
    // The test is one-sided (a bias makes T large), and the larger of the two variance estimates
    // errs towards passing: here T / K is below 1 (the pixels that did find the rare path
    // overstate their variance).
    EXPECT_LT(floored.chi2_z, 4.0) << "T = " << floored.chi2 << " over " << floored.terms;
    EXPECT_LT(floored.chi2, own.chi2);
}

TEST(Agreement, NoiselessPixelsMustBeEqual) {
    // A sky every sample sees alike has variance 0 in both renders: no z, but equal means.
    Image sky(4, 4), zero(4, 4), other(4, 4);
    for (Color& c : sky.pixels) c = Color(0.25f, 0.5f, 1.0f);
    for (Color& c : other.pixels) c = Color(0.25f, 0.5f, 1.01f);
    const Agreement equal = agreement(sky, zero, sky, zero, 2);
    EXPECT_EQ(equal.terms, 0);
    EXPECT_EQ(equal.exact_terms, 2 * 2 * 3);
    EXPECT_EQ(equal.exact_mismatches, 0);
    const Agreement differ = agreement(other, zero, sky, zero, 2);
    EXPECT_EQ(differ.exact_mismatches, 2 * 2);  // the blue channel of each block
}

TEST(Agreement, SizesMustMatch) {
    const Image a(4, 4), b(4, 3);
    EXPECT_THROW(agreement(a, a, b, b, 2), InputError);
    EXPECT_THROW(agreement(a, a, a, a, 0), std::invalid_argument);
}
