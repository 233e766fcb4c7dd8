// Lesson 7's machinery on its own (chapters/07_metropolis/primary_samples.h, chain.h): a rejected
// proposal restores every number bit for bit; skipped small steps applied lazily have the
// distribution of steps applied one by one; on targets of known shape the chain's splats follow
// the target, a number read on part of the domain does not draw the chain there, and without
// the bootstrap's resampling a start-up bias shows while with it none does (docs/accuracy.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "07_metropolis/chain.h"
#include "07_metropolis/primary_samples.h"
#include "statistics.h"

using namespace lessons;
namespace {

bool same_entry(const PrimarySamples::Entry& a, const PrimarySamples::Entry& b) {
    return std::memcmp(&a.value, &b.value, sizeof(float)) == 0 && a.changed == b.changed;
}

// Reads n numbers of each of the sampler's three streams, as one path would.
void read_path(PrimarySamples& x, int n) {
    x.start_path();
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) x.stream(k).uniform();
}

// The Kolmogorov-Smirnov distance between two samples' empirical distributions.
double ks_distance(std::vector<double> a, std::vector<double> b) {
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    size_t i = 0, j = 0;
    double d = 0.0;
    while (i < a.size() && j < b.size()) {
        const double x = std::min(a[i], b[j]);
        while (i < a.size() && a[i] <= x) ++i;
        while (j < b.size() && b[j] <= x) ++j;
        d = std::max(
            d, std::fabs(static_cast<double>(i) / a.size() - static_cast<double>(j) / b.size()));
    }
    return d;
}

// The signed displacement from a to b on the circle [0, 1): in [-0.5, 0.5).
double displacement(float a, float b) {
    double d = static_cast<double>(b) - static_cast<double>(a);
    d -= std::floor(d + 0.5);
    return d;
}

}  // namespace

TEST(PrimarySamples, ARejectedProposalRestoresEveryNumberBitForBit) {
    // A chain's state after accepted small and large steps, the last of which read 8 numbers of
    // each stream (so all are the state's, up to date); then proposals of each kind that read
    // them and 4 more (a longer path), rejected. The 8 come back bit for bit, value and age. Of
    // the 4 the state had never read: after a large step they are unmade again; after a small
    // one they hold the state's own numbers (made for the proposal to move, and kept).
    PrimarySamples x(Rng(7, 0, 0), 0.05f, 0.3f, 3);
    read_path(x, 6);
    for (int step = 0; step < 40; ++step) {
        x.propose();
        read_path(x, 3 + step % 5);
        if (step % 3 != 2)
            x.accept();
        else
            x.reject();
    }
    x.propose();
    read_path(x, 8);
    x.accept();
    for (const bool want_large : {true, false}) {
        const std::vector<PrimarySamples::Entry> before = x.entries();
        ASSERT_GE(before.size(), 24u);
        const int64_t iteration = x.iteration();
        while (x.propose() != want_large) x.reject();  // a proposal of the kind wanted
        read_path(x, 12);
        const std::vector<PrimarySamples::Entry> during = x.entries();
        for (size_t i = 0; i < during.size(); ++i)
            EXPECT_EQ(during[i].changed, iteration + 1) << "entry " << i << " was read";
        x.reject();
        EXPECT_EQ(x.iteration(), iteration);
        const std::vector<PrimarySamples::Entry> after = x.entries();
        ASSERT_EQ(after.size(), 36u);
        for (size_t i = 0; i < 24; ++i)
            EXPECT_TRUE(same_entry(before[i], after[i]))
                << (want_large ? "large" : "small") << " step, entry " << i;
        for (size_t i = 24; i < after.size(); ++i) {
            if (want_large)
                EXPECT_EQ(after[i].changed, -1) << "entry " << i;
            else
                EXPECT_TRUE(after[i].changed >= 0 && after[i].changed <= iteration) << i;
        }
    }
}

TEST(PrimarySamples, SkippedSmallStepsAppliedLazilyAreThoseAppliedOneByOne) {
    // Number 0 of stream 0, read at the start; then n = 6 accepted small steps. Read at every
    // step, it moves by n normal steps one by one; read only at the end, it moves once by the
    // lazily combined step. The two displacements' distributions agree (two-sample
    // Kolmogorov-Smirnov), and both are the normal distribution of deviation sigma sqrt(n)
    // (one-sample, against the closed form; wrapping is negligible at 8 deviations).
    const float sigma = 0.02f;
    const int n = 6, trials = 4000;
    std::vector<double> lazy, one_by_one;
    for (int trial = 0; trial < trials; ++trial) {
        for (const bool every_step : {false, true}) {
            PrimarySamples x(Rng(11, static_cast<uint64_t>(trial), every_step), sigma, 0.0f, 3);
            x.start_path();
            const float start = x.stream(0).uniform();
            for (int step = 0; step < n; ++step) {
                x.propose();
                x.start_path();
                if (every_step) x.stream(0).uniform();
                x.stream(1).uniform();  // the path reads something else every step
                x.accept();
            }
            x.start_path();
            const float end = x.stream(0).uniform();
            (every_step ? one_by_one : lazy).push_back(displacement(start, end));
        }
    }
    const double m = trials;
    const double two_sample = ks_distance(lazy, one_by_one);
    // Critical values at alpha 0.01: 1.628 sqrt(2 / m) for two samples of m, 1.628 / sqrt(m) for
    // one against a closed form.
    EXPECT_LT(two_sample, 1.628 * std::sqrt(2.0 / m));
    const double deviation = sigma * std::sqrt(static_cast<double>(n));
    for (const std::vector<double>* sample : {&lazy, &one_by_one}) {
        std::vector<double> s = *sample;
        std::sort(s.begin(), s.end());
        double d = 0.0;
        for (size_t i = 0; i < s.size(); ++i) {
            const double F = 0.5 * std::erfc(-s[i] / (deviation * std::sqrt(2.0)));
            d = std::max({d, std::fabs(F - i / m), std::fabs(F - (i + 1) / m)});
        }
        EXPECT_LT(d, 1.628 / std::sqrt(m)) << (sample == &lazy ? "lazy" : "one by one");
    }
    std::printf("KS: lazy against one by one %.4f (limit %.4f)\n", two_sample,
                1.628 * std::sqrt(2.0 / m));
}

namespace {

// A target on [0, 1) of known shape: f(u) = 1 + 4 u + 9 on [0.2, 0.3), in K = 10 bins; the
// exact mean of f over bin j is 1 + 4 (j + 0.5) / K + 9 [j = 2].
constexpr int kBins = 10;
ChainValue step_target(PrimarySamples& x) {
    x.start_path();
    const float u = x.stream(0).uniform();
    const float f = 1.0f + 4.0f * u + (u >= 0.2f && u < 0.3f ? 9.0f : 0.0f);
    return {Color(f), static_cast<uint32_t>(std::min(static_cast<int>(u * kBins), kBins - 1))};
}
double step_bin_mean(int j) {
    return 1.0 + 4.0 * (j + 0.5) / kBins + (j == 2 ? 9.0 : 0.0);
}

// One estimate of every bin's mean of f: b times the splats in the bin, over the mutations per
// bin (as a pass of lesson 7 makes its image), from `chains` chains of `length` mutations.
std::vector<double> chain_histogram(const ChainTarget& target, uint64_t seed, int chains,
                                    int length, const ChainSettings& settings, ChainStart start,
                                    int bootstrap_count) {
    const Bootstrap boot = bootstrap(target, bootstrap_count, seed, 1, settings, 1);
    std::vector<double> bins(kBins, 0.0);
    for (int c = 0; c < chains; ++c) {
        const ChainRun run =
            run_chain(target, boot, 2, static_cast<uint64_t>(c), length, settings, start);
        for (const ChainSplat& s : run.splats) bins[s.pixel] += s.value.x;
    }
    const double scale = boot.b * kBins / (static_cast<double>(chains) * length);
    for (double& v : bins) v *= scale;
    return bins;
}

}  // namespace

TEST(Chain, OnAKnownOneDimensionalTargetItsSplatsFollowTheTarget) {
    // R = 32 independent runs (bootstrap, 4 chains of 2,000 mutations): each bin's mean over the
    // runs against the exact mean of f over the bin, a Student t with R - 1 degrees of freedom
    // each (one run's splats are correlated; the runs are not), and the sum of their squares as
    // a chi-square of K degrees (its p-value above 0.001), with each bin's t within the Sidak
    // limit over K bins.
    ChainSettings settings;
    settings.sigma = 0.05f;
    const int runs = 32;
    std::vector<std::vector<double>> per_bin(kBins);
    for (int r = 0; r < runs; ++r) {
        const std::vector<double> h =
            chain_histogram(step_target, 100 + r, 4, 2000, settings, ChainStart::Resampled, 256);
        for (int j = 0; j < kBins; ++j) per_bin[j].push_back(h[j]);
    }
    const double t_max = test::student_t_quantile(test::sidak(0.01, kBins), runs - 1);
    double chi2 = 0.0;
    for (int j = 0; j < kBins; ++j) {
        const test::MeanAndError m = test::mean_and_error(per_bin[j]);
        const double t = (m.mean - step_bin_mean(j)) / m.standard_error;
        chi2 += t * t;
        std::printf("bin %d: %.4f +- %.4f, exact %.4f, t %.2f\n", j, m.mean, m.standard_error,
                    step_bin_mean(j), t);
        EXPECT_LT(std::fabs(t), t_max) << "bin " << j;
    }
    EXPECT_GT(test::chi2_p_value(chi2, kBins), 0.001) << "chi-square " << chi2;
}

TEST(Chain, ANumberReadOnlyOnPartOfTheDomainDoesNotDrawTheChainThere) {
    // 50 stripes in u1; in every other one (B) f reads u2, 10 if u2 < 0.1 and 0.1 otherwise;
    // elsewhere (A) f = 1. So B holds 0.545 of the light, A 0.5. A small step from A into B must
    // move the state's own u2 (its value from when it was last read, moved since), and keep it
    // if the proposal is refused: drawing those moves afresh at each refusal gives every such
    // proposal a new chance at u2 < 0.1 and overfills B (as the lazy scheme without that rule
    // did: this test failed on it). Each part's estimate over R = 64 independent runs against
    // the exact one, Student's t, Sidak over the two.
    const ChainTarget target = [](PrimarySamples& x) {
        x.start_path();
        const float u1 = x.stream(0).uniform();
        if (std::fmod(50.0f * u1, 1.0f) >= 0.5f) return ChainValue{Color(1.0f), 1u};
        return ChainValue{Color(x.stream(1).uniform() < 0.1f ? 10.0f : 0.1f), 0u};
    };
    ChainSettings settings;
    settings.sigma = 0.03f;
    settings.large_step_probability = 0.1f;
    settings.streams = 2;
    const int runs = 64;
    std::vector<std::vector<double>> per_part(2);
    for (int r = 0; r < runs; ++r) {
        const std::vector<double> h =
            chain_histogram(target, 900 + r, 4, 4000, settings, ChainStart::Resampled, 256);
        for (int j = 0; j < 2; ++j) per_part[j].push_back(h[j] / kBins);  // the integral
    }
    const double t_max = test::student_t_quantile(test::sidak(0.01, 2), runs - 1);
    const double exact[2] = {0.545, 0.5};
    for (int j = 0; j < 2; ++j) {
        const test::MeanAndError m = test::mean_and_error(per_part[j]);
        const double t = (m.mean - exact[j]) / m.standard_error;
        std::printf("%s: %.4f +- %.4f, exact %.4f, t %.2f\n", j == 0 ? "B" : "A", m.mean,
                    m.standard_error, exact[j], t);
        EXPECT_LT(std::fabs(t), t_max) << (j == 0 ? "B" : "A");
    }
}

TEST(Chain, WithoutResamplingTheStartIsBiasedAndWithItItIsNot) {
    // f(u) = 100 on [0, 0.1), 1 elsewhere: nine tenths of the light in the first bin. Chains of
    // 4 mutations, mostly small steps, from starts picked uniformly among the bootstrap's states
    // spend their few steps where they began, mostly outside the bright bin: the first bin's
    // estimate is far too low (a start-up bias). Picked in proportion to f, the starts are
    // already distributed as the target, and the same short chains are unbiased.
    const ChainTarget target = [](PrimarySamples& x) {
        x.start_path();
        const float u = x.stream(0).uniform();
        return ChainValue{Color(u < 0.1f ? 100.0f : 1.0f), u < 0.1f ? 0u : 1u};
    };
    ChainSettings settings;
    settings.sigma = 0.01f;
    settings.large_step_probability = 0.05f;
    const double exact = 100.0;  // the mean of f over the first bin (of K = 10 equal bins)
    for (const ChainStart start : {ChainStart::Resampled, ChainStart::Uniform}) {
        std::vector<double> estimates;
        for (int r = 0; r < 64; ++r)
            estimates.push_back(chain_histogram(target, 500 + r, 64, 4, settings, start, 512)[0]);
        const test::MeanAndError m = test::mean_and_error(estimates);
        const double t = (m.mean - exact) / m.standard_error;
        std::printf("%s start: first bin %.3f +- %.3f (exact %.1f), t %.1f\n",
                    start == ChainStart::Resampled ? "resampled" : "uniform", m.mean,
                    m.standard_error, exact, t);
        if (start == ChainStart::Resampled)
            EXPECT_LT(std::fabs(t), test::student_t_quantile(0.01, 63));
        else
            EXPECT_LT(t, -10.0) << "a uniform start should show a start-up bias";
    }
}
