// Participating media (common/media/): the Henyey-Greenstein phase function against its closed
// forms (it integrates to 1, its mean cosine is g, g > 0 scatters forward in the BSDFs'
// convention), its sampling against its density (chi-square), Beer-Lambert transmittance, and
// the free-flight sampling's densities (chi-square over distance) and estimators (unbiased per
// channel, within their standard errors) (docs/accuracy.md).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "media/medium.h"
#include "media/phase.h"
#include "sampling/rng.h"
#include "statistics.h"

using namespace lessons;

namespace {

const std::vector<float> kAsymmetries = {-0.9f, -0.5f, 0.0f, 0.0005f, 0.3f, 0.9f};

// 2 pi times the integral over cos(theta) in [-1, 1] of weight(cos) HG(cos, g).
double integrate_over_sphere(float g, double (*weight)(double)) {
    return 2.0 * kPi *
           test::adaptive_simpson(
               [&](double c) {
                   return weight(c) *
                          static_cast<double>(henyey_greenstein(static_cast<float>(c), g));
               },
               -1.0, 1.0, 1e-8, 20);
}

Medium fog(Color sigma_a, Color sigma_s, float g = 0.0f) {
    Medium m;
    m.name = "fog";
    m.sigma_a = sigma_a;
    m.sigma_s = sigma_s;
    m.g = g;
    return m;
}

}  // namespace

TEST(HenyeyGreenstein, IntegratesToOneAndItsMeanCosineIsG) {
    for (float g : kAsymmetries) {
        EXPECT_NEAR(integrate_over_sphere(g, [](double) { return 1.0; }), 1.0, 1e-5) << "g " << g;
        EXPECT_NEAR(integrate_over_sphere(g, [](double c) { return c; }), g, 1e-5) << "g " << g;
    }
}

TEST(HenyeyGreenstein, PositiveGScattersForwardWithBothDirectionsPointingAway) {
    // The light comes along -wi and goes on along wo: with wi = -wo it has not turned at all.
    const HenyeyGreenstein forward(0.8f);
    const Vec3 wo = glm::normalize(Vec3(0.3f, -0.2f, 0.9f));
    EXPECT_GT(forward.eval(wo, -wo), 10.0f * forward.eval(wo, wo));
    EXPECT_NEAR(forward.eval(wo, -wo), henyey_greenstein(1.0f, 0.8f),
                1e-4f * forward.eval(wo, -wo));
    // Sampled: the mean of cos(theta) = -dot(wo, wi) is g, within 5 standard errors.
    Rng rng(7);
    std::vector<double> cosines;
    for (int i = 0; i < 200000; ++i) {
        const PhaseSample s = forward.sample(wo, {rng.uniform(), rng.uniform()});
        cosines.push_back(-static_cast<double>(glm::dot(wo, s.wi)));
    }
    const test::MeanAndError m = test::mean_and_error(cosines);
    EXPECT_NEAR(m.mean, 0.8, 5.0 * m.standard_error);
}

TEST(HenyeyGreenstein, SamplingMatchesItsDensity) {
    const double significance = test::sidak(0.01, static_cast<int>(kAsymmetries.size()));
    uint64_t seed = 11;
    for (float g : kAsymmetries) {
        const HenyeyGreenstein phase(g);
        const Vec3 wo = glm::normalize(Vec3(0.5f, 0.1f, -0.4f));
        Rng rng(seed++);
        // Peaked lobes (|g| = 0.9 puts half its density within 10 degrees) get finer cells.
        const int cells = std::abs(g) > 0.5f ? 80 : 20;
        const auto r = test::chi2_test_directions(
            [&](Vec3& w) {
                const PhaseSample s = phase.sample(wo, {rng.uniform(), rng.uniform()});
                EXPECT_NEAR(s.pdf, phase.pdf(wo, s.wi), 2e-3f * s.pdf);
                EXPECT_NEAR(s.p, phase.eval(wo, s.wi), 2e-3f * s.p);
                EXPECT_NEAR(glm::length(s.wi), 1.0f, 1e-5f);
                w = s.wi;
                return true;
            },
            [&](const Vec3& w) { return static_cast<double>(phase.pdf(wo, w)); }, 400000,
            significance, cells, 2 * cells);
        EXPECT_TRUE(r.passed) << "g " << g << ": " << r.report;
        EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3) << "g " << g;
    }
}

TEST(Medium, TransmittanceIsBeerLambertPerChannel) {
    const Medium m = fog(Color(0.1f, 0.0f, 0.5f), Color(0.2f, 0.0f, 0.25f));
    const Color T = m.transmittance(2.0f);
    EXPECT_FLOAT_EQ(T.x, std::exp(-0.3f * 2.0f));
    EXPECT_FLOAT_EQ(T.y, 1.0f);
    EXPECT_FLOAT_EQ(T.z, std::exp(-0.75f * 2.0f));
    // Multiplicative over consecutive pieces, 1 at no distance, and exact at infinity (no NaN
    // from 0 x infinity in the channel without extinction).
    const Color product = m.transmittance(0.7f) * m.transmittance(1.3f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(product[c], T[c], 1e-6f);
    EXPECT_EQ(m.transmittance(0.0f), Color(1.0f));
    EXPECT_EQ(m.transmittance(kInfinity), Color(0.0f, 1.0f, 0.0f));
    const Color albedo = m.albedo();
    EXPECT_FLOAT_EQ(albedo.x, 0.2f / 0.3f);
    EXPECT_EQ(albedo.y, 0.0f);
    EXPECT_FLOAT_EQ(albedo.z, 0.25f / 0.75f);
    EXPECT_FALSE(m.is_vacuum());
    EXPECT_TRUE(fog(Color(0.0f), Color(0.0f)).is_vacuum());
}

// The collision distances of sample_free_flight in bins over [0, t_max), and the pass-through
// bin, against the mixture over channels (chi-square), for colours of sigma_t far apart and
// channel weights equal and unequal.
TEST(Medium, FreeFlightDistancesFollowTheChannelMixture) {
    const Medium m = fog(Color(0.05f, 0.4f, 0.0f), Color(0.45f, 1.6f, 0.0f));  // sigma_t .5, 2, 0
    const float t_max = 3.0f;
    const int bins = 30, n = 300000;
    int run = 0;
    for (const Color& weights : {Color(1.0f), Color(0.2f, 0.7f, 0.1f)}) {
        Rng rng(31 + run++);
        std::vector<double> observed(bins + 1, 0.0);
        for (int i = 0; i < n; ++i) {
            const FreeFlight f =
                sample_free_flight(m, t_max, rng.uniform(), rng.uniform(), weights);
            ASSERT_TRUE(f.t >= 0.0f && f.t <= t_max);
            ASSERT_GT(f.pdf, 0.0f);
            // The density it reports is the channel mixture's, computed here in double.
            const double sum = static_cast<double>(weights.x) + weights.y + weights.z;
            double mixture = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double s = m.sigma_t()[c];
                mixture += weights[c] / sum * (f.collided ? s : 1.0) * std::exp(-s * f.t);
            }
            EXPECT_NEAR(f.pdf, mixture, 1e-5 * mixture);
            const int b =
                f.collided ? std::min(bins - 1, static_cast<int>(f.t / t_max * bins)) : bins;
            observed[static_cast<size_t>(b)] += 1.0;
        }
        // Expected: the mixture's probability of each bin, sum_c P_c (T_c(a) - T_c(b)), and of
        // passing, sum_c P_c T_c(t_max).
        const Color P = weights / (weights.x + weights.y + weights.z);
        double chi2 = 0.0;
        for (int b = 0; b <= bins; ++b) {
            const Color Ta = m.transmittance(t_max * b / bins);
            const Color Tb = m.transmittance(t_max * (b + 1) / bins);
            const double p = b < bins ? glm::dot(P, Ta - Tb) : glm::dot(P, m.transmittance(t_max));
            const double e = p * n;
            const double d = observed[static_cast<size_t>(b)] - e;
            chi2 += d * d / e;
        }
        const double p_value = test::chi2_p_value(chi2, bins);
        EXPECT_GT(p_value, test::sidak(0.01, 2)) << "chi2 " << chi2 << " weights " << run;
    }
}

// Per channel, the collision estimator T sigma_s / pdf integrates sigma_s T over [0, t_max)
// (the single-scattering integral with in-scattered radiance 1: (sigma_s / sigma_t) (1 -
// T(t_max))), and the pass-through one T / pdf gives T(t_max): both unbiased whichever channel
// drew the distance, within 5 standard errors of the closed forms, for equal and unequal channel
// weights (one of them 0) and an infinite t_max. Spectral MIS bounds each channel's collision
// weight by sigma_s,c / (P_c sigma_t,c) where P_c > 0: checked on every sample.
TEST(Medium, FreeFlightEstimatorsAreUnbiasedInEveryChannel) {
    const Medium m = fog(Color(0.1f, 1.0f, 0.02f), Color(0.9f, 3.0f, 0.08f));  // sigma_t 1, 4, .1
    struct Case {
        Color weights;
        float t_max;
    };
    uint64_t seed = 77;
    for (const Case& k : {Case{Color(1.0f), 2.0f}, Case{Color(0.2f, 0.7f, 0.1f), 2.0f},
                          Case{Color(1.0f, 0.0f, 1.0f), 2.0f}, Case{Color(1.0f), kInfinity}}) {
        SCOPED_TRACE("weights " + std::to_string(k.weights.x) + " " + std::to_string(k.weights.y) +
                     " " + std::to_string(k.weights.z) + ", t_max " + std::to_string(k.t_max));
        const Color P = k.weights / (k.weights.x + k.weights.y + k.weights.z);
        Rng rng(seed++);
        const int n = 300000;
        std::vector<double> scattered[3], passed[3];
        for (int i = 0; i < n; ++i) {
            const FreeFlight f =
                sample_free_flight(m, k.t_max, rng.uniform(), rng.uniform(), k.weights);
            for (int c = 0; c < 3; ++c) {
                const double w = static_cast<double>(f.transmittance[c]) / f.pdf;
                ASSERT_TRUE(std::isfinite(w));
                scattered[c].push_back(f.collided ? w * m.sigma_s[c] : 0.0);
                passed[c].push_back(f.collided ? 0.0 : w);
                if (f.collided && P[c] > 0.0f)
                    ASSERT_LE(w * m.sigma_s[c],
                              m.sigma_s[c] / (P[c] * m.sigma_t()[c]) * (1.0 + 1e-5));
            }
        }
        for (int c = 0; c < 3; ++c) {
            const double T = std::exp(-static_cast<double>(m.sigma_t()[c]) * k.t_max);
            const double single = static_cast<double>(m.albedo()[c]) * (1.0 - T);
            const test::MeanAndError s = test::mean_and_error(scattered[c]);
            const test::MeanAndError p = test::mean_and_error(passed[c]);
            EXPECT_NEAR(s.mean, single, 5.0 * s.standard_error + 1e-9) << "channel " << c;
            EXPECT_NEAR(p.mean, T, 5.0 * p.standard_error + 1e-9) << "channel " << c;
        }
    }
}

TEST(Medium, FreeFlightInAVacuumChannelPassesToInfinityWithoutNaN) {
    const Medium m = fog(Color(0.0f, 0.5f, 0.0f), Color(0.0f));  // only green absorbs
    Rng rng(5);
    for (int i = 0; i < 1000; ++i) {
        const FreeFlight f = sample_free_flight(m, kInfinity, rng.uniform(), rng.uniform());
        ASSERT_TRUE(std::isfinite(f.pdf) && f.pdf > 0.0f);
        ASSERT_TRUE(is_finite(f.transmittance));
        if (!f.collided) {
            // Red or blue chose it: passing has probability 2/3, and green's light is all gone.
            EXPECT_EQ(f.t, kInfinity);
            EXPECT_FLOAT_EQ(f.pdf, 2.0f / 3.0f);
            EXPECT_EQ(f.transmittance, Color(1.0f, 0.0f, 1.0f));
        }
    }
}
