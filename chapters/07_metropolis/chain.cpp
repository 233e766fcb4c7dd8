// Lesson 7, section 3: the Markov chain (see chain.h).
#include "07_metropolis/chain.h"

#include <algorithm>
#include <cmath>

#include "accel/parallel.h"
#include "scene/scene.h"

namespace lessons {

namespace {

// A uniform double in [0, 1) with 53 random bits.
double uniform_double(Rng& rng) {
    const uint64_t hi = rng.next_u32() >> 5, lo = rng.next_u32() >> 6;
    return static_cast<double>((hi << 26) | lo) * 0x1p-53;
}

// The bootstrap state a chain starts from.
size_t start_state(const Bootstrap& boot, Rng& rng, ChainStart start) {
    const size_t n = boot.importance.size();
    if (start == ChainStart::Resampled) {
        // In proportion to I: the first state whose running sum exceeds u times the total.
        const double target = uniform_double(rng) * boot.cumulative.back();
        const auto at = std::upper_bound(boot.cumulative.begin(), boot.cumulative.end(), target);
        size_t i = std::min(static_cast<size_t>(at - boot.cumulative.begin()), n - 1);
        while (boot.importance[i] <= 0.0 && i > 0) --i;  // u * total on a sum's last bit
        return i;
    }
    for (;;) {  // uniformly among the states with light (there is one: b > 0)
        const size_t i =
            std::min(static_cast<size_t>(uniform_double(rng) * static_cast<double>(n)), n - 1);
        if (boot.importance[i] > 0.0) return i;
    }
}

}  // namespace

double chain_importance(const Color& value) {
    const double I = static_cast<double>(luminance(value));
    return std::isfinite(I) && is_finite(value) && I > 0.0 ? I : 0.0;
}

Bootstrap bootstrap(const ChainTarget& target, int count, uint64_t seed, uint64_t stream_id,
                    const ChainSettings& settings, int threads) {
    Bootstrap boot;
    boot.seed = seed;
    boot.stream_id = stream_id;
    const size_t n = static_cast<size_t>(std::max(count, 1));
    boot.importance.assign(n, 0.0);
    const int parts = part_count(n, threads, 16);
    std::vector<uint64_t> rays(static_cast<size_t>(parts), 0), bad(static_cast<size_t>(parts), 0);
    parallel_parts(n, threads, 16, [&](size_t begin, size_t end, int part) {
        const uint64_t rays_before = rays_traced_by_this_thread();
        for (size_t i = begin; i < end; ++i) {
            PrimarySamples x(Rng(seed, stream_id, i), settings.sigma,
                             settings.large_step_probability, settings.streams);
            const Color value = target(x).value;
            boot.importance[i] = chain_importance(value);
            if (!is_finite(value)) ++bad[static_cast<size_t>(part)];
        }
        rays[static_cast<size_t>(part)] = rays_traced_by_this_thread() - rays_before;
    });
    boot.cumulative.resize(n);
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) boot.cumulative[i] = sum += boot.importance[i];
    boot.b = sum / static_cast<double>(n);
    for (int p = 0; p < parts; ++p) {
        boot.rays += rays[static_cast<size_t>(p)];
        boot.non_finite += bad[static_cast<size_t>(p)];
    }
    return boot;
}

ChainRun run_chain(const ChainTarget& target, const Bootstrap& boot, uint64_t chain_stream,
                   uint64_t index, int64_t mutations, const ChainSettings& settings,
                   ChainStart start, const std::atomic<bool>* stop) {
    ChainRun run;
    if (!(boot.b > 0.0) || mutations <= 0) return run;
    const uint64_t rays_before = rays_traced_by_this_thread();
    // The chain's decisions (its start, each acceptance) and its new numbers: two sequences.
    Rng decide(boot.seed, chain_stream, 2 * index);
    const size_t first = start_state(boot, decide, start);
    // The start: the bootstrap state replayed from its own numbers, then the chain's own.
    PrimarySamples x(Rng(boot.seed, boot.stream_id, first), settings.sigma,
                     settings.large_step_probability, settings.streams);
    ChainValue current = target(x);
    double I_current = chain_importance(current.value);
    x.set_fresh(Rng(boot.seed, chain_stream, 2 * index + 1));
    double held = 0.0;  // the weight the current state has gathered since it became current
    auto splat = [&](const ChainValue& v, double weight) {
        if (weight > 0.0) run.splats.push_back({v.pixel, v.value * static_cast<float>(weight)});
    };
    for (int64_t m = 0; m < mutations; ++m) {
        if (stop && (m & 255) == 0 && stop->load()) break;
        const bool large = x.propose();
        ++run.proposed;
        run.large_proposed += large;
        const ChainValue proposal = target(x);
        const double I_proposal = chain_importance(proposal.value);
        if (!is_finite(proposal.value)) ++run.non_finite;
        const double a = I_current > 0.0 ? std::min(1.0, I_proposal / I_current) : 1.0;
        // Expected values: the proposal's share now, the current state's when it is left.
        if (I_proposal > 0.0) splat(proposal, a / I_proposal);
        held += 1.0 - a;
        if (uniform_double(decide) < a) {
            if (I_current > 0.0) splat(current, held / I_current);
            current = proposal;
            I_current = I_proposal;
            held = 0.0;
            x.accept();
            ++run.accepted;
            run.large_accepted += large;
        } else {
            x.reject();
        }
    }
    if (I_current > 0.0) splat(current, held / I_current);
    run.rays = rays_traced_by_this_thread() - rays_before;
    return run;
}

}  // namespace lessons
