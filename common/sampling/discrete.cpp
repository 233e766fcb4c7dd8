// Discrete choices on the grid of the uniform numbers (see discrete.h).
#include "sampling/discrete.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lessons {

namespace {
constexpr int64_t kUnits = int64_t{1} << 24;  // the uniform numbers' grid: 2^-24
constexpr float kUnit = 0x1p-24f;
}  // namespace

void build_choice_cdf(std::span<const double> weights, std::span<float> cdf) {
    const size_t n = weights.size();
    if (n == 0) return;
    double total = 0.0;
    size_t positive = 0;
    for (double w : weights) {
        total += w;
        positive += w > 0.0 ? 1 : 0;
    }
    std::vector<int64_t> c(n);
    if (!(total > 0.0) || !std::isfinite(total)) {  // nothing to weigh by: uniform
        for (size_t i = 0; i < n; ++i)
            c[i] = static_cast<int64_t>(std::llround(static_cast<double>(i + 1) * kUnits / n));
    } else {
        // The running share rounded to the nearest unit (the sum taken in the order `total`
        // was, so that the last positive entry lands on exactly kUnits) ...
        double running = 0.0;
        for (size_t i = 0; i < n; ++i) {
            running += weights[i];
            c[i] = std::llround(running / total * static_cast<double>(kUnits));
        }
        // ... then at least one unit for every entry of positive weight, where there are units
        // enough: a forward pass raises an entry that got none (which may push the table past
        // kUnits), a backward pass from kUnits lowers the entries below it, each keeping one
        // unit per positive entry after it (so none loses its unit again).
        if (positive <= static_cast<size_t>(kUnits)) {
            for (size_t i = 0; i < n; ++i) {
                const int64_t before = i > 0 ? c[i - 1] : 0;
                c[i] = std::max(c[i], before + (weights[i] > 0.0 ? 1 : 0));
            }
            c[n - 1] = kUnits;
            for (size_t i = n - 1; i-- > 0;)
                c[i] = std::min(c[i], c[i + 1] - (weights[i + 1] > 0.0 ? 1 : 0));
        }
    }
    c[n - 1] = kUnits;
    for (size_t i = 0; i < n; ++i)
        cdf[i] = static_cast<float>(std::clamp<int64_t>(c[i], 0, kUnits)) * kUnit;
}

std::vector<float> choice_cdf(std::span<const double> weights) {
    std::vector<float> cdf(weights.size());
    build_choice_cdf(weights, cdf);
    return cdf;
}

size_t choose_entry(std::span<const float> cdf, float u, float* rest) {
    const size_t n = cdf.size();
    const size_t k = std::min<size_t>(
        static_cast<size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()), n - 1);
    if (rest) {
        const float lo = k > 0 ? cdf[k - 1] : 0.0f, hi = cdf[k];
        *rest =
            hi > lo ? std::clamp((u - lo + 0.5f * kUnit) / (hi - lo), 0.0f, 0x1.fffffep-1f) : 0.5f;
    }
    return k;
}

}  // namespace lessons
