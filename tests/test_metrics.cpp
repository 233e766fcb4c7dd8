// Error metrics against hand-computed values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "io/input_error.h"
#include "render/metrics.h"
#include "sampling/rng.h"

using namespace lessons;

TEST(Metrics, HandComputedValues) {
    Image reference(2, 1), image(2, 1);
    reference.pixels = {Color(1.0f, 0.0f, 0.5f), Color(0.0f)};
    image.pixels = {Color(1.5f, 0.0f, 0.5f), Color(0.0f, -1.0f, 0.0f)};
    const ErrorMetrics m = compare_images(image, reference);
    // d = (0.5, 0, 0, 0, -1, 0) over 6 channels.
    EXPECT_DOUBLE_EQ(m.mse, (0.25 + 1.0) / 6.0);
    EXPECT_DOUBLE_EQ(m.rmse, std::sqrt((0.25 + 1.0) / 6.0));
    EXPECT_DOUBLE_EQ(m.mae, 1.5 / 6.0);
    // relmse: 0.25 / (1 + 0.01) + 1 / (0 + 0.01), over 6.
    EXPECT_NEAR(m.relmse, (0.25 / 1.01 + 1.0 / 0.01) / 6.0, 1e-12);
}

TEST(Metrics, AReferenceAgainstItselfIsZeroAndSizesMustMatch) {
    Image a(3, 2);
    for (size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] = Color(0.1f * i, 2.0f, 1e4f);
    const ErrorMetrics m = compare_images(a, a);
    EXPECT_EQ(m.mse, 0.0);
    EXPECT_EQ(m.relmse, 0.0);
    EXPECT_EQ(m.mae, 0.0);
    EXPECT_THROW(compare_images(a, Image(2, 3), "x.exr"), InputError);
}

// Block means: a 4x4 image in blocks of 2 (2x2 blocks), against a reference of 1 everywhere
// but one black block.
TEST(Metrics, BlockMeansFindTheBlockThatDiffersAndSkipBlackOnes) {
    Image reference(4, 4), image(4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const bool black = x >= 2 && y >= 2;  // the bottom-right block
            reference.pixels[y * 4 + x] = Color(black ? 0.0f : 1.0f);
            image.pixels[y * 4 + x] = Color(black ? 0.5f : (x >= 2 && y < 2) ? 1.1f : 1.0f);
        }
    const MeanComparison c = compare_means(image, reference, 2);
    EXPECT_EQ(c.blocks_x, 2);
    EXPECT_EQ(c.blocks_y, 2);
    EXPECT_EQ(c.blocks_compared, 3);
    EXPECT_TRUE(std::isnan(c.ratios[3]));
    EXPECT_NEAR(c.ratio_min, 1.0, 1e-12);
    EXPECT_NEAR(c.ratio_max, 1.1, 1e-6);
    EXPECT_EQ(c.worst_x, 2);  // the top-right block
    EXPECT_EQ(c.worst_y, 0);
    EXPECT_NEAR(c.image_mean, (8 * 1.0 + 4 * 1.1 + 4 * 0.5) / 16.0, 1e-6);
    EXPECT_NEAR(c.mean_ratio, (8 * 1.0 + 4 * 1.1 + 4 * 0.5) / 12.0, 1e-6);
    EXPECT_EQ(c.mean_ratio_noise, 0.0);  // no halves: unknown
    EXPECT_THROW(compare_means(image, Image(2, 2), 2), InputError);
}

// Halves A = m (1 + e), B = m (1 - e) in every block: each block mean's relative standard error
// is |A - B| / (A + B) = e; the ratio of two such images has sqrt(2) e; the whole mean of n
// equal blocks has e / sqrt(n) per image.
TEST(Metrics, BlockMeanNoiseComesFromTheHalvesDifferences) {
    const float e = 0.02f;
    Image a(4, 4), b(4, 4), c(4, 4), d(4, 4);
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        a.pixels[i] = c.pixels[i] = Color(1.0f + e);
        b.pixels[i] = d.pixels[i] = Color(1.0f - e);
    }
    const MeanComparison m = compare_means(a, c, 2, &b, &d);
    EXPECT_NEAR(m.mean_ratio, 1.0, 1e-6);
    EXPECT_NEAR(m.block_ratio_noise, std::sqrt(2.0) * e, 1e-6);
    EXPECT_NEAR(m.mean_ratio_noise, std::sqrt(2.0) * e / 2.0, 1e-6);  // 4 blocks
}

// Blocks of different brightness and noise: the whole mean's standard error is
// sqrt(sum (A - B)^2) / sum (A + B) over the blocks (their noise is independent), not the
// blocks' mean relative noise; the worst block carries its own.
TEST(Metrics, TheWholeMeansNoiseWeighsTheBlocksByTheirLight) {
    // 4x2 pixels in blocks of 2: a bright quiet block (10 +- 0.1) and a dark noisy one (1 +- 0.2).
    Image a(4, 2), b(4, 2), ref(4, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) {
            const bool bright = x < 2;
            a.pixels[y * 4 + x] = Color(bright ? 10.1f : 1.2f);
            b.pixels[y * 4 + x] = Color(bright ? 9.9f : 0.8f);
            ref.pixels[y * 4 + x] = Color(bright ? 10.0f : 1.0f);
        }
    const MeanComparison m = compare_means(a, ref, 2, &b, nullptr);
    // Per block (12 channel values): sums A - B = 12 x 0.2 and 12 x 0.4; A + B = 12 x 20, 12 x 2.
    const double whole = std::sqrt(0.25 * (2.4 * 2.4 + 4.8 * 4.8)) / (0.5 * (240.0 + 24.0));
    EXPECT_NEAR(m.mean_ratio_noise, whole, 1e-6);
    EXPECT_NEAR(m.worst_ratio, 1.0, 1e-6);  // both blocks' means equal the reference's
    EXPECT_NEAR(m.block_ratio_noise, std::sqrt(0.5 * (0.01 * 0.01 + 0.2 * 0.2)), 1e-6);
}

TEST(Metrics, TheConvergedErrorIsZeroWithinItsStandardErrorForNoiseAndFindsABias) {
    // An image of 64 x 64 pixels whose channels are the reference (0.5) plus Gaussian noise of a
    // known variance per pixel (1e-3, 2e-3 or 3e-3), that variance as its variance image: bias2
    // is 0 within three of its standard errors. The same noise about 0.5 + 0.05: bias2 is
    // 0.05^2 within three standard errors, and far from 0 in them. (Fixed seed.)
    const int w = 64, h = 64;
    Image reference(w, h), variance(w, h), noisy(w, h), offset(w, h);
    Rng rng(2024);
    auto gaussian = [&] {
        const double u1 = std::max(double(rng.uniform()), 1e-12), u2 = rng.uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
    };
    for (size_t i = 0; i < reference.pixels.size(); ++i) {
        const double v = 1e-3 * static_cast<double>(1 + i % 3);
        reference.pixels[i] = Color(0.5f);
        variance.pixels[i] = Color(static_cast<float>(v));
        Color c;
        for (int k = 0; k < 3; ++k) c[k] = static_cast<float>(0.5 + std::sqrt(v) * gaussian());
        noisy.pixels[i] = c;
        offset.pixels[i] = c + Color(0.05f);
    }
    const ConvergedError unbiased = converged_error(noisy, reference, variance, nullptr);
    EXPECT_NEAR(unbiased.noise_mse, 2e-3, 1e-6);  // the variances are floats
    EXPECT_GT(unbiased.bias2_se, 0.0);
    EXPECT_LE(std::fabs(unbiased.bias2), 3.0 * unbiased.bias2_se)
        << unbiased.bias2 << " +- " << unbiased.bias2_se;
    // The reference's own variance adds to the noise: the same image against a reference said
    // to carry as much again has bias2 about -2e-3.
    const ConvergedError doubled = converged_error(noisy, reference, variance, &variance);
    EXPECT_NEAR(doubled.bias2, unbiased.bias2 - 2e-3, 1e-6);
    const ConvergedError biased = converged_error(offset, reference, variance, nullptr);
    EXPECT_NEAR(biased.bias2, 0.05 * 0.05, 3.0 * biased.bias2_se);
    EXPECT_GT(biased.bias2, 10.0 * biased.bias2_se);
    EXPECT_THROW(converged_error(noisy, Image(2, 2), variance, nullptr), std::invalid_argument);
}
