// A discrete choice by one uniform number: which light (lights/lights.h), which row and column of
// an environment map (scene/environment.h). The choice probabilities are proportional to
// non-negative weights, held as a cumulative table (CDF) of floats.
//
// Every uniform number the samplers make is a multiple of 2^-24 in [0, 1) (sampling/rng.h). So
// the table's entries are put on that grid too: each is an integer number of units of 2^-24,
// and then the probability an entry is chosen with, its units times 2^-24, is exactly the
// difference of two table entries, the number the estimators divide by. A table built from
// shares rounded to floats could not promise that: beside an entry of weight 1e8, one of weight
// 1 would get the same float on both sides (a probability of 0, never chosen), though light
// still arrives from it by other paths, and an estimator that weighs those paths against its
// choice (lesson 5's MIS) would lose that light.
//
// Hence the rule: every entry of positive weight gets at least one unit (probability >= 2^-24),
// the shares of the others rounded to the nearest unit as the running sum goes, the total
// exactly 1. An entry of zero weight gets no unit (it is never chosen, and sends nothing to find).
// This needs at most 2^24 entries of positive weight (16,777,216 lights, or texels in one row);
// beyond that the floor is not applied, and any entry whose share rounds to no unit keeps
// probability 0, which the estimators treat as "this strategy cannot make the path" (lesson 5's
// mis.cpp). All weights zero: a uniform choice.
//
// The rest of u within the chosen entry (for reuse, as the environment map places a point in
// its texel) takes as many values as the entry has units: the middle of each, so that an entry
// of one unit is sampled at its centre rather than on its edge.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace lessons {

// The cumulative table of `weights` (each finite and >= 0) on the 2^-24 grid; its last entry
// is 1. Writes weights.size() entries to `cdf`.
void build_choice_cdf(std::span<const double> weights, std::span<float> cdf);
std::vector<float> choice_cdf(std::span<const double> weights);

// The entry a uniform number u in [0, 1) picks: the first whose cumulative value exceeds u.
// With `rest`, u rescaled to [0, 1) within the entry's interval, for reuse as a fresh number.
size_t choose_entry(std::span<const float> cdf, float u, float* rest = nullptr);

// The probability that choose_entry picks entry i (exact, as explained above).
inline float entry_probability(std::span<const float> cdf, size_t i) {
    return cdf[i] - (i > 0 ? cdf[i - 1] : 0.0f);
}

}  // namespace lessons
