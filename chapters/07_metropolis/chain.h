// Lesson 7, section 3: the Markov chain (Veach and Guibas, "Metropolis Light Transport",
// SIGGRAPH 1997; in primary sample space, Kelemen et al. 2002).
//
// The chain's states x are distributed, in the limit, in proportion to a target I(x) >= 0, the
// luminance of the state's contribution f(x): Metropolis-Hastings proposes y from x (a small or
// large step, primary_samples.h: both symmetric) and accepts it with probability
// a = min(1, I(y) / I(x)), which keeps detailed balance, I(x) T(x -> y) a(x -> y) =
// I(y) T(y -> x) a(y -> x), so I / b is the chain's stationary density, b = the integral of I.
// A pixel's value is then b times the expectation, under I / b, of f / I in that pixel: every
// proposal adds both outcomes with their expected weights (Veach 1997, 11.3.2; "expected-value
// splatting"), a f(y) / I(y) for y and (1 - a) f(x) / I(x) for x, so rejected proposals still
// count.
//
// b comes from a bootstrap: n independent states (large steps), b = the mean of I over them.
// Each chain starts from one of them, picked in proportion to its I
// (importance resampling): the start is then distributed as I / b already, so the chain has no
// start-up bias, and the image, b times the chains' mean, is an unbiased estimate of the true one
// for any chain length (with b estimated from the same n states: E[b g(X_0)] = the integral of
// I g, and the chain keeps I / b invariant).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "07_metropolis/primary_samples.h"
#include "geometry/math.h"

namespace lessons {

// What a chain explores: f(x) for the state x (lesson 7: a path's light), landing at a place of
// the image (a pixel; a bin of a histogram in the tests).
struct ChainValue {
    Color value{0.0f};
    uint32_t pixel = 0;
};
using ChainTarget = std::function<ChainValue(PrimarySamples& x)>;

struct ChainSettings {
    float sigma = 0.01f;  // the small step's standard deviation
    float large_step_probability = 0.3f;
    int streams = 1;  // the primary samples' streams
};

// The bootstrap: `count` independent states, state i's numbers from Rng(seed, stream_id, i), on
// `threads` threads (the same result for any number).
struct Bootstrap {
    uint64_t seed = 0, stream_id = 0;
    std::vector<double> importance;  // I of each state
    std::vector<double> cumulative;  // their running sums, in order
    double b = 0.0;                  // the mean of I
    uint64_t rays = 0;
    uint64_t non_finite = 0;  // states whose light was not finite (I = 0)
};
Bootstrap bootstrap(const ChainTarget& target, int count, uint64_t seed, uint64_t stream_id,
                    const ChainSettings& settings, int threads);

// How a chain starts: from a bootstrap state picked in proportion to I (no start-up bias), or,
// to show that bias, picked uniformly among those with I > 0.
enum class ChainStart { Resampled, Uniform };

struct ChainSplat {
    uint32_t pixel;
    Color value;  // f / I times the splat's weight: b / (mutations per pixel) turns it into light
};
struct ChainRun {
    std::vector<ChainSplat> splats;
    uint64_t proposed = 0, accepted = 0, large_proposed = 0, large_accepted = 0;
    uint64_t rays = 0;
    uint64_t non_finite = 0;  // proposals whose light was not finite: refused, not splatted
};

// Chain `index`: its start from the bootstrap, then `mutations` proposals, each splatting both
// outcomes. Its decisions (the start, each acceptance) come from Rng(seed, chain_stream,
// 2 index), its new numbers from Rng(seed, chain_stream, 2 index + 1). Stops early if `stop` is
// set. A bootstrap with b = 0 runs no chain.
ChainRun run_chain(const ChainTarget& target, const Bootstrap& boot, uint64_t chain_stream,
                   uint64_t index, int64_t mutations, const ChainSettings& settings,
                   ChainStart start = ChainStart::Resampled,
                   const std::atomic<bool>* stop = nullptr);

// The luminance a chain targets, as a double (0 for anything not finite).
double chain_importance(const Color& value);

}  // namespace lessons
