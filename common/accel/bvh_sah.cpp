// The binned surface area heuristic of the BVH's build (Wald 2007; bvh.h): what a split and a leaf
// cost, and where a node of the binary tree is split most cheaply. The tree itself is built in
// bvh_binary.cpp.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <vector>

#include "accel/bvh_build.h"
#include "accel/parallel.h"

namespace lessons::bvh_build {

namespace {

constexpr float kTraversalCost = 1.0f;  // relative to one primitive intersection
// A node of at least this many primitives is binned by every idle thread at once (up to 16).
// Below, a thread's start costs more than it saves.
constexpr uint32_t kParallelBinning = 1u << 16;

// The bins of a node along each axis: the box and count of the primitives whose centroids fall
// in each. A bin is one vector of eight floats: its box's minimum in lanes 0-2 and its negated
// maximum in lanes 4-6, so that growing it by a primitive's box is one minimum instruction
// (max(a, b) = -min(-a, -b), with the same comparisons as Box4::expand, so the same bits), and
// its count in lane 3, as an unsigned integer's bits (added, and blended in). Binning updates
// three bins per primitive, the build's innermost loop: one load and one store each, where a
// Box4 and a separate count took three of each (docs/performance.md, design item 15).
struct Bins {
    Float8 bin[3][kBins];

    // A bin with no primitive: an empty box (minimum +inf, negated maximum +inf), count 0 (the
    // bits of 0.0f).
    static constexpr Float8 kEmpty = {kInfinity, kInfinity, kInfinity, 0.0f,
                                      kInfinity, kInfinity, kInfinity, kInfinity};

    Bins() {
        for (auto& axis_bins : bin)
            for (Float8& b : axis_bins) b = kEmpty;
    }

    // The bins of a centroid along all three axes at once, in the lanes of one vector, as the
    // comment above bin_at_most says (a NaN lane fails `b > 0` and goes to bin 0).
    static Int4 bins_of(const Float4& centroid, const Float4& lo, const Float4& scale) {
        Float4 b = (centroid - lo) * scale;
        b = b > 0.0f ? b : Float4{};
        b = b < static_cast<float>(kBins) ? b : Float4{} + static_cast<float>(kBins - 1);
        return __builtin_convertvector(b, Int4);  // truncates, as static_cast<int> does
    }
    // Grows bin v by bin o: the box around both (Box4::expand's comparisons, lane by lane), the
    // sum of their counts.
    static void merge(Float8& v, const Float8& o) {
        const Float8 smaller = o < v ? o : v;
        // Unsigned: the box lanes' bits are added too, and thrown away; they must not overflow
        // a signed type.
        const UInt8 summed = __builtin_bit_cast(UInt8, v) + __builtin_bit_cast(UInt8, o);
        v = kCountLane ? __builtin_bit_cast(Float8, summed) : smaller;
    }
    void add(const BuildRef* first, const BuildRef* last, const Float4& lo, const Float4& scale) {
        for (const BuildRef* r = first; r != last; ++r) {
            const Int4 b = bins_of(r->centroid(), lo, scale);
            // The primitive as a bin of one (lane 7, -0 here, is computed with but never used).
            Float8 prim = __builtin_shufflevector(r->lo, -r->hi, 0, 1, 2, 3, 4, 5, 6, 7);
            prim[3] = std::bit_cast<float>(1u);
            for (int axis = 0; axis < 3; ++axis) merge(bin[axis][b[axis]], prim);
        }
    }
    void add(const Bins& other) {
        for (int axis = 0; axis < 3; ++axis)
            for (int b = 0; b < kBins; ++b) merge(bin[axis][b], other.bin[axis][b]);
    }
    static uint32_t count_of(const Float8& v) { return std::bit_cast<uint32_t>(v[3]); }
    // Bounds3::surface_area of a bin's box, with the same arithmetic: empty where a minimum
    // exceeds its maximum (a NaN makes neither), else from the extent max - min, which is
    // -(negated max) - min exactly. The fourth lanes are zeros, not the count.
    static float area_of(const Float8& v) {
        const Float4 lo = __builtin_shufflevector(v, Float8{}, 0, 1, 2, 8);
        const Float4 hi = -__builtin_shufflevector(v, Float8{}, 4, 5, 6, 8);
        if ((lane_bits(lo > hi) & 7u) != 0) return 0.0f;
        const Float4 extent = hi - lo;
        return 2.0f * (extent[0] * extent[1] + extent[1] * extent[2] + extent[2] * extent[0]);
    }
    // Bit b: bin b of the axis holds a primitive.
    uint32_t occupied(int axis) const {
        uint32_t bits = 0;
        for (int b = 0; b < kBins; ++b)
            bits |= static_cast<uint32_t>(count_of(bin[axis][b]) != 0) << b;
        return bits;
    }

private:
    static constexpr Int8 kCountLane = {0, 0, 0, -1, 0, 0, 0, 0};
};

// The cost of splitting a node of area node_area in two: kTraversalCost + weight / node_area,
// where the weight is the sum over the two sides of area x leaf_cost(count).
float side_weight(float area, uint32_t count) {
    return area * leaf_cost(count);
}
float split_cost(float weight, float node_area) {
    return kTraversalCost + weight / node_area;
}

}  // namespace

// Whether no split of the primitives [first, last) can cost less than their leaf, by a lower
// bound of every split's cost: one side holds the largest of their boxes, whose area it has at
// least, the other at least the smallest's, and either side's leaf costs at least leaf_cost(1).
// The bound is split_cost's arithmetic with operands no larger than a split's (a union's area is
// at least each member's), and rounding is monotonic, so it is at most the cost of every split
// as computed: when it reaches the leaf's cost, the split search would keep the leaf, and the
// tree is the same bits without it. For two primitives it is their one split's cost exactly.
// About two thirds of a fine mesh's small nodes are decided here (docs/performance.md, design
// item 15).
bool no_split_beats_leaf(const BuildRef* first, const BuildRef* last, float node_area) {
    float largest = 0.0f, smallest = kInfinity;
    for (const BuildRef* r = first; r != last; ++r) {
        const float area = r->box().bounds().surface_area();
        // A NaN coordinate makes the area NaN, which max and min would skip, while the search
        // sees such a box as empty in that lane (Box4::expand keeps the other operand): no bound.
        if (!(area >= 0.0f)) return false;
        largest = std::max(largest, area);
        smallest = std::min(smallest, area);
    }
    const float bound = split_cost(side_weight(largest, 1) + side_weight(smallest, 1), node_area);
    return bound >= leaf_cost(static_cast<uint32_t>(last - first));  // false for NaN (A = 0)
}

namespace {

// The bins of the primitives [first, last) along all three axes, for centroids starting at lo
// with `scale` bins per unit: one pass, shared among the idle threads for a large node.
Bins bin_centroids(const BuildRef* first, const BuildRef* last, const Float4& lo,
                   const Float4& scale, Workers& workers) {
    const auto count = static_cast<uint32_t>(last - first);
    Bins bins;
    int helpers = 0;
    while (count >= kParallelBinning && helpers < 15 && workers.claim()) ++helpers;
    if (helpers == 0) {
        bins.add(first, last, lo, scale);
    } else {
        // The idle threads bin a part each, this one the first; then this one merges. The
        // claims go back however this ends.
        struct Claims {
            Workers& workers;
            int count;
            ~Claims() {
                for (int i = 0; i < count; ++i) workers.release();
            }
        } claims{workers, helpers};
        std::vector<Bins> partial(static_cast<size_t>(helpers + 1));
        parallel_parts(count, helpers + 1, 1, [&](size_t begin, size_t end, int part) {
            partial[part].add(first + begin, first + end, lo, scale);
        });
        for (const Bins& p : partial) bins.add(p);
    }
    return bins;
}

// The cheapest split between two bins of one axis, taken as `best` if it costs less (its weight,
// area x leaf cost summed over both sides, kept in best_weight): the axis swept from both sides.
// The sweep visits occupied bins only: most nodes hold a few primitives (the leaves' parents,
// and the leaves, which may still be split), and sweeping all 16 bins of each axis took half the
// build's time there. A split after an empty bin costs what the split before it costs, and the
// first of equal costs is kept, so skipping it changes nothing: the answer is that of the full
// sweep, bit for bit.
void sweep_axis(const Bins& bins, int axis, float node_area, Split& best, float& best_weight) {
    const uint32_t occupied = bins.occupied(axis);
    // Sweep from the right to get the weight (area x leaf cost) of every right-hand side, each
    // stored at the right side's first occupied bin. A side is itself a bin (its box and
    // count), grown bin by bin.
    std::array<float, kBins> right_weight;
    Float8 side = Bins::kEmpty;
    for (uint32_t m = occupied; m != 0;) {
        const int b = 31 - std::countl_zero(m);
        m &= ~(1u << b);
        if (m == 0) break;  // the first occupied bin: no split leaves it on the right
        Bins::merge(side, bins.bin[axis][b]);
        right_weight[b] = side_weight(Bins::area_of(side), Bins::count_of(side));
    }
    side = Bins::kEmpty;
    for (uint32_t m = occupied; m != 0;) {
        const int b = std::countr_zero(m);
        m &= m - 1;
        if (m == 0) break;  // the last occupied bin: no split leaves it on the left
        Bins::merge(side, bins.bin[axis][b]);
        const int next = std::countr_zero(m);  // the right side's first bin
        const float weight =
            side_weight(Bins::area_of(side), Bins::count_of(side)) + right_weight[next];
        // For a node of positive area the cost rounds monotonically with the weight, so a
        // weight no less than the best's cannot cost less: its division is skipped.
        if (node_area > 0.0f && !(weight < best_weight)) continue;
        const float cost = split_cost(weight, node_area);
        if (cost < best.cost) {
            best = {axis, b, cost};
            best_weight = weight;
        }
    }
}

}  // namespace

// The binned surface area heuristic for a node's primitives: bins their centroids along all three
// axes in one pass (shared among the idle threads for a large node), then sweeps every axis from
// both sides for the cheapest split between two bins. `scale` (bins per unit of centroid extent)
// is returned for the partition that follows; the split's axis is negative when no axis can be
// split.
Split BinaryBuilder::cheapest_split(const BuildTask& task, Float4& scale) {
    const Bounds3 centroid_box = task.extent.centroids.bounds();
    const Float4 lo = task.extent.centroids.lo;
    bool usable[3];
    for (int axis = 0; axis < 3; ++axis) {
        const float extent = centroid_box.max[axis] - centroid_box.min[axis];
        scale[axis] = kBins / extent;
        usable[axis] = extent > 0.0f && std::isfinite(scale[axis]);  // else below float
    }                                                                // resolution, or NaN
    scale[3] = 0.0f;
    const float node_area = task.extent.box.bounds().surface_area();
    const Bins bins = bin_centroids(refs_ + task.begin, refs_ + task.end, lo, scale, workers_);
    Split best;
    float best_weight = kInfinity;
    for (int axis = 0; axis < 3; ++axis)
        if (usable[axis]) sweep_axis(bins, axis, node_area, best, best_weight);
    return best;
}

}  // namespace lessons::bvh_build
