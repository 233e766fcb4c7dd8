// The BVH's wide nodes: the binary tree of the build (bvh_binary.cpp) cut into 8-wide nodes where
// the surface area heuristic says, and laid out, with the primitives in the order of its leaves
// (bvh.h).
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cassert>
#include <memory>
#include <vector>

#include "accel/bvh_build.h"
#include "accel/parallel.h"

namespace lessons::bvh_build {

namespace {

// Where the binary tree is cut into wide nodes: the cut with the least total surface area of
// wide nodes, which the SAH takes as the expected number of wide nodes a ray visits (a wide
// node's eight boxes cost one test; the leaves are the binary tree's whatever the cut). By
// dynamic programming, as in the optimal collapse of Ylitie, Karras and Laine ("Efficient
// Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017), here over interior
// nodes only: cost(v, k) is the least cost of v's subtree when it may fill up to k slots of its
// parent, either as one slot (a leaf, or a wide node of its own: its area plus the cheapest way
// for its two children to fill its 8 slots) or opened, its children's subtrees sharing the k
// slots. Opening a node into its parent saves its area, so nodes come out full where they can:
// the greedy collapse before (each node adopting the children of its widest child until it had
// eight) left half the wide nodes of a mesh with two children (docs/performance.md).
class WideCut {
public:
    // On up to `threads` threads; the cut is the same on any number.
    WideCut(const BinaryNode* binary, uint32_t node_count, int threads)
        : binary_(binary),
          left_slots_(new std::array<uint8_t, kBvhWidth>[node_count]) {  // written before read
        // Children before parents, by recursion: each node's costs are its call's result, read
        // once by its parent, and no table of them is kept (beyond the heads' costs below, when
        // threads share the cut). The binary tree is at most Bvh::kMaxDepth deep.
        if (binary_[0].count > 0) return;
        threads = build_threads(threads);
        if (threads == 1) {
            solve(0);
            return;
        }
        // The subtrees a few levels down (four to eight per thread) are solved on every thread,
        // each taking the next; then the nodes above them, here. Each node is solved from its
        // children's costs alone, so the order does not change the cut.
        const int depth = std::min(
            12, static_cast<int>(std::bit_width(4u * static_cast<unsigned>(threads) - 1u)));
        std::vector<uint32_t> heads;
        find_heads(0, depth, heads);
        std::vector<Costs> head_costs(heads.size());
        std::atomic<size_t> next{0};
        parallel_parts(static_cast<size_t>(threads), threads, 1, [&](size_t, size_t, int) {
            for (size_t i; (i = next.fetch_add(1)) < heads.size();) head_costs[i] = solve(heads[i]);
        });
        size_t taken = 0;
        solve_above(0, depth, head_costs, taken);
        assert(taken == heads.size());
    }

    // The slots of interior node v as a wide node, in order: binary nodes, each a leaf or the
    // root of a wide node.
    int slots(uint32_t v, uint32_t out[kBvhWidth]) const {
        int used = 0;
        const uint32_t left = binary_[v].first;
        const int k = left_slots_[v][kBvhWidth - 1];
        frontier(left, k, out, used);
        frontier(left + 1, kBvhWidth - k, out, used);
        return used;
    }

private:
    // The least cost of interior node v's subtree when it may fill up to k slots of its parent,
    // for k = 1 .. 8 (element k - 1); left_slots_[v] records how each is reached.
    using Costs = std::array<float, kBvhWidth>;
    static constexpr Costs kLeaf{};  // a leaf fills one slot, at no cost of wide nodes
    Costs solve(uint32_t v) {
        const uint32_t left = binary_[v].first, right = left + 1;
        const Costs left_cost = binary_[left].count > 0 ? kLeaf : solve(left);
        const Costs right_cost = binary_[right].count > 0 ? kLeaf : solve(right);
        return combine(v, left_cost, right_cost);
    }
    // The interior nodes `depth` levels below interior node v, left to right (branches that end
    // sooner in leaves give none: they are solved above).
    void find_heads(uint32_t v, int depth, std::vector<uint32_t>& heads) const {
        if (depth == 0) {
            heads.push_back(v);
            return;
        }
        for (const uint32_t child : {binary_[v].first, binary_[v].first + 1})
            if (binary_[child].count == 0) find_heads(child, depth - 1, heads);
    }
    // solve(v), with the heads' costs given, in find_heads' order.
    Costs solve_above(uint32_t v, int depth, const std::vector<Costs>& head_costs, size_t& taken) {
        if (depth == 0) return head_costs[taken++];
        const uint32_t left = binary_[v].first, right = left + 1;
        const Costs left_cost =
            binary_[left].count > 0 ? kLeaf : solve_above(left, depth - 1, head_costs, taken);
        const Costs right_cost =
            binary_[right].count > 0 ? kLeaf : solve_above(right, depth - 1, head_costs, taken);
        return combine(v, left_cost, right_cost);
    }
    // Interior node v's costs from its children's.
    Costs combine(uint32_t v, const Costs& left_cost, const Costs& right_cost) {
        float open[kBvhWidth + 1];
        uint8_t split[kBvhWidth + 1];
        for (int k = 2; k <= kBvhWidth; ++k) {
            open[k] = kInfinity;
            split[k] = 1;
            for (int j = 1; j < k; ++j) {
                const float c = left_cost[j - 1] + right_cost[k - j - 1];
                if (c < open[k]) {
                    open[k] = c;
                    split[k] = static_cast<uint8_t>(j);
                }
            }
        }
        const float as_node = binary_[v].box().surface_area() + open[kBvhWidth];
        Costs cost;
        cost[0] = as_node;
        left_slots_[v][0] = 0;  // one slot: v itself
        for (int k = 2; k <= kBvhWidth; ++k) {
            // On a tie, one node fewer. With 8 slots, v is opened whatever the costs (as_node
            // adds v's area to open[8]; a NaN area must not say otherwise), so that
            // left_slots_[v][7] says how a wide node v shares its slots: slots() reads it.
            const bool opened = k == kBvhWidth || !(open[k] > as_node);
            cost[k - 1] = opened ? open[k] : as_node;
            left_slots_[v][k - 1] = opened ? split[k] : 0;
        }
        return cost;
    }

    // Appends the slots that v's subtree fills when it may fill k.
    void frontier(uint32_t v, int k, uint32_t out[kBvhWidth], int& used) const {
        const int j = binary_[v].count > 0 ? 0 : left_slots_[v][k - 1];
        if (j == 0) {
            out[used++] = v;
            return;
        }
        frontier(binary_[v].first, j, out, used);
        frontier(binary_[v].first + 1, k - j, out, used);
    }

    const BinaryNode* binary_;
    std::unique_ptr<std::array<uint8_t, kBvhWidth>[]> left_slots_;
};

// Collapses binary node b into a wide node (or, for a leaf, a leaf slot) along the cut; returns
// the slot's code for the parent. Leaves are laid out in the final primitive order as they are
// reached (depth first), each starting at a multiple of kLeafAlignment: order[] is filled here
// from the build's order.
struct Collapse {
    const BinaryNode* binary;
    const WideCut& cut;
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
    uint32_t slots[kBvhWidth];
    const int used = cut.slots(b, slots);
    const auto index = static_cast<uint32_t>(nodes.size());
    nodes.emplace_back();
    for (int axis = 0; axis < 6; ++axis)
        nodes[index].bounds[axis] = BoxLanes{} + (axis % 2 == 0 ? kInfinity : -kInfinity);
    for (int i = 0; i < used; ++i) {
        const Bounds3 box = binary[slots[i]].box();
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

}  // namespace

void collapse_to_wide(const BinaryNode* binary, uint32_t node_count, int threads,
                      const std::vector<uint32_t>& build_order, LargePageVector<BvhNode>& nodes,
                      std::vector<uint32_t>& order) {
    const WideCut cut(binary, node_count, threads);
    Collapse collapse{binary, cut, build_order, nodes, order};
    // The root is always a wide node, even over a single leaf.
    nodes.reserve(node_count / 3 + 1);
    if (binary[0].count > 0) {
        const Bounds3 bounds = binary[0].box();
        nodes.emplace_back();
        for (int axis = 0; axis < 6; ++axis)
            nodes[0].bounds[axis] = BoxLanes{} + (axis % 2 == 0 ? kInfinity : -kInfinity);
        for (int axis = 0; axis < 3; ++axis) {
            nodes[0].bounds[2 * axis][0] = bounds.min[axis];
            nodes[0].bounds[2 * axis + 1][0] = bounds.max[axis];
        }
        nodes[0].child[0] = collapse.leaf(0, binary[0].count);
        for (int i = 1; i < kBvhWidth; ++i) nodes[0].child[i] = 0;
    } else {
        collapse(0);
    }
}

}  // namespace lessons::bvh_build
