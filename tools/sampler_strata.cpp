// sampler_strata: how evenly each sampler spreads a pixel's first N samples, at every N (not only
// powers of two), one dimension at a time and in pairs of neighbouring dimensions
// (docs/performance.md, "The samplers at every sample count").
//
//   build/bin/sampler_strata [--max-n N] [--dims D] [--pixels P]
//
// For each dimension d: the widest gap the first N values leave in [0, 1) (around the circle),
// times N, the worst over N = 2 .. max-n and the pixels (a stratified dimension stays near 1-2;
// independent values reach about ln N and more). For each pair (d, d + 1): the fraction of the
// cells of a k x k grid, k = floor(sqrt(N)), that the first N samples leave empty, the mean over
// N = 4 .. max-n and the pixels (independent samples: about e^(-N / k^2), ~0.34; a well
// stratified pair: near 0).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sampling/rng.h"

using namespace lessons;

namespace {

// The first `n` values of dimension d of pixel `pixel`'s samples.
enum Kind { kIndependent, kKronecker, kSobol };
const char* const kNames[] = {"independent", "kronecker", "sobol"};

std::vector<float> values(Kind kind, uint64_t pixel, int d, int n) {
    std::vector<float> v;
    for (int s = 0; s < n; ++s) {
        Rng rng = kind == kKronecker ? Rng::kronecker(3, pixel, s)
                  : kind == kSobol   ? Rng::sobol(3, pixel, s)
                                     : Rng(3, pixel, s);
        float u = 0.0f;
        for (int e = 0; e <= d; ++e) u = rng.uniform();
        v.push_back(u);
    }
    return v;
}

double worst_gap(Kind kronecker, int d, int max_n, int pixels) {
    double worst = 0.0;
    for (int pixel = 0; pixel < pixels; ++pixel) {
        const std::vector<float> all = values(kronecker, pixel, d, max_n);
        std::vector<float> sorted;
        for (int n = 1; n <= max_n; ++n) {
            sorted.insert(std::upper_bound(sorted.begin(), sorted.end(), all[n - 1]), all[n - 1]);
            if (n < 2) continue;
            double gap = sorted.front() + 1.0 - sorted.back();
            for (size_t i = 1; i < sorted.size(); ++i) gap = std::max(gap, double(sorted[i] - sorted[i - 1]));
            worst = std::max(worst, n * gap);
        }
    }
    return worst;
}

double empty_cells(Kind kronecker, int d, int max_n, int pixels) {
    double sum = 0.0;
    int count = 0;
    for (int pixel = 0; pixel < pixels; ++pixel) {
        const std::vector<float> a = values(kronecker, pixel, d, max_n);
        const std::vector<float> b = values(kronecker, pixel, d + 1, max_n);
        for (int n = 4; n <= max_n; ++n) {
            const int k = static_cast<int>(std::floor(std::sqrt(static_cast<double>(n))));
            std::vector<char> hit(static_cast<size_t>(k) * k, 0);
            for (int s = 0; s < n; ++s)
                hit[std::min(k - 1, static_cast<int>(a[s] * k)) * k +
                    std::min(k - 1, static_cast<int>(b[s] * k))] = 1;
            sum += static_cast<double>(std::count(hit.begin(), hit.end(), 0)) / (k * k);
            ++count;
        }
    }
    return sum / count;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app("sampler_strata: the samplers' stratification at every sample count", "sampler_strata");
    int max_n = 512, dims = 16, pixels = 4;
    app.add_option("--max-n", max_n, "Largest sample count")->check(CLI::Range(4, 4096));
    app.add_option("--dims", dims, "Dimensions")->check(CLI::Range(2, Rng::kKroneckerDims));
    app.add_option("--pixels", pixels, "Pixels")->check(CLI::Range(1, 1024));
    CLI11_PARSE(app, argc, argv);
    std::printf("dimension");
    for (const char* name : kNames) std::printf(",%s_worst_n_gap", name);
    std::printf("\n");
    for (int d = 0; d < dims; ++d) {
        std::printf("%d", d);
        for (Kind k : {kIndependent, kKronecker, kSobol}) std::printf(",%.2f", worst_gap(k, d, max_n, pixels));
        std::printf("\n");
    }
    std::printf("\npair");
    for (const char* name : kNames) std::printf(",%s_empty_cells", name);
    std::printf("\n");
    for (int d = 0; d + 1 < dims; ++d) {
        std::printf("%d+%d", d, d + 1);
        for (Kind k : {kIndependent, kKronecker, kSobol}) std::printf(",%.3f", empty_cells(k, d, max_n, pixels));
        std::printf("\n");
    }
    return 0;
}
