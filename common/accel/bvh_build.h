// What the BVH's build shares among its files (private to common/accel/). The build, as
// bvh.cpp runs it: every primitive's box copied into a BuildRef; a binary tree over them, top
// down (bvh_binary.cpp), each node split where the binned surface area heuristic says
// (bvh_sah.cpp); then the binary tree cut into 8-wide nodes (bvh_wide.cpp).
#pragma once

#include <atomic>
#include <bit>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "accel/build_workers.h"
#include "accel/bvh.h"
#include "geometry/bounds.h"
#include "geometry/simd.h"

namespace lessons::bvh_build {

// Bins along each axis into which the heuristic sorts a node's centroids (bvh_sah.cpp).
constexpr int kBins = 16;

// A box as two vectors of four floats (x, y, z and a fourth lane), so that growing it by another
// box takes one minimum and one maximum instruction (Bounds3 takes six scalar ones): the
// extents of a node's primitives and of its children (the bins are vectors of eight: Bins). The
// comparisons are Bounds3::expand's, lane by lane, so the boxes (and the tree) are the same
// bits. The fourth lane is not part of the box: a primitive's copy keeps its index there
// (BuildRef).
struct Box4 {
    Float4 lo = Float4{} + kInfinity, hi = Float4{} - kInfinity;
    static Box4 of(const Bounds3& b) {
        return {Float4{b.min.x, b.min.y, b.min.z, 0.0f}, Float4{b.max.x, b.max.y, b.max.z, 0.0f}};
    }
    void expand(const Box4& b) {
        lo = b.lo < lo ? b.lo : lo;
        hi = hi < b.hi ? b.hi : hi;
    }
    void expand(const Float4& p) {
        lo = p < lo ? p : lo;
        hi = hi < p ? p : hi;
    }
    Bounds3 bounds() const { return {Vec3(lo[0], lo[1], lo[2]), Vec3(hi[0], hi[1], hi[2])}; }
};

// A primitive as the build sorts it: a copy of its box, 32 bytes, with the primitive's index in
// the minimum's fourth lane (as bits: below 2^28, so a small positive float, never NaN), so that
// every pass over a node's primitives reads memory in order, with no index to follow. A plain
// pair of vectors, so that the array of them is not written before the threads fill it.
struct BuildRef {
    Float4 lo, hi;
    static BuildRef of(const Bounds3& b, uint32_t prim) {
        const Box4 box = Box4::of(b);
        BuildRef r{box.lo, box.hi};
        r.lo[3] = std::bit_cast<float>(prim);
        return r;
    }
    Box4 box() const { return {lo, hi}; }
    uint32_t prim() const { return std::bit_cast<uint32_t>(lo[3]); }
    // Bounds3::centroid's arithmetic, in all lanes at once; the index's lane is taken as 0
    // (as a float it is a denormal for indices below 2^23, and arithmetic on denormals can take
    // the processor a hundred times longer).
    Float4 centroid() const {
        Float4 low = lo;
        low[3] = 0.0f;
        return 0.5f * (low + hi);
    }
    float centroid(int axis) const { return 0.5f * (lo[axis] + hi[axis]); }
};

// The boxes of a set of primitives and of their centroids: what a node needs to bin them.
struct Extent {
    Box4 box, centroids;
    void add(const BuildRef& r) { add(r, r.centroid()); }
    void add(const BuildRef& r, const Float4& centroid) {
        box.expand(r.box());
        centroids.expand(centroid);
    }
    void add(const Extent& e) {
        box.expand(e.box);
        centroids.expand(e.centroids);
    }
};

// The binary tree the build makes before collapsing it: 32-byte nodes, children side by side.
// Plain floats, so that the array for every node the tree may need is not written before use.
struct BinaryNode {
    float lo[3], hi[3];
    uint32_t first;  // interior: index of the left child (right = first + 1); leaf: first primitive
    uint32_t count;  // number of primitives in a leaf; 0 for an interior node
    Bounds3 box() const { return {Vec3(lo[0], lo[1], lo[2]), Vec3(hi[0], hi[1], hi[2])}; }
};

// A node still to build: its index, its primitives [begin, end) and its depth in the tree.
struct BuildTask {
    uint32_t node, begin, end, depth;
    Extent extent;  // of primitives [begin, end)
};

// A split of a node's primitives between two bins of one axis, and what the heuristic says it
// costs.
struct Split {
    int axis = -1;
    int bin = 0;  // primitives in bins [0, bin] go left
    float cost = kInfinity;
};

// The cost the heuristic gives n primitives in a leaf, in units of one test: a leaf's primitives
// are tested four at once, so ceil(n / 4) block tests, plus a quarter per primitive, an empirical
// term that favours tighter leaves. Measured (docs/performance.md, design item 9): counting
// blocks alone makes every leaf of the 32-triangle Cornell box full and large, and its shadow
// rays 25-40% slower; counting primitives alone leaves the meshes' leaves a quarter empty.
inline float leaf_cost(uint32_t n) {
    return static_cast<float>((n + 3) / 4) + 0.25f * static_cast<float>(n);
}

// A centroid's bin along an axis whose centroids start at lo, with `scale` bins per unit, is the
// integer part of b = (centroid - lo) scale, clamped to [0, kBins - 1]; a NaN b (from a NaN
// coordinate) is in bin 0 (Bins::bins_of). Whether that bin is at most `bin`, for a bin before
// the last (a split's: some occupied bin follows it), by one comparison: b <= 0 or NaN is bin 0;
// b in [0, kBins) is in bin trunc(b), at most `bin` exactly where b < bin + 1 (a float,
// exactly); b >= kBins is in the last bin, beyond `bin`, and there b >= bin + 1 too.
inline bool bin_at_most(float centroid, float lo, float scale, float bin_end) {
    return !((centroid - lo) * scale >= bin_end);  // bin_end = bin + 1
}

// Whether no split of the primitives [first, last) can cost less than their leaf (bvh_sah.cpp).
bool no_split_beats_leaf(const BuildRef* first, const BuildRef* last, float node_area);

// The binary tree over `refs`, reordering them so that every node's primitives are contiguous;
// node 0 is the root. Subtrees are built by as many threads as allowed, each into nodes it takes
// from a shared counter: which thread builds what, and the nodes' numbering, vary from run to
// run, but every node's primitives, box and split do not (binning merges per-thread bins by
// minima, maxima and sums, whose results do not depend on the order), so the tree collapsed
// from node 0 (Collapse, depth first) is the same bits on any number of threads.
class BinaryBuilder {
public:
    BinaryBuilder(BuildRef* refs, uint32_t count, int threads);

    // Every node of the tree, at most 2 n - 1; node 0 is the root.
    std::unique_ptr<BinaryNode[]> build(const Extent& root);
    // After build(): at least the number of nodes used (some chunks' ends are unused).
    uint32_t nodes_taken() const { return next_node_.load(); }

private:
    // The steps of one node, in bvh_binary.cpp: made a leaf, then perhaps split in two, its
    // children queued or handed to another thread; the split itself in bvh_sah.cpp.
    void subtree(BuildTask root);
    BinaryNode& write_leaf(const BuildTask& task);
    std::optional<uint32_t> divide(const BuildTask& task, Extent& left, Extent& right);
    BuildRef* partition_at_split(const BuildTask& task, const Split& best, const Float4& scale,
                                 Extent& left, Extent& right);
    BuildRef* partition_at_median(const BuildTask& task, Extent& left, Extent& right);
    void queue_children(const BuildTask& left, const BuildTask& right,
                        std::vector<BuildTask>& tasks);
    Split cheapest_split(const BuildTask& task, Float4& scale);

    BuildRef* const refs_;
    const uint32_t count_;
    std::unique_ptr<BinaryNode[]> nodes_;
    std::atomic<uint32_t> next_node_{1};  // the first node of the next chunk
    std::atomic<uint32_t> subtrees_handed_{0};
    Workers workers_;
};

// Collapses the binary tree (`node_count` nodes taken, node 0 the root) into wide nodes along the
// cut of least cost (WideCut), on up to `threads` threads: appends them to `nodes`, the root
// first (a wide node even over a single leaf), and the primitive order to `order`, from the
// build's order of the primitives (bvh_wide.cpp).
void collapse_to_wide(const BinaryNode* binary, uint32_t node_count, int threads,
                      const std::vector<uint32_t>& build_order, LargePageVector<BvhNode>& nodes,
                      std::vector<uint32_t>& order);

}  // namespace lessons::bvh_build
