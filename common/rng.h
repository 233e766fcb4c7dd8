// The one random-number generator of the suite: PCG32 (O'Neill 2014), seeded per pixel and per
// sample so that an image does not depend on how pixels are shared among threads.
#pragma once

#include <cstdint>

namespace lessons {

// 64-bit finaliser of SplitMix64 / MurmurHash3: turns structured integers (seed, pixel, sample)
// into well-mixed bits.
inline uint64_t mix_bits(uint64_t v) {
    v ^= v >> 31;
    v *= 0x7fb5d329728ea185ULL;
    v ^= v >> 27;
    v *= 0x81dadef4bc2dd44dULL;
    v ^= v >> 33;
    return v;
}

class Rng {
public:
    // A generator for one (seed, pixel, sample) triple. Streams differ per pixel, states per
    // sample, so no two pixel samples share a sequence.
    Rng(uint64_t seed, uint64_t pixel_index, uint64_t sample_index) {
        inc_ = (mix_bits(seed ^ mix_bits(pixel_index + 0x9e3779b97f4a7c15ULL)) << 1u) | 1u;
        state_ = 0;
        next_u32();
        state_ += mix_bits(sample_index ^ mix_bits(seed + pixel_index));
        next_u32();
    }
    explicit Rng(uint64_t seed = 0) : Rng(seed, 0, 0) {}

    uint32_t next_u32() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
    }

    // Uniform in [0, 1): the top 24 bits scaled by 2^-24, so the largest value is 1 - 2^-24,
    // exactly representable and strictly below 1.
    float uniform() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }

private:
    uint64_t state_ = 0;
    uint64_t inc_ = 1;
};

}  // namespace lessons
