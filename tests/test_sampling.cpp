// Every sampling routine against its density: chi-square tests (docs/accuracy.md), and finite
// outputs at the ends of [0, 1).
#include <gtest/gtest.h>

#include "sampling/discrete.h"
#include "sampling/rng.h"
#include "sampling/sampling.h"
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
            for (const Vec3& o : {Vec3(0, 0, -1), Vec3(3, 0.5f, 1e-3f), Vec3(0.5f, 0.5f, 1e-3f)}) {
                const Vec2 r =
                    SphericalRectangle(o, Vec3(0), Vec3(1, 0, 0), Vec3(0, 1, 0)).sample(u);
                EXPECT_TRUE(r.x >= 0.0f && r.x <= 1.0f && r.y >= 0.0f && r.y <= 1.0f)
                    << r.x << " " << r.y;
            }
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

namespace {
// Solid angle of the rectangle [x0, x1] x [y0, y1] in the plane z = -h seen from the origin, in
// double: sum over corners of +-atan(x y / (h |(x, y, h)|)) (the solid angle of the rectangle
// [0, x] x [0, y] is atan(x y / (h r))).
double rectangle_solid_angle(double x0, double x1, double y0, double y1, double h) {
    auto corner = [h](double x, double y) {
        return std::atan(x * y / (h * std::sqrt(x * x + y * y + h * h)));
    };
    return corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0);
}
}  // namespace

TEST(Sampling, SphericalRectangleSolidAngleMatchesTheClosedForm) {
    // A 2 x 1.5 rectangle in the plane z = -h (edges along x and y), seen from the origin:
    // above its middle, beside it and close to its plane (where area sampling fails), far away.
    struct Case {
        double x0, y0, h;
    };
    for (const Case& c : {Case{-1.0, -0.75, 1.0}, Case{0.05, -0.75, 0.01}, Case{-1.0, 3.0, 0.2},
                          Case{3.0, 4.0, 20.0}}) {
        const SphericalRectangle rect(Vec3(0.0f), Vec3(float(c.x0), float(c.y0), float(-c.h)),
                                      Vec3(2, 0, 0), Vec3(0, 1.5f, 0));
        const double expected = rectangle_solid_angle(c.x0, c.x0 + 2.0, c.y0, c.y0 + 1.5, c.h);
        EXPECT_NEAR(rect.solid_angle(), expected, 2e-4 * expected + 1e-6) << c.x0 << " " << c.h;
        EXPECT_TRUE(rect.well_conditioned());
        // The same rectangle seen from the other side (o mirrored through its plane).
        const SphericalRectangle back(Vec3(0, 0, float(-2.0 * c.h)),
                                      Vec3(float(c.x0), float(c.y0), float(-c.h)), Vec3(2, 0, 0),
                                      Vec3(0, 1.5f, 0));
        EXPECT_NEAR(back.solid_angle(), expected, 2e-4 * expected + 1e-6);
    }
    // In its plane it subtends nothing, and the caller must sample by area: beside it, on the
    // line of an edge, inside it, at a corner. Nor is a tiny solid angle, where the excess of
    // the angles over 2 pi cancels, sampled by solid angle.
    for (const Vec3& o : {Vec3(5, 0, 0), Vec3(5, 0.5f, 0), Vec3(0.5f, 0.5f, 0), Vec3(0)}) {
        const SphericalRectangle in_plane(o, Vec3(0), Vec3(1, 0, 0), Vec3(0, 1, 0));
        EXPECT_FALSE(in_plane.well_conditioned()) << o.x << " " << o.y;
        EXPECT_TRUE(std::isfinite(in_plane.solid_angle()));
    }
    const SphericalRectangle far(Vec3(0, 0, 200), Vec3(0), Vec3(1, 0, 0), Vec3(0, 1, 0));
    EXPECT_TRUE(std::isfinite(far.solid_angle()));  // about A / d^2 = 2.5e-5 sr
    EXPECT_FALSE(far.well_conditioned());
}

TEST(Sampling, SphericalRectangleDirectionsAreUniformInSolidAngle) {
    // Chi-square of the directions towards the sampled points against 1 / Omega over the
    // rectangle's directions, from above it, from near its plane beside it, and obliquely. The
    // rectangle is turned so that its edges lie along no axis.
    const Vec3 eu = 2.0f * glm::normalize(Vec3(1, 0.2f, 0)), ev = glm::normalize(Vec3(-0.2f, 1, 0));
    const Vec3 corner(-1, -0.5f, 1);
    const Vec3 n = glm::normalize(glm::cross(eu, ev));
    for (const Vec3& o : {Vec3(0, 0, 0), Vec3(1.8f, 0.3f, 0.97f), Vec3(-2, 1, 0.3f)}) {
        const SphericalRectangle rect(o, corner, eu, ev);
        ASSERT_TRUE(rect.well_conditioned());
        Rng rng(5);
        const auto r = test::chi2_test_directions(
            [&](Vec3& w) {
                const Vec2 ab = rect.sample({rng.uniform(), rng.uniform()});
                w = glm::normalize(corner + ab.x * eu + ab.y * ev - o);
                return true;
            },
            [&](const Vec3& w) -> double {
                // Does the ray o + t w meet the rectangle? (Plane, then edge coordinates.)
                const double denom = glm::dot(glm::dvec3(n), glm::dvec3(w));
                if (denom == 0.0) return 0.0;
                const double t = glm::dot(glm::dvec3(n), glm::dvec3(corner - o)) / denom;
                if (t <= 0.0) return 0.0;
                const glm::dvec3 rel = glm::dvec3(o) + t * glm::dvec3(w) - glm::dvec3(corner);
                const double a = glm::dot(rel, glm::dvec3(eu)) / 4.0;
                const double b = glm::dot(rel, glm::dvec3(ev));
                // Points on an edge are sampled (a, b in [0, 1]); the float direction towards
                // them may pass a rounding error outside.
                const double tolerance = 1e-5;
                return a >= -tolerance && a <= 1.0 + tolerance && b >= -tolerance &&
                               b <= 1.0 + tolerance
                           ? 1.0 / rect.solid_angle()
                           : 0.0;
            },
            kSamples, kSignificance, 80, 80);
        EXPECT_TRUE(r.passed) << o.x << " " << o.y << " " << o.z << ": " << r.report;
        EXPECT_NEAR(r.pdf_integral, 1.0, 5e-3);
    }
}

TEST(Sampling, ChoiceTablesGiveEveryPositiveWeightAnExactPositiveProbability) {
    // The table a light or a texel is chosen from (sampling/discrete.h): on the grid of the
    // uniform numbers, so that the probability the estimators divide by is the probability the
    // sampler realises, counted here over every one of the 2^24 values of u; no entry of
    // positive weight at 0, however small its share; no entry of zero weight above 0; and each
    // share within a few units of 2^-24 of its weight's share.
    const std::vector<std::vector<double>> cases = {{1e8, 1.0},
                                                    {1.0, 1e8},
                                                    {0.0, 3.0, 0.0, 1e-12, 5.0, 0.0},
                                                    {2.0},
                                                    {0.0, 0.0, 0.0},
                                                    {1e9, 1.0, 1.0, 1.0, 1e-3, 1e9},
                                                    {1.0, 2.0, 3.0, 4.0}};
    for (const std::vector<double>& weights : cases) {
        const std::vector<float> cdf = choice_cdf(weights);
        ASSERT_EQ(cdf.size(), weights.size());
        EXPECT_EQ(cdf.back(), 1.0f);
        double total = 0.0;
        size_t positive = 0;
        for (double w : weights) {
            total += w;
            positive += w > 0.0;
        }
        std::vector<uint32_t> count(weights.size(), 0);
        for (uint32_t k = 0; k < (1u << 24); ++k) ++count[choose_entry(cdf, k * 0x1p-24f)];
        for (size_t i = 0; i < weights.size(); ++i) {
            const float p = entry_probability(cdf, i);
            EXPECT_EQ(static_cast<double>(count[i]) * 0x1p-24, p) << "entry " << i;
            if (total > 0.0) {
                EXPECT_EQ(p > 0.0f, weights[i] > 0.0)
                    << "entry " << i << " of weight " << weights[i];
                EXPECT_NEAR(p, weights[i] / total, (positive + 1) * 0x1p-24) << "entry " << i;
            } else {
                EXPECT_NEAR(p, 1.0 / weights.size(), 0x1p-24);  // nothing to weigh by: uniform
            }
        }
    }
    // The rest of u within the chosen entry: the middle of each of its units, from half a unit
    // above 0 to half a unit below 1 (an entry of one unit: its centre).
    const std::vector<float> cdf = choice_cdf(std::vector<double>{1.0, 3.0});
    float rest = -1.0f;
    EXPECT_EQ(choose_entry(cdf, 0.25f, &rest), 1u);
    EXPECT_EQ(rest, 0.5f * 0x1p-24f / 0.75f);
    EXPECT_EQ(choose_entry(cdf, 0.25f - 0x1p-24f, &rest), 0u);
    EXPECT_EQ(rest, (0.25f - 0.5f * 0x1p-24f) / 0.25f);
    const std::vector<float> tiny = choice_cdf(std::vector<double>{1e12, 1.0, 1e12});
    ASSERT_EQ(entry_probability(tiny, 1), 0x1p-24f);
    EXPECT_EQ(choose_entry(tiny, tiny[0], &rest), 1u);
    EXPECT_EQ(rest, 0.5f);
}
