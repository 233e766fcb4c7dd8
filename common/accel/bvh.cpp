// Binned-SAH construction of the BVH (traversal is in bvh.h).
#include "accel/bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace lessons {

namespace {

constexpr int kBins = 16;
constexpr float kTraversalCost = 1.0f;  // relative to one primitive intersection
constexpr int kMedianSplitDepth = 64;   // deeper than this, split at the median (see kStackSize)

// A box as two vectors of four floats (x, y, z and an unused lane), so that growing it by another
// box takes one minimum and one maximum instruction: binning does so three times per primitive
// and node, the build's innermost loop. Bounds3 takes six scalar ones. The comparisons are
// Bounds3::expand's, lane by lane, so the boxes (and the tree) are the same bits.
struct Box4 {
    Float4 lo = Float4{} + kInfinity, hi = Float4{} - kInfinity;
    static Box4 of(const Bounds3& b) {
        return {Float4{b.min.x, b.min.y, b.min.z, 0.0f}, Float4{b.max.x, b.max.y, b.max.z, 0.0f}};
    }
    void expand(const Box4& b) {
        lo = b.lo < lo ? b.lo : lo;
        hi = hi < b.hi ? b.hi : hi;
    }
    Bounds3 bounds() const { return {Vec3(lo[0], lo[1], lo[2]), Vec3(hi[0], hi[1], hi[2])}; }
};

struct Bin {
    Box4 box;
    uint32_t count = 0;
};

// The binary tree the build makes before collapsing it: 32-byte nodes, children side by side.
struct BinaryNode {
    Bounds3 box;
    uint32_t first;  // interior: index of the left child (right = first + 1); leaf: first primitive
    uint32_t count;  // number of primitives in a leaf; 0 for an interior node
};

struct BuildTask {
    uint32_t node, begin, end, depth;
};

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
float leaf_cost(uint32_t n) {
    return static_cast<float>((n + 3) / 4) + 0.25f * static_cast<float>(n);
}

int bin_of(float centroid, float lo, float scale) {
    const float b = (centroid - lo) * scale;
    if (!(b > 0.0f)) return 0;  // also catches NaN
    if (!(b < static_cast<float>(kBins))) return kBins - 1;
    return static_cast<int>(b);
}

// Collapses binary node b into a wide node (or, for a leaf, a leaf slot); returns the slot's
// code for the parent. Each node adopts the two children of its largest interior child until it
// has eight: large boxes are the ones rays enter most often (the SAH's reasoning).
// Leaves are laid out in the final primitive order as they are reached (depth first), each
// starting at a multiple of kLeafAlignment: order[] is filled here from the build's order.
struct Collapse {
    const std::vector<BinaryNode>& binary;
    const std::vector<uint32_t>& build_order;
    LargePageVector<BvhNode>& nodes;
    std::vector<uint32_t>& order;

    uint32_t leaf(uint32_t first, uint32_t count) {
        while (order.size() % Bvh::kLeafAlignment != 0) order.push_back(Bvh::kPadding);
        const auto start = static_cast<uint32_t>(order.size());
        for (uint32_t i = first; i < first + count; ++i) order.push_back(build_order[i]);
        return BvhNode::make_leaf(start, count);
    }
    uint32_t operator()(uint32_t b);
};

uint32_t Collapse::operator()(uint32_t b) {
    if (binary[b].count > 0) return leaf(binary[b].first, binary[b].count);
    uint32_t slots[kBvhWidth] = {binary[b].first, binary[b].first + 1};
    int used = 2;
    while (used < kBvhWidth) {
        int widest = -1;
        float widest_area = -1.0f;
        for (int i = 0; i < used; ++i) {
            const BinaryNode& c = binary[slots[i]];
            if (c.count == 0 && c.box.surface_area() > widest_area) {
                widest = i;
                widest_area = c.box.surface_area();
            }
        }
        if (widest < 0) break;  // every slot is a leaf
        const uint32_t left = binary[slots[widest]].first;
        slots[widest] = left;
        slots[used++] = left + 1;
    }
    const auto index = static_cast<uint32_t>(nodes.size());
    nodes.emplace_back();
    for (int axis = 0; axis < 6; ++axis)
        nodes[index].bounds[axis] = BoxLanes{} + (axis % 2 == 0 ? kInfinity : -kInfinity);
    for (int i = 0; i < used; ++i) {
        const Bounds3& box = binary[slots[i]].box;
        const uint32_t child = (*this)(slots[i]);  // may move nodes
        BvhNode& node = nodes[index];
        for (int axis = 0; axis < 3; ++axis) {
            node.bounds[2 * axis][i] = box.min[axis];
            node.bounds[2 * axis + 1][i] = box.max[axis];
        }
        node.child[i] = child;
    }
    for (int i = used; i < kBvhWidth; ++i) nodes[index].child[i] = 0;  // never entered: empty box
    return index;
}

// A primitive as the build sorts it: a copy of its box, with its centroid and index, so that every
// pass over a node's primitives reads memory in order (no index chasing).
struct BuildRef {
    Box4 box;
    Vec3 centroid;
    uint32_t prim;
};

// The binned surface area heuristic for the primitives [first, last) of a node with box
// node_box: bins their centroids along all three axes in one pass, then sweeps every axis from
// both sides for the cheapest split between two bins. `scale` (bins per unit of centroid extent)
// is returned for the partition that follows; best.axis < 0 when no axis can be split.
Split cheapest_split(const BuildRef* first, const BuildRef* last, const Bounds3& centroid_box,
                     const Bounds3& node_box, Vec3& scale) {
    bool usable[3];
    for (int axis = 0; axis < 3; ++axis) {
        const float extent = centroid_box.max[axis] - centroid_box.min[axis];
        scale[axis] = kBins / extent;
        usable[axis] = extent > 0.0f && std::isfinite(scale[axis]);  // else below float
    }                                                                // resolution, or NaN
    std::array<std::array<Bin, kBins>, 3> bins{};
    for (const BuildRef* r = first; r != last; ++r)
        for (int axis = 0; axis < 3; ++axis) {
            Bin& bin = bins[axis][bin_of(r->centroid[axis], centroid_box.min[axis], scale[axis])];
            bin.box.expand(r->box);
            ++bin.count;
        }
    Split best;
    const float node_area = node_box.surface_area();
    for (int axis = 0; axis < 3; ++axis) {
        if (!usable[axis]) continue;
        // Sweep from the right to get the area and count of every right-hand side.
        std::array<float, kBins> right_area{};
        std::array<uint32_t, kBins> right_count{};
        Box4 acc;
        uint32_t acc_count = 0;
        for (int b = kBins - 1; b > 0; --b) {
            acc.expand(bins[axis][b].box);
            acc_count += bins[axis][b].count;
            right_area[b] = acc.bounds().surface_area();
            right_count[b] = acc_count;
        }
        acc = Box4{};
        acc_count = 0;
        for (int b = 0; b < kBins - 1; ++b) {
            acc.expand(bins[axis][b].box);
            acc_count += bins[axis][b].count;
            if (acc_count == 0 || right_count[b + 1] == 0) continue;
            const float cost =
                kTraversalCost + (acc.bounds().surface_area() * leaf_cost(acc_count) +
                                  right_area[b + 1] * leaf_cost(right_count[b + 1])) /
                                     node_area;
            if (cost < best.cost) best = {axis, b, cost};
        }
    }
    return best;
}

// Builds the binary tree over `refs`, reordering them so that every node's primitives are
// contiguous; node 0 is the root.
std::vector<BinaryNode> build_binary_tree(std::vector<BuildRef>& refs) {
    const uint32_t n = static_cast<uint32_t>(refs.size());
    std::vector<BinaryNode> binary;
    binary.reserve(2 * n);
    binary.push_back({});
    std::vector<BuildTask> tasks{{0, 0, n, 0}};
    while (!tasks.empty()) {
        const BuildTask task = tasks.back();
        tasks.pop_back();
        const uint32_t count = task.end - task.begin;
        BuildRef* const first = refs.data() + task.begin;
        BuildRef* const last = refs.data() + task.end;

        Box4 node_box4;
        Bounds3 centroid_box;
        for (const BuildRef* r = first; r != last; ++r) {
            node_box4.expand(r->box);
            centroid_box.expand(r->centroid);
        }
        const Bounds3 node_box = node_box4.bounds();
        BinaryNode& node = binary[task.node];
        node.box = node_box;
        node.first = task.begin;
        node.count = count;
        if (count == 1) continue;

        Vec3 scale;
        const Split best = cheapest_split(first, last, centroid_box, node_box, scale);

        // Up to kMaxLeafSize primitives make a leaf, tested together, four at once (Scene), for
        // about the cost of one test; unless the heuristic's split costs less still (large
        // primitives whose boxes together span far more than each does: the walls of a room;
        // docs/performance.md, design item 13). Never a median split: that is no saving.
        const bool sah_split =
            best.axis >= 0 && task.depth < static_cast<uint32_t>(kMedianSplitDepth);
        if (count <= static_cast<uint32_t>(Bvh::kMaxLeafSize) &&
            !(sah_split && best.cost < leaf_cost(count)))
            continue;  // leaf

        uint32_t mid;
        if (sah_split) {
            const int axis = best.axis;
            const float lo = centroid_box.min[axis];
            BuildRef* split = std::partition(first, last, [&](const BuildRef& r) {
                return bin_of(r.centroid[axis], lo, scale[axis]) <= best.bin;
            });
            mid = static_cast<uint32_t>(split - refs.data());
        } else {
            // No usable split (all centroids coincide) or too deep: halve by count.
            const int axis = centroid_box.longest_axis();
            mid = task.begin + count / 2;
            std::nth_element(first, refs.data() + mid, last,
                             [&](const BuildRef& a, const BuildRef& b) {
                                 return a.centroid[axis] < b.centroid[axis];
                             });
        }

        const uint32_t left = static_cast<uint32_t>(binary.size());
        binary.push_back({});
        binary.push_back({});
        binary[task.node].first = left;  // re-index: push_back may have moved `node`
        binary[task.node].count = 0;
        tasks.push_back({left + 1, mid, task.end, task.depth + 1});
        tasks.push_back({left, task.begin, mid, task.depth + 1});
    }
    return binary;
}

}  // namespace

Bvh::Bvh(std::span<const Bounds3> boxes) {
    const uint32_t n = static_cast<uint32_t>(boxes.size());
    if (n == 0) return;
    if (boxes.size() > BvhNode::kMaxFirst)
        throw std::length_error("too many primitives for one BVH: " + std::to_string(boxes.size()));
    std::vector<BuildRef> refs(n);
    for (uint32_t i = 0; i < n; ++i) refs[i] = {Box4::of(boxes[i]), boxes[i].centroid(), i};
    const std::vector<BinaryNode> binary = build_binary_tree(refs);

    // Collapse the binary tree into wide nodes.
    bounds_ = binary[0].box;
    std::vector<uint32_t> build_order(n);
    for (uint32_t i = 0; i < n; ++i) build_order[i] = refs[i].prim;
    refs = {};
    prim_index_.reserve(n + n / 2);
    Collapse collapse{binary, build_order, nodes_, prim_index_};
    // The root is always a wide node, even over a single leaf.
    nodes_.reserve(binary.size() / 3 + 1);
    if (binary[0].count > 0) {
        nodes_.emplace_back();
        for (int axis = 0; axis < 6; ++axis)
            nodes_[0].bounds[axis] = BoxLanes{} + (axis % 2 == 0 ? kInfinity : -kInfinity);
        for (int axis = 0; axis < 3; ++axis) {
            nodes_[0].bounds[2 * axis][0] = bounds_.min[axis];
            nodes_[0].bounds[2 * axis + 1][0] = bounds_.max[axis];
        }
        nodes_[0].child[0] = collapse.leaf(0, binary[0].count);
        for (int i = 1; i < kBvhWidth; ++i) nodes_[0].child[i] = 0;
    } else {
        collapse(0);
    }
    nodes_.shrink_to_fit();
    prim_index_.shrink_to_fit();
    if (prim_index_.size() > BvhNode::kMaxFirst)
        throw std::length_error("too many primitives for one BVH: " + std::to_string(n));
}

size_t Bvh::memory_bytes() const {
    return nodes_.capacity() * sizeof(BvhNode) + prim_index_.capacity() * sizeof(uint32_t);
}

}  // namespace lessons
