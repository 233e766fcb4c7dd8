// Frames, the random-number generator and bounding boxes.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include "geometry/bounds.h"
#include "geometry/math.h"
#include "geometry/simd.h"
#include "sampling/rng.h"
#include "test_util.h"

using namespace lessons;

TEST(Frame, IsOrthonormalForEveryNormalIncludingTheHardOnes) {
    Rng rng(1);
    std::vector<Vec3> normals = {{0, 0, 1},
                                 {0, 0, -1},
                                 {1, 0, 0},
                                 {0, -1, 0},
                                 glm::normalize(Vec3(1e-7f, 0, -1)),
                                 glm::normalize(Vec3(0, 1e-7f, -1))};
    for (int i = 0; i < 10000; ++i) normals.push_back(test::random_unit_vector(rng));
    for (const Vec3& n : normals) {
        const Frame f(n);
        EXPECT_NEAR(glm::length(f.s), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::length(f.t), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(f.s, f.t), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(f.s, f.n), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(f.t, f.n), 0.0f, 1e-5f);
        // Right-handed: s x t = n, so local z is the normal.
        EXPECT_NEAR(glm::dot(glm::cross(f.s, f.t), n), 1.0f, 1e-5f);
        const Vec3 v = test::random_unit_vector(rng);
        const Vec3 back = f.to_world(f.to_local(v));
        EXPECT_NEAR(glm::length(back - v), 0.0f, 1e-5f);
        EXPECT_NEAR(f.to_local(n).z, 1.0f, 1e-5f);
    }
}

TEST(Rng, UniformIsInHalfOpenUnitIntervalWithMeanOneHalf) {
    Rng rng(42, 7, 3);
    double sum = 0.0;
    const int n = 1000000;
    for (int i = 0; i < n; ++i) {
        const float u = rng.uniform();
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
        sum += u;
    }
    // Standard error of the mean of U(0,1): sqrt(1/12 / n) = 2.9e-4; allow 5 sigma.
    EXPECT_NEAR(sum / n, 0.5, 5 * 2.9e-4);
}

TEST(Rng, DifferentPixelsAndSamplesGiveDifferentSequences) {
    std::set<uint32_t> first_values;
    for (uint64_t pixel = 0; pixel < 100; ++pixel)
        for (uint64_t sample = 0; sample < 100; ++sample)
            first_values.insert(Rng(0, pixel, sample).next_u32());
    // 10^4 draws from 2^32 values: a collision is unlikely (p ~ 1.2%); allow a few.
    EXPECT_GE(first_values.size(), 9995u);
    EXPECT_EQ(Rng(5, 1, 2).next_u32(), Rng(5, 1, 2).next_u32());
}

TEST(Rng, KroneckerSamplesStaySpreadAtEverySampleCountNotOnlyPowersOfTwo) {
    // --time stops at any sample count, so the stratification must hold at every N, not only at
    // powers of two. For every N from 2 to 512 and each of the first 16 dimensions, the widest
    // gap the first N samples leave in [0, 1) (around the circle) times N: Sobol's dimensions
    // (0 and 1, (0, 1)-sequences) stay at most 2 (every dyadic interval of length 2^-k,
    // 2^k <= N, holds a point), Kronecker's at most 6 (measured on this seed: 4.7 at worst, in
    // dimension 15); N independent values leave about ln N (6.2 at N = 512), often twice that.
    double worst_sobol = 0.0, worst_kronecker = 0.0, worst_independent = 0.0;
    for (uint64_t pixel = 0; pixel < 4; ++pixel)
        for (int d = 0; d < 16; ++d) {
            std::vector<float> k, r;  // kept sorted: the first N values
            for (int n = 1; n <= 512; ++n) {
                Rng a = Rng::kronecker(3, pixel, n - 1), b(3, pixel, n - 1);
                float u = 0.0f, v = 0.0f;
                for (int e = 0; e <= d; ++e) {
                    u = a.uniform();
                    v = b.uniform();
                }
                k.insert(std::upper_bound(k.begin(), k.end(), u), u);
                r.insert(std::upper_bound(r.begin(), r.end(), v), v);
                if (n < 2) continue;
                auto widest = [](const std::vector<float>& w) {
                    double gap = w.front() + 1.0 - w.back();
                    for (size_t i = 1; i < w.size(); ++i) gap = std::max(gap, double(w[i] - w[i - 1]));
                    return gap;
                };
                (d < Rng::kSobolDims ? worst_sobol : worst_kronecker) =
                    std::max(d < Rng::kSobolDims ? worst_sobol : worst_kronecker, n * widest(k));
                worst_independent = std::max(worst_independent, n * widest(r));
            }
        }
    EXPECT_LE(worst_sobol, 2.0 + 1e-5);
    EXPECT_LE(worst_kronecker, 6.0);
    EXPECT_GT(worst_independent, 8.0);  // the test tells the two apart
}

TEST(Rng, SobolSamplesStratifyEveryPairTheyDrawAtEverySampleCount) {
    // Rng::sobol draws values in pairs (2j, 2j + 1). For a pair, the share of a k x k grid,
    // k = floor(sqrt(N)), that the first N samples leave empty, as a mean over N = 4 .. 256 and
    // 4 pixels: independent samples leave about 0.34; the pairs Rng::sobol draws leave about 0.19
    // (each prefix of 2^k is a (0, k, 2)-net), and its other neighbours (2j + 1, 2j + 2), which
    // no sample takes together, are as good as independent ones. (Rng::kronecker's pair (2, 3)
    // leaves 0.62: build/bin/sampler_strata, docs/performance.md.) Each value also stays spread
    // on its own: the widest gap times N at most 4 at every N (independent values: about 10).
    auto value = [](bool sobol, uint64_t pixel, int s, int d) {
        Rng rng = sobol ? Rng::sobol(5, pixel, s) : Rng(5, pixel, s);
        float u = 0.0f;
        for (int e = 0; e <= d; ++e) u = rng.uniform();
        return u;
    };
    auto empty_share = [&](bool sobol, int d) {
        double sum = 0.0;
        int count = 0;
        for (uint64_t pixel = 0; pixel < 4; ++pixel)
            for (int n = 4; n <= 256; ++n) {
                const int k = static_cast<int>(std::floor(std::sqrt(static_cast<double>(n))));
                std::vector<char> hit(static_cast<size_t>(k) * k, 0);
                for (int s = 0; s < n; ++s)
                    hit[std::min(k - 1, static_cast<int>(value(sobol, pixel, s, d) * k)) * k +
                        std::min(k - 1, static_cast<int>(value(sobol, pixel, s, d + 1) * k))] = 1;
                sum += static_cast<double>(std::count(hit.begin(), hit.end(), 0)) / (k * k);
                ++count;
            }
        return sum / count;
    };
    for (int d : {0, 2, 4, 10}) {
        EXPECT_LT(empty_share(true, d), 0.23) << "pair " << d << ", " << d + 1;
        EXPECT_GT(empty_share(false, d), 0.30) << "independent pair " << d << ", " << d + 1;
    }
    for (int d : {1, 3}) EXPECT_LT(empty_share(true, d), 0.37) << "pair " << d << ", " << d + 1;
    double worst = 0.0;
    for (uint64_t pixel = 0; pixel < 4; ++pixel)
        for (int d = 0; d < 8; ++d) {
            std::vector<float> sorted;
            for (int n = 1; n <= 256; ++n) {
                const float u = value(true, pixel, n - 1, d);
                ASSERT_GE(u, 0.0f);
                ASSERT_LT(u, 1.0f);
                sorted.insert(std::upper_bound(sorted.begin(), sorted.end(), u), u);
                if (n < 2) continue;
                double gap = sorted.front() + 1.0 - sorted.back();
                for (size_t i = 1; i < sorted.size(); ++i) gap = std::max(gap, double(sorted[i] - sorted[i - 1]));
                worst = std::max(worst, n * gap);
            }
        }
    EXPECT_LE(worst, 4.0);
}

TEST(Rng, Uniform2TakesOneSobolPairWhateverWasDrawnBefore) {
    // A path vertex draws one value (which light), a 2D sample (the point on it) and another
    // (the BSDF's direction); here two vertices, each with a skip before its light's point (in
    // the render, Russian roulette adds one value per vertex from the fourth on). With Rng::sobol,
    // uniform2() skips a value after an odd number of them, so that each 2D sample is one pair
    // of the sequence: the first 64 samples of a pixel then put exactly one point in each cell
    // of an 8 x 8 grid (a (0, 6, 2)-net). Two values taken one by one after an odd count
    // straddle two pairs and do not (the test's contrast). The other samplers give the next
    // two values, as before.
    auto one_per_cell = [](const std::vector<Vec2>& points) {
        std::vector<int> count(64, 0);
        for (const Vec2& p : points)
            ++count[std::min(7, static_cast<int>(p.x * 8)) * 8 +
                    std::min(7, static_cast<int>(p.y * 8))];
        return std::all_of(count.begin(), count.end(), [](int c) { return c == 1; });
    };
    for (uint64_t pixel = 0; pixel < 4; ++pixel) {
        std::vector<std::vector<Vec2>> pairs(4);
        std::vector<Vec2> straddling;
        for (int s = 0; s < 64; ++s) {
            Rng rng = Rng::sobol(9, pixel, s);
            rng.uniform2();                      // the position in the pixel
            rng.uniform();                       // which light
            pairs[0].push_back(rng.uniform2());  // the point on it
            pairs[1].push_back(rng.uniform2());  // the BSDF's direction
            rng.uniform();                       // the next vertex: which light
            pairs[2].push_back(rng.uniform2());
            pairs[3].push_back(rng.uniform2());
            Rng odd = Rng::sobol(9, pixel, s);
            for (int k = 0; k < 3; ++k) odd.uniform();
            const float a = odd.uniform();
            straddling.push_back({a, odd.uniform()});
        }
        for (size_t k = 0; k < pairs.size(); ++k)
            EXPECT_TRUE(one_per_cell(pairs[k])) << "pixel " << pixel << ", 2D sample " << k;
        EXPECT_FALSE(one_per_cell(straddling)) << "pixel " << pixel;
    }
    for (Rng (*make)(uint64_t, uint64_t, uint64_t) :
         {&Rng::kronecker, +[](uint64_t a, uint64_t b, uint64_t c) { return Rng(a, b, c); }}) {
        Rng a = make(9, 1, 5), b = make(9, 1, 5);
        a.uniform();
        b.uniform();
        const Vec2 pair = a.uniform2();
        EXPECT_EQ(pair.x, b.uniform());
        EXPECT_EQ(pair.y, b.uniform());
    }
}

TEST(Rng, KroneckerSamplesOfAPixelSpreadEvenly) {
    // 64 samples of one pixel: in each of the first four dimensions the sampler's values (Sobol's
    // in the first two, Kronecker's in the next) leave no gap in [0, 1) wider than 4/64 (three-gap
    // theorem: frac(sqrt(p)) has small continued-fraction terms); independent values leave gaps of
    // about ln(64)/64 ~ 4.2/64 on average, often far more.
    int independent_wide = 0;
    for (uint64_t pixel = 0; pixel < 50; ++pixel) {
        std::vector<std::vector<float>> kronecker(4), independent(4);
        for (uint64_t s = 0; s < 64; ++s) {
            Rng k = Rng::kronecker(3, pixel, s), r(3, pixel, s);
            for (int d = 0; d < 4; ++d) {
                kronecker[d].push_back(k.uniform());
                independent[d].push_back(r.uniform());
            }
        }
        auto widest_gap = [](std::vector<float> v) {
            std::sort(v.begin(), v.end());
            float gap = v.front() + 1.0f - v.back();  // around the circle
            for (size_t i = 1; i < v.size(); ++i) gap = std::max(gap, v[i] - v[i - 1]);
            return gap;
        };
        for (int d = 0; d < 4; ++d) {
            for (float u : kronecker[d]) {
                ASSERT_GE(u, 0.0f);
                ASSERT_LT(u, 1.0f);
            }
            EXPECT_LT(widest_gap(kronecker[d]), 4.0f / 64.0f) << "pixel " << pixel << " dim " << d;
            independent_wide += widest_gap(independent[d]) >= 4.0f / 64.0f;
        }
    }
    EXPECT_GT(independent_wide, 100);  // of 200: the test tells the two apart
    // Past kKroneckerDims the values come from PCG32, and the same triple repeats exactly.
    Rng a = Rng::kronecker(1, 2, 3), b = Rng::kronecker(1, 2, 3);
    for (int i = 0; i < Rng::kKroneckerDims + 10; ++i) ASSERT_EQ(a.uniform(), b.uniform());
}

TEST(NextFloat, StepsAsStdNextafterDoesEverywhere) {
    // Ray origins step one float off the surface with next_float_up/down, an inline bit
    // manipulation: it must give std::nextafter's bits for zeros of both signs, denormals, the
    // largest floats, infinities and ordinary values of every sign and exponent; NaN stays NaN.
    const float max = std::numeric_limits<float>::max();
    const float tiny = std::numeric_limits<float>::denorm_min();
    std::vector<float> values = {
        0.0f,  -0.0f, tiny,      -tiny,      1e-40f, -1e-40f, std::numeric_limits<float>::min(),
        max,   -max,  kInfinity, -kInfinity, 1.0f,   -1.0f,   555.0f,
        -1e30f};
    Rng rng(12);
    for (int i = 0; i < 10000; ++i)
        values.push_back(std::bit_cast<float>(static_cast<uint32_t>(rng.next_u32())));
    int checked = 0;
    for (float v : values) {
        if (std::isnan(v)) {
            EXPECT_TRUE(std::isnan(next_float_up(v)) && std::isnan(next_float_down(v)));
            continue;
        }
        ++checked;
        EXPECT_EQ(std::bit_cast<uint32_t>(next_float_up(v)),
                  std::bit_cast<uint32_t>(std::nextafter(v, kInfinity)))
            << v;
        EXPECT_EQ(std::bit_cast<uint32_t>(next_float_down(v)),
                  std::bit_cast<uint32_t>(std::nextafter(v, -kInfinity)))
            << v;
    }
    EXPECT_GT(checked, 9000);
}

TEST(NextFloat, TheLanesStepAsTheScalarFunction) {
    // The scene's boxes are rounded outwards four lanes at a time (Scene::build_bvh), by
    // next_floats_up: the same bits as next_float_up (and, negated, next_float_down) in every
    // lane, NaN payloads included, for the special values and random bit patterns, 40,000 in
    // all. (All 2^32 patterns agreed when it was written, in a run too long for a test.)
    const float max = std::numeric_limits<float>::max();
    const float tiny = std::numeric_limits<float>::denorm_min();
    std::vector<float> values = {0.0f, -0.0f, tiny, -tiny, 1e-40f, -1e-40f, max, -max, kInfinity,
                                 -kInfinity, std::numeric_limits<float>::quiet_NaN(), 1.0f, -1.0f};
    Rng rng(13);
    while (values.size() % 4 != 0 || values.size() < 40000)
        values.push_back(std::bit_cast<float>(rng.next_u32()));
    for (size_t i = 0; i < values.size(); i += 4) {
        const Float4 v = {values[i], values[i + 1], values[i + 2], values[i + 3]};
        const Float4 up = next_floats_up(v), down = -next_floats_up(-v);
        for (int lane = 0; lane < 4; ++lane) {
            ASSERT_EQ(std::bit_cast<uint32_t>(up[lane]),
                      std::bit_cast<uint32_t>(next_float_up(v[lane])))
                << v[lane];
            ASSERT_EQ(std::bit_cast<uint32_t>(down[lane]),
                      std::bit_cast<uint32_t>(next_float_down(v[lane])))
                << v[lane];
        }
    }
}

TEST(Rng, TheKroneckerSamplersPositionsInAPixelFormANet) {
    // The first two values of Rng::kronecker (where a sample lies in its pixel) come from Sobol's
    // sequence with a random digital shift: the first 2^k samples of a pixel form a
    // (0, k, 2)-net, exactly one point in each box [a 2^-j, (a + 1) 2^-j) x [b 2^-(k-j), ...).
    // Independent points fail this at once; a Kronecker lattice fails it too.
    for (int k : {4, 6, 8}) {
        const int n = 1 << k;
        for (uint64_t pixel = 0; pixel < 20; ++pixel) {
            std::vector<Vec2> points;
            for (int s = 0; s < n; ++s) {
                Rng rng = Rng::kronecker(5, pixel, static_cast<uint64_t>(s));
                const float x = rng.uniform();
                points.push_back({x, rng.uniform()});
            }
            for (int j = 0; j <= k; ++j) {
                std::vector<int> count(static_cast<size_t>(n), 0);
                for (const Vec2& p : points) {
                    const int a = static_cast<int>(p.x * static_cast<float>(1 << j));
                    const int b = static_cast<int>(p.y * static_cast<float>(1 << (k - j)));
                    ++count[static_cast<size_t>(a * (1 << (k - j)) + b)];
                }
                for (int c : count)
                    ASSERT_EQ(c, 1) << n << " samples, pixel " << pixel << ", boxes 2^-" << j
                                    << " x 2^-" << k - j;
            }
        }
    }
}

TEST(Bounds, SurfaceAreaAndUnion) {
    Bounds3 b;
    EXPECT_TRUE(b.empty());
    EXPECT_EQ(b.surface_area(), 0.0f);
    b.expand(Vec3(0, 0, 0));
    b.expand(Vec3(1, 2, 3));
    EXPECT_FLOAT_EQ(b.surface_area(), 2.0f * (2 + 6 + 3));
    EXPECT_EQ(b.longest_axis(), 2);
    const Bounds3 c = merge(b, Bounds3{Vec3(-1), Vec3(0)});
    EXPECT_EQ(c.min, Vec3(-1));
    EXPECT_EQ(c.max, Vec3(1, 2, 3));
}

// lane_bits turns a vector comparison into bit i for lane i, for every pattern of four and of
// eight lanes, as the plain loop over the lanes does (the BVH and the leaf blocks loop over these
// bits: a wrong order would test the wrong child or triangle).
template <class FloatN, class MaskN, int kLanes>
void expect_lane_bits_for_every_pattern() {
    for (unsigned pattern = 0; pattern < (1u << kLanes); ++pattern) {
        FloatN v{};
        for (int i = 0; i < kLanes; ++i) v[i] = (pattern >> i) & 1u ? 1.0f : -1.0f;
        const MaskN m = v > 0.0f;
        EXPECT_EQ(lane_bits(m), pattern);
        EXPECT_EQ((lane_bits_by_loop<MaskN, kLanes>(m)), pattern);
    }
}
TEST(LaneBits, GiveBitIForLaneIForEveryPattern) {
    expect_lane_bits_for_every_pattern<Float4, Mask4, 4>();
    expect_lane_bits_for_every_pattern<Float8, Mask8, 8>();
}
