// The one random-number generator of the suite: PCG32 (O'Neill 2014), seeded per pixel and per
// sample so that an image does not depend on how pixels are shared among threads.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "geometry/math.h"
#include "sampling/random_numbers.h"

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

namespace detail {
// Sobol's dimension 1: for byte b of an index and each of its 256 values, the XOR of the
// generator columns v_{8b+j} (v_1 = 1/2, v_k = v_{k-1} XOR v_{k-1}/2) of its set bits j.
constexpr std::array<std::array<uint32_t, 256>, 4> sobol_byte_tables() {
    std::array<uint32_t, 32> column{};
    for (uint32_t k = 0, v = 1u << 31; k < 32; ++k, v ^= v >> 1) column[k] = v;
    std::array<std::array<uint32_t, 256>, 4> t{};
    for (int b = 0; b < 4; ++b)
        for (uint32_t x = 0; x < 256; ++x) {
            uint32_t bits = 0;
            for (int j = 0; j < 8; ++j)
                if ((x >> j) & 1u) bits ^= column[8 * b + j];
            t[b][x] = bits;
        }
    return t;
}
inline constexpr std::array<std::array<uint32_t, 256>, 4> kSobolByteTables = sobol_byte_tables();
}  // namespace detail

// Final, so that a call on an Rng itself (lessons 1 to 4, and every caller that holds one) is a
// direct call; lessons 5 and 6 take any RandomNumbers (random_numbers.h).
class Rng final : public RandomNumbers {
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

    // The same triple, drawn from a randomised Kronecker (Richtmyer) sequence instead: value d
    // of sample i is frac(shift_d + i alpha_d), with alpha_d = frac(sqrt(p_d)) for the d-th
    // prime and shift_d uniform, hashed from (seed, pixel, d) (a Cranley-Patterson rotation).
    // Every value is still uniform on [0, 1), so estimates stay unbiased, but the samples of one
    // pixel spread evenly over each dimension instead of clumping. Values past kKroneckerDims
    // come from PCG32. (--sampler kronecker; docs/performance.md.)
    // The first two values, which place the sample in its pixel, come from the first two
    // dimensions of Sobol's sequence instead, each XORed with a hash of (seed, pixel, d) (a
    // random digital shift, which keeps every value uniform): any first 2^k samples of a pixel
    // then form a (0, k, 2)-net, one point in each of the 2^k boxes of area 2^-k with power-of-
    // two sides. Across an edge in the image (a lamp's outline) the net's error falls faster
    // with the sample count than the lattice's.
    static Rng kronecker(uint64_t seed, uint64_t pixel_index, uint64_t sample_index) {
        Rng rng(seed, pixel_index, sample_index);
        rng.kronecker_ = true;
        rng.sample_ = sample_index;
        rng.key_ = mix_bits(seed ^ mix_bits(pixel_index ^ 0xd1b54a32d192ed03ULL));
        return rng;
    }
    static constexpr int kKroneckerDims = 64;
    static constexpr int kSobolDims = 2;

    // The same triple, drawn from Owen-scrambled Sobol points instead (--sampler sobol): values
    // 2j and 2j + 1 of sample i are the first two dimensions of Sobol's sequence at a shuffled
    // index, each scrambled. The shuffle and the scrambles are nested uniform scrambles (Owen
    // 1995) made by hashing (Burley, "Practical Hash-based Owen Scrambling", JCGT 2020), keyed by
    // (seed, pixel, pair): every value stays uniform, so estimates stay unbiased. Each pair's
    // first 2^k samples form a (0, k, 2)-net, for every k: the shuffle maps them onto an aligned
    // block of 2^k Sobol points, which is a net too. So every 2D sample a path takes (a light
    // sample's point, a BSDF direction) is stratified, at every sample count, and different
    // pairs are decorrelated by their different shuffles. Values past kSobolPairDims come from
    // PCG32. (docs/performance.md, "Pairs of dimensions".)
    static Rng sobol(uint64_t seed, uint64_t pixel_index, uint64_t sample_index) {
        Rng rng(seed, pixel_index, sample_index);
        rng.scrambled_sobol_ = true;
        rng.sample_ = sample_index;
        rng.key_ = mix_bits(seed ^ mix_bits(pixel_index ^ 0x94d049bb133111ebULL));
        return rng;
    }
    static constexpr int kSobolPairDims = 64;

    uint32_t next_u32() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
    }

    // Uniform in [0, 1): the top 24 bits scaled by 2^-24, so the largest value is 1 - 2^-24,
    // exactly representable and strictly below 1.
    float uniform() override {
        if (scrambled_sobol_ && dimension_ < kSobolPairDims) {
            // A pair's two values share their index and keys: both are made at its first.
            const int d = dimension_++;
            if (d & 1) return pair_second_;
            return scrambled_sobol_pair(d);
        }
        if (kronecker_ && dimension_ < kSobolDims) return sobol_value(dimension_++);
        if (kronecker_ && dimension_ < kKroneckerDims) return kronecker_value(dimension_++);
        return static_cast<float>(next_u32() >> 8) * 0x1p-24f;
    }

    // Two values for one 2D sample (a point on a light, a BSDF's direction, a point in the
    // pixel). With --sampler sobol they are one pair of the sequence, so stratified together:
    // after an odd number of values the next one is skipped, so that the pair starts at an even
    // dimension. The other samplers give the next two values.
    Vec2 uniform2() override {
        if (scrambled_sobol_ && (dimension_ & 1) && dimension_ < kSobolPairDims) ++dimension_;
        const float a = uniform();
        return {a, uniform()};
    }

private:
    // Dimension 0 of Sobol's sequence is the van der Corput sequence, sample i's bits mirrored
    // about the binary point; dimension 1 has the generator columns v_1 = 1/2,
    // v_k = v_{k-1} XOR v_{k-1}/2 (Pascal's triangle mod 2), XORed together for the bits set in i.
    float sobol_value(int d) const {
        const uint32_t bits =
            sobol_bits(static_cast<uint32_t>(sample_), d) ^
            static_cast<uint32_t>(mix_bits(key_ + static_cast<uint64_t>(d)) >> 32);
        return static_cast<float>(bits >> 8) * 0x1p-24f;
    }
    // Sobol's first two dimensions of index i, as 32-bit fractions; dimension 1 by a table of
    // the XOR of its columns for each value of each byte of i (four lookups, not 32 steps).
    static uint32_t sobol_bits(uint32_t i, int d) {
        if (d == 0) return reverse_bits(i);
        return detail::kSobolByteTables[0][i & 255u] ^
               detail::kSobolByteTables[1][(i >> 8) & 255u] ^
               detail::kSobolByteTables[2][(i >> 16) & 255u] ^ detail::kSobolByteTables[3][i >> 24];
    }

    static uint32_t reverse_bits(uint32_t b) {
        b = (b << 16) | (b >> 16);
        b = ((b & 0x00ff00ffu) << 8) | ((b & 0xff00ff00u) >> 8);
        b = ((b & 0x0f0f0f0fu) << 4) | ((b & 0xf0f0f0f0u) >> 4);
        b = ((b & 0x33333333u) << 2) | ((b & 0xccccccccu) >> 2);
        return ((b & 0x55555555u) << 1) | ((b & 0xaaaaaaaau) >> 1);
    }
    // A bijection of 32-bit words in which each bit changes only with the bits below it (adding
    // and multiplying by even numbers carry upwards), keyed by `seed` (Laine and Karras 2011).
    static uint32_t upward_permutation(uint32_t x, uint32_t seed) {
        x += seed;
        x ^= x * 0x6c50b47cu;
        x ^= x * 0xb82f1e52u;
        x ^= x * 0xc7afe638u;
        x ^= x * 0x8d22f6e6u;
        return x;
    }
    // A nested uniform scramble of a fraction's bits: each bit flips with the bits above it (more
    // significant), as Owen's scramble does; the same bijection applied to bit-reversed words.
    static uint32_t owen_scramble(uint32_t bits, uint32_t seed) {
        return reverse_bits(upward_permutation(reverse_bits(bits), seed));
    }
    // Values d and d + 1 (d even); returns the first and keeps the second in pair_second_.
    float scrambled_sobol_pair(int d) {
        const uint64_t pair_key = mix_bits(key_ + static_cast<uint64_t>(d / 2));
        // The shuffle: an Owen scramble of the index maps its first 2^k values onto an aligned
        // block of 2^k (the bits above k are flipped alike for all of them).
        const uint32_t index =
            owen_scramble(static_cast<uint32_t>(sample_), static_cast<uint32_t>(pair_key));
        const auto value = [&](int e) {
            const uint32_t bits = owen_scramble(sobol_bits(index, e),
                                                static_cast<uint32_t>(mix_bits(pair_key + 1 + e)));
            return static_cast<float>(bits >> 8) * 0x1p-24f;
        };
        pair_second_ = value(1);
        return value(0);
    }
    // In 64-bit fixed point, where frac() is the wrap-around of unsigned addition: the value's
    // bits are shift + i alpha modulo 2^64, and its top 24 bits the float.
    float kronecker_value(int d) const {
        const uint64_t shift = mix_bits(key_ + static_cast<uint64_t>(d));
        const uint64_t v = shift + sample_ * kronecker_alpha(d);
        return static_cast<float>(v >> 40) * 0x1p-24f;
    }
    // frac(sqrt(p)) for the first kKroneckerDims primes, times 2^64: irrational and independent
    // over the rationals, so every pair of dimensions is equidistributed.
    static uint64_t kronecker_alpha(int d) {
        static const auto alphas = [] {
            std::array<uint64_t, kKroneckerDims> a{};
            int found = 0;
            for (int n = 2; found < kKroneckerDims; ++n) {
                bool prime = true;
                for (int k = 2; k * k <= n; ++k) prime = prime && n % k != 0;
                if (!prime) continue;
                const double r = std::sqrt(static_cast<double>(n));
                a[found++] = static_cast<uint64_t>(std::ldexp(r - std::floor(r), 64));
            }
            return a;
        }();
        return alphas[d];
    }

    uint64_t state_ = 0;
    uint64_t inc_ = 1;
    bool kronecker_ = false;
    bool scrambled_sobol_ = false;
    int dimension_ = 0;
    float pair_second_ = 0.0f;  // (sobol) the second value of the pair begun last
    uint64_t sample_ = 0, key_ = 0;
};

}  // namespace lessons
