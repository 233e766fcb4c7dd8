// Where a random walk draws its numbers from: the seam between a light-transport algorithm and
// the numbers that drive it. Lessons 1 to 6 draw them from Rng (rng.h), fresh for every pixel
// sample. Lesson 7 (Metropolis light transport) draws them from a primary-sample-space state
// that replays, mutates and restores them (chapters/07_metropolis/primary_samples.h), so that
// the same walk code makes a path from any vector of numbers in [0, 1). A walk written against
// this interface neither knows nor cares which: it asks for one number or a pair.
#pragma once

#include "geometry/math.h"

namespace lessons {

class RandomNumbers {
public:
    virtual ~RandomNumbers() = default;
    // The next number, uniform in [0, 1).
    virtual float uniform() = 0;
    // The next two, for one 2D sample (a point on a light, a BSDF's direction): a source that
    // stratifies pairs (Rng's Sobol sampler) keeps them one pair.
    virtual Vec2 uniform2() = 0;

protected:
    RandomNumbers() = default;
    RandomNumbers(const RandomNumbers&) = default;
    RandomNumbers& operator=(const RandomNumbers&) = default;
};

}  // namespace lessons
