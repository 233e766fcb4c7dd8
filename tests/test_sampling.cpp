// Every sampling routine against its density: chi-square tests (ACCURACY.md), and finite
// outputs at the ends of [0, 1).
#include <gtest/gtest.h>

#include "rng.h"
#include "sampling.h"
#include "statistics.h"

using namespace lessons;

namespace {
// Every chi-square test of the suite shares one family-wise significance of 0.01.
const double kSignificance = test::sidak(0.01, 60);
constexpr int kSamples = 1000000;
}  // namespace

TEST(Sampling, UniformHemisphereMatchesItsDensity) {
    Rng rng(1);
    const auto r = test::chi2_test_directions(
        [&](Vec3& w) {
            w = sample_uniform_hemisphere({rng.uniform(), rng.uniform()});
            return true;
        },
        [](const Vec3& w) { return w.z > 0.0f ? uniform_hemisphere_pdf() : 0.0; }, kSamples,
        kSignificance);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3);
}

TEST(Sampling, CosineHemisphereMatchesItsDensity) {
    Rng rng(2);
    const auto r = test::chi2_test_directions(
        [&](Vec3& w) {
            w = sample_cosine_hemisphere({rng.uniform(), rng.uniform()});
            return true;
        },
        [](const Vec3& w) { return cosine_hemisphere_pdf(w.z); }, kSamples, kSignificance);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3);
}

TEST(Sampling, UniformSphereMatchesItsDensity) {
    Rng rng(3);
    const auto r = test::chi2_test_directions(
        [&](Vec3& w) {
            w = sample_uniform_sphere({rng.uniform(), rng.uniform()});
            return true;
        },
        [](const Vec3&) { return uniform_sphere_pdf(); }, kSamples, kSignificance);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3);
}

TEST(Sampling, UniformConeMatchesItsDensity) {
    for (float one_minus_cos : {0.6f, 0.05f}) {
        Rng rng(4);
        const auto r = test::chi2_test_directions(
            [&](Vec3& w) {
                w = sample_uniform_cone({rng.uniform(), rng.uniform()}, one_minus_cos);
                return true;
            },
            [&](const Vec3& w) {
                return 1.0f - w.z <= one_minus_cos ? uniform_cone_pdf(one_minus_cos) : 0.0f;
            },
            kSamples, kSignificance, 80, 40);
        EXPECT_TRUE(r.passed) << one_minus_cos << ": " << r.report;
        EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3) << one_minus_cos;
    }
}

TEST(Sampling, TriangleSamplesAreUniformByArea) {
    // Barycentrics (b1, b2) uniform on the triangle b1, b2 >= 0, b1 + b2 <= 1: each of the four
    // sub-triangles cut by the edge midpoints gets a quarter of the samples.
    Rng rng(5);
    int counts[4] = {0, 0, 0, 0};
    const int n = 400000;
    for (int i = 0; i < n; ++i) {
        const Vec2 b = sample_uniform_triangle({rng.uniform(), rng.uniform()});
        ASSERT_GE(b.x, 0.0f);
        ASSERT_GE(b.y, 0.0f);
        ASSERT_LE(b.x + b.y, 1.0f + 1e-6f);
        const int cell = b.x > 0.5f ? 1 : b.y > 0.5f ? 2 : (b.x + b.y < 0.5f ? 0 : 3);
        ++counts[cell];
    }
    // Binomial standard deviation sqrt(n p (1 - p)) = 274; allow 5 of them.
    for (int c : counts) EXPECT_NEAR(c, n / 4, 5 * 274);
}

TEST(Sampling, OutputsAreFiniteAtTheEndsOfTheUnitSquare) {
    const float ends[] = {0.0f, 0.5f, 0x1.fffffep-1f};
    for (float a : ends)
        for (float b : ends) {
            const Vec2 u(a, b);
            EXPECT_TRUE(is_finite(sample_uniform_hemisphere(u)));
            EXPECT_TRUE(is_finite(sample_cosine_hemisphere(u)));
            EXPECT_TRUE(is_finite(sample_uniform_sphere(u)));
            EXPECT_TRUE(is_finite(sample_uniform_cone(u, 1e-7f)));
            const Vec2 d = sample_concentric_disk(u);
            EXPECT_TRUE(std::isfinite(d.x) && std::isfinite(d.y));
            const Vec2 t = sample_uniform_triangle(u);
            EXPECT_TRUE(std::isfinite(t.x) && std::isfinite(t.y));
        }
}

TEST(Sampling, MisHeuristicsSumToOne) {
    for (float a : {0.0f, 0.1f, 1.0f, 7.0f, 1e30f})
        for (float b : {0.0f, 0.3f, 2.0f, 1e30f}) {
            if (a + b == 0.0f) continue;
            EXPECT_NEAR(balance_heuristic(a, b) + balance_heuristic(b, a), 1.0f, 1e-6f);
            EXPECT_NEAR(power_heuristic(a, b) + power_heuristic(b, a), 1.0f, 1e-6f)
                << a << " " << b;
        }
}

TEST(Sampling, TheChiSquareTestRejectsAWrongDensity) {
    // Cosine-weighted samples judged against the uniform density, and the slightly wrong
    // normalisation (e + 8) / (8 pi)-style mistake of a 5% heavier lobe: both must fail.
    Rng rng(6);
    const auto wrong_shape = test::chi2_test_directions(
        [&](Vec3& w) {
            w = sample_cosine_hemisphere({rng.uniform(), rng.uniform()});
            return true;
        },
        [](const Vec3& w) { return w.z > 0.0f ? uniform_hemisphere_pdf() : 0.0; }, 100000,
        kSignificance);
    EXPECT_FALSE(wrong_shape.passed) << wrong_shape.report;
    const auto too_heavy = test::chi2_test_directions(
        [&](Vec3& w) {
            w = sample_cosine_hemisphere({rng.uniform(), rng.uniform()});
            return true;
        },
        [](const Vec3& w) { return 1.05 * cosine_hemisphere_pdf(w.z); }, 100000, kSignificance);
    EXPECT_FALSE(too_heavy.passed) << too_heavy.report;
}
