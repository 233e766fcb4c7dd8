// SIMD lanes for the 4-wide shape tests and the 8-wide BVH: vector types (GCC/Clang vector
// extensions) and the masks their comparisons give.
#pragma once

#include <limits>

#if defined(__SSE__)
#include <immintrin.h>
#endif

namespace lessons {

// Four floats in one SSE register (GCC/Clang vector extension): arithmetic and comparisons act on
// all four lanes at once, for a leaf's four triangles or quads.
using Float4 = float __attribute__((vector_size(16)));
// Eight floats in one AVX register, for the BVH's eight boxes.
using Float8 = float __attribute__((vector_size(32)));
// Four 32-bit integers, as Float4 converts to (bin indices, one per lane).
using Int4 = int __attribute__((vector_size(16)));
// Eight 32-bit integers (the build's bins: a count beside a box; unsigned where lanes are added,
// so that no sum overflows a signed type).
using Int8 = int __attribute__((vector_size(32)));
using UInt8 = unsigned __attribute__((vector_size(32)));

// A vector comparison gives -1 (all bits set) in each lane where it holds, else 0. lane_bits
// gathers them as bit i for lane i, for a loop over the lanes that hold: on x86 the movmskps
// instruction reads the lanes' sign bits (one for four lanes; for eight, one with AVX, two
// without); elsewhere a loop.
using Mask4 = decltype(Float4{} < Float4{});
using Mask8 = decltype(Float8{} < Float8{});
template <class Mask, int kLanes>
inline unsigned lane_bits_by_loop(const Mask& m) {
    unsigned bits = 0;
    for (int i = 0; i < kLanes; ++i) bits |= static_cast<unsigned>(m[i] & 1) << i;
    return bits;
}
inline unsigned lane_bits(const Mask4& m) {
#if defined(__SSE__)
    return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(m)));
#else
    return lane_bits_by_loop<Mask4, 4>(m);
#endif
}
inline unsigned lane_bits(const Mask8& m) {
#if defined(__AVX__)
    return static_cast<unsigned>(_mm256_movemask_ps(reinterpret_cast<__m256>(m)));
#elif defined(__SSE__)
    const Mask4 low = {m[0], m[1], m[2], m[3]}, high = {m[4], m[5], m[6], m[7]};
    return lane_bits(low) | lane_bits(high) << 4;
#else
    return lane_bits_by_loop<Mask8, 8>(m);
#endif
}

// next_float_up (geometry/math.h) in each lane, without a branch: a NaN or +inf stays, a zero
// (either sign) becomes the smallest denormal, a positive float's bits go up by one and a
// negative float's (-inf's too) down by one. The same bits as the scalar function, lane by lane
// (NextFloat.TheLanesStepAsTheScalarFunction); -next_floats_up(-v) is next_float_down's.
inline Float4 next_floats_up(const Float4& v) {
    using UInt4 = unsigned __attribute__((vector_size(16)));
    const UInt4 bits = __builtin_bit_cast(UInt4, v);
    const Float4 stepped = __builtin_bit_cast(Float4, v > 0.0f ? bits + 1u : bits - 1u);
    const Float4 moved = v == 0.0f ? Float4{} + std::numeric_limits<float>::denorm_min() : stepped;
    return ((v != v) | (v == std::numeric_limits<float>::infinity())) ? v : moved;
}

}  // namespace lessons
