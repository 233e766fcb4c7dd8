// Lesson 7, Metropolis light transport (chapters/07_metropolis): the primary samples (a
// rejected proposal restores every number bit for bit; skipped small steps applied lazily have
// the distribution of steps applied one by one), the chain on a one-dimensional target of known
// shape (its splats follow the target; without the bootstrap's resampling a start-up bias shows
// and with it none does), the furnace in closed form with b, lesson 5's images pixel by pixel
// (with large steps only, and with the default mutations), and the same bits for any number of
// threads and for a render split into parts (docs/accuracy.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "05_bidirectional/bidirectional.h"
#include "07_metropolis/chain.h"
#include "07_metropolis/metropolis.h"
#include "07_metropolis/multiplexed.h"
#include "07_metropolis/primary_samples.h"
#include "io/scene_file.h"
#include "render/progressive.h"
#include "statistics.h"
#include "test_util.h"

using namespace lessons;

namespace {

bool same_bits(const Image& a, const Image& b) {
    return a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Color)) == 0;
}

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
    // A chain's state after accepted small and large steps; then proposals of each kind that
    // read the state's numbers and more (a longer path), rejected: every entry, value and age,
    // is as before, and the numbers read for the first time are unmade again.
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
    for (const bool want_large : {false, true}) {
        const std::vector<PrimarySamples::Entry> before = x.entries();
        const int64_t iteration = x.iteration();
        // Propose until the step is of the kind wanted (rejecting the others unread).
        while (x.propose() != want_large) x.reject();
        read_path(x, 12);
        const std::vector<PrimarySamples::Entry> during = x.entries();
        size_t changed = 0;
        for (size_t i = 0; i < before.size(); ++i) changed += !same_entry(before[i], during[i]);
        EXPECT_GT(changed, before.size() / 2) << "the proposal changed the numbers it read";
        x.reject();
        EXPECT_EQ(x.iteration(), iteration);
        const std::vector<PrimarySamples::Entry> after = x.entries();
        ASSERT_GE(after.size(), before.size());
        for (size_t i = 0; i < before.size(); ++i)
            EXPECT_TRUE(same_entry(before[i], after[i]))
                << (want_large ? "large" : "small") << " step, entry " << i;
        for (size_t i = before.size(); i < after.size(); ++i)
            EXPECT_EQ(after[i].changed, -1) << "entry " << i << " was first made by the proposal";
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

namespace {

RenderSettings independent(uint64_t seed, int threads = 0) {
    RenderSettings settings = test::quiet_settings(seed, threads);
    settings.sampler = RenderSettings::Sampler::Independent;
    return settings;
}

double image_average(const Image& image) {
    double sum = 0.0;
    for (const Color& c : image.pixels) sum += static_cast<double>(luminance(c));
    return sum / static_cast<double>(image.pixels.size());
}

Scene small_scene(const char* name, int width, int height) {
    return load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/" + name, {width, height});
}

}  // namespace

TEST(Metropolis, TheFurnaceIsItsClosedFormAndBIsTheImageMean) {
    // Inside a sphere that emits L_e = 1 and reflects rho = 0.5, every pixel sees L_e / (1 - rho)
    // = 2, and with at most 3 segments L_e (1 - rho^3) / (1 - rho) = 1.75. Each lesson 7 render
    // (8 passes of 16 x 16 pixels) from its own seed is independent of the others: over K = 8
    // seeds, the image mean and the bootstrap's b (the image's mean luminance) against the
    // closed form, by Student's t with 7 degrees (Sidak over the 4 tests).
    const float rho = 0.5f, Le = 1.0f;
    Scene scene = test::furnace(rho, Le);
    scene.width = scene.height = 16;
    const double t_max = test::student_t_quantile(test::sidak(0.01, 4), 7);
    for (const int max_depth : {0, 3}) {
        const double expected =
            max_depth == 0 ? Le / (1.0 - rho) : Le * (1.0 - std::pow(rho, 3.0)) / (1.0 - rho);
        MetropolisOptions options;
        options.max_depth = max_depth;
        std::vector<double> means, bs;
        for (int seed = 0; seed < 8; ++seed) {
            const MetropolisModel model(scene, options);
            const RenderResult r = render_scene(scene, model, 8, independent(300 + seed));
            EXPECT_EQ(r.nan_samples + r.inf_samples, 0u);
            means.push_back(image_average(r.image));
            bs.push_back(model.mean_b());
        }
        const test::MeanAndError m = test::mean_and_error(means), b = test::mean_and_error(bs);
        std::printf("depth %d: image %.5f +- %.5f, b %.5f +- %.5f, expected %.5f\n", max_depth,
                    m.mean, m.standard_error, b.mean, b.standard_error, expected);
        EXPECT_LT(std::fabs(m.mean - expected) / m.standard_error, t_max) << "depth " << max_depth;
        EXPECT_LT(std::fabs(b.mean - expected) / b.standard_error, t_max) << "depth " << max_depth;
    }
}

namespace {

// Per pixel, K independent lesson 7 renders against one long lesson 5 render: the difference of
// means over its standard error (lesson 7's across the K seeds, lesson 5's from its film), each
// channel; returns the largest |t| and the image means.
struct PixelAgreement {
    double worst_t = 0.0, mean7 = 0.0, mean5 = 0.0, se7 = 0.0;
    size_t worst_pixel = 0;
    std::array<double, 4> worst{};  // there: lesson 7's mean and error, lesson 5's
};
PixelAgreement against_lesson_five(const Scene& scene, const MetropolisOptions& options, int K,
                                   int passes, const RenderResult& five) {
    const size_t n = five.image.pixels.size();
    std::vector<std::vector<double>> runs(n * 3);
    std::vector<double> means;
    for (int seed = 0; seed < K; ++seed) {
        const MetropolisModel model(scene, options);
        const RenderResult r = render_scene(scene, model, passes, independent(700 + seed));
        EXPECT_EQ(r.nan_samples + r.inf_samples, 0u);
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) runs[3 * i + c].push_back(r.image.pixels[i][c]);
        means.push_back(image_average(r.image));
    }
    PixelAgreement a;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            const test::MeanAndError m = test::mean_and_error(runs[3 * i + c]);
            const double se5 = std::sqrt(static_cast<double>(five.variance.pixels[i][c]));
            const double se = std::sqrt(m.standard_error * m.standard_error + se5 * se5);
            const double d = m.mean - static_cast<double>(five.image.pixels[i][c]);
            if (se > 0.0) {
                if (std::fabs(d) / se > a.worst_t) {
                    a.worst_t = std::fabs(d) / se;
                    a.worst_pixel = i;
                    a.worst = {m.mean, m.standard_error, five.image.pixels[i][c], se5};
                }
            } else {
                EXPECT_EQ(d, 0.0) << "pixel " << i;
            }
        }
    const test::MeanAndError m = test::mean_and_error(means);
    a.mean7 = m.mean;
    a.se7 = m.standard_error;
    a.mean5 = image_average(five.image);
    return a;
}

}  // namespace

TEST(Metropolis, AgreesWithLessonFivePixelByPixelOnTheCornellBox) {
    // The Cornell box at 16 x 16: lesson 5 at 8,192 spp; lesson 7 over K = 16 seeds of 256
    // passes (a pass's image is far from normal in a dim pixel, which a chain visits in a few
    // clumps or not at all; the mean of 256 independent passes is close to normal), with large
    // steps only (every state an independent path: lesson 5's strategies
    // drawn one at a time) and with the defaults (mostly small steps). Each pixel and channel's
    // difference over its standard error within Student's t with 15 degrees at 0.01, Sidak over
    // every pixel and channel; the image means agree too.
    const Scene scene = small_scene("cornell_box.toml", 16, 16);
    const BidirectionalModel five_model(scene, BidirOptions{});
    const RenderResult five = render_scene(scene, five_model, 8192, independent(77));
    const int K = 16;
    const double t_max = test::student_t_quantile(
        test::sidak(0.01, static_cast<int>(3 * five.image.pixels.size())), K - 1);
    for (const float large : {1.0f, 0.3f}) {
        MetropolisOptions options;
        options.large_step_probability = large;
        const PixelAgreement a = against_lesson_five(scene, options, K, 256, five);
        std::printf(
            "large steps %.1f: worst pixel t %.2f (limit %.2f); image mean %.5f +- %.5f "
            "against lesson 5's %.5f\n",
            large, a.worst_t, t_max, a.mean7, a.se7, a.mean5);
        EXPECT_LT(a.worst_t, t_max)
            << "large-step probability " << large << ", pixel " << a.worst_pixel << ": lesson 7 "
            << a.worst[0] << " +- " << a.worst[1] << ", lesson 5 " << a.worst[2] << " +- "
            << a.worst[3];
        EXPECT_LT(std::fabs(a.mean7 - a.mean5) / a.se7, test::student_t_quantile(0.01, K - 1));
    }
}

TEST(Metropolis, IsTheSameForAnyNumberOfThreadsAndForPartsMerged) {
    // The chains of a pass are fixed in number and each draws from (seed, pass, chain); their
    // splats are summed in chain order. So 1, 2 and 3 threads give the same bits, and a render
    // split into passes [0, 2) and [2, 4), each with a model of its own, merges into the single
    // run's films exactly.
    const Scene scene = small_scene("cornell_spheres.toml", 32, 24);
    const MetropolisOptions options;
    std::vector<RenderResult> results;
    for (const int threads : {1, 2, 3})
        results.push_back(
            render_scene(scene, MetropolisModel(scene, options), 4, independent(5, threads)));
    EXPECT_GT(image_average(results[0].image), 0.0);
    for (size_t k = 1; k < results.size(); ++k) {
        EXPECT_TRUE(same_bits(results[0].image, results[k].image)) << k + 1 << " threads";
        EXPECT_TRUE(same_bits(results[0].variance, results[k].variance)) << k + 1 << " threads";
    }
    const RenderSettings settings = independent(5);
    const MetropolisModel single_model(scene, options);
    ProgressiveFilms single(scene, single_model, 0.0f);
    ASSERT_TRUE(single.render_to(4, settings));
    std::vector<Film> merged;
    for (const int first : {0, 2}) {
        const MetropolisModel part_model(scene, options);
        RenderPart part;
        part.first_sample = first;
        ProgressiveFilms films(scene, part_model, 0.0f, part);
        ASSERT_TRUE(films.render_to(2, settings));
        if (merged.empty())
            merged = films.films();
        else
            merged[0].add(films.films()[0]);
    }
    EXPECT_TRUE(same_bits(single.films()[0].mean(), merged[0].mean()));
    EXPECT_TRUE(same_bits(single.films()[0].mean(), results[0].image));
}
