// The binary tree of the BVH's build: top down, node by node, each split where the surface area
// heuristic says (bvh_sah.cpp), the larger subtrees handed to idle threads (bvh_build.h).
#include <algorithm>
#include <atomic>
#include <cassert>
#include <vector>

#include "accel/bvh_build.h"

namespace lessons::bvh_build {

namespace {

constexpr int kMedianSplitDepth = 64;  // deeper than this, split at the median (see kStackSize)
// A subtree of at least this many primitives may be built by another thread. Below, a thread's
// start costs more than it saves.
constexpr uint32_t kSubtreeTask = 4096;
// A thread takes nodes from the shared array kNodeChunk at a time, so that two threads never
// write nodes in the same cache line (nor the shared counter at every node): measured, taking
// them two at a time made the build on two threads do 50% more work than on one. The array has
// room for every subtree's last chunk, partly unused: at most kMaxSubtrees subtrees are handed
// to other threads.
constexpr uint32_t kNodeChunk = 256;
constexpr uint32_t kMaxSubtrees = 1024;

// Reorders [first, last) so that the primitives whose centroids `goes_left` holds for come
// first, and returns where the others start; `left` and `right` receive the extents of the two
// parts. The swaps are those of libstdc++'s std::partition, so the order is that of the build
// before the extents were gathered here (which saved the children a pass over their primitives).
// Each primitive's centroid is computed once, for the test and its side's extent.
template <class GoesLeft>
BuildRef* partition(BuildRef* first, BuildRef* last, GoesLeft goes_left, Extent& left,
                    Extent& right) {
    for (;;) {
        Float4 c_first, c_last;
        for (;;) {
            if (first == last) return first;
            c_first = first->centroid();
            if (!goes_left(c_first)) break;
            left.add(*first++, c_first);
        }
        --last;  // *first goes right: find one on the right to swap it with
        for (;;) {
            if (first == last) {
                right.add(*first, c_first);
                return first;
            }
            c_last = last->centroid();
            if (goes_left(c_last)) break;
            right.add(*last--, c_last);
        }
        std::swap(*first, *last);
        left.add(*first++, c_last);
        right.add(*last, c_first);
    }
}

// The nodes a subtree's thread has taken from the shared array and not used yet, kNodeChunk at a
// time: [next, end).
struct NodeChunk {
    uint32_t next = 0, end = 0;
    // Two nodes side by side (a node's children): the index of the first.
    uint32_t take_two(std::atomic<uint32_t>& next_node) {
        if (next == end) {
            next = next_node.fetch_add(kNodeChunk, std::memory_order_relaxed);
            end = next + kNodeChunk;
        }
        const uint32_t children = next;
        next += 2;
        return children;
    }
};

}  // namespace

BinaryBuilder::BinaryBuilder(BuildRef* refs, uint32_t count, int threads)
    : refs_(refs),
      count_(count),
      nodes_(new BinaryNode[2 * size_t{count} + size_t{kNodeChunk} * (kMaxSubtrees + 1)]),
      workers_(threads) {}

std::unique_ptr<BinaryNode[]> BinaryBuilder::build(const Extent& root) {
    try {
        subtree({0, 0, count_, 0, root});
    } catch (...) {  // out of memory: let the other threads finish before unwinding
        try {
            workers_.join_all();
        } catch (...) {  // theirs: this thread's own exception goes on
        }
        throw;
    }
    workers_.release();  // this thread is idle now: another may start
    workers_.join_all();
    return std::move(nodes_);
}

// Builds the subtree of `root` (whose node index is taken), handing the larger child of a node to
// an idle thread whenever there is one and the child is large enough.
void BinaryBuilder::subtree(BuildTask root) {
    NodeChunk chunk;  // this subtree's nodes still free in its chunk
    std::vector<BuildTask> tasks{root};
    while (!tasks.empty()) {
        const BuildTask task = tasks.back();
        tasks.pop_back();
        BinaryNode& node = write_leaf(task);
        Extent left, right;
        const std::optional<uint32_t> mid = divide(task, left, right);
        if (!mid) continue;  // a leaf
        const uint32_t children = chunk.take_two(next_node_);
        node.first = children;
        node.count = 0;
        queue_children({children, task.begin, *mid, task.depth + 1, left},
                       {children + 1, *mid, task.end, task.depth + 1, right}, tasks);
    }
}

// The task's node as a leaf of its primitives: what it stays unless it is divided.
BinaryNode& BinaryBuilder::write_leaf(const BuildTask& task) {
    BinaryNode& node = nodes_[task.node];
    const Bounds3 node_box = task.extent.box.bounds();
    for (int axis = 0; axis < 3; ++axis) {
        node.lo[axis] = node_box.min[axis];
        node.hi[axis] = node_box.max[axis];
    }
    node.first = task.begin;
    node.count = task.end - task.begin;
    return node;
}

// Whether and where the task's node is split: the position in the primitives where its right
// child's start (those before, its left child's, now come first), with the extents of both
// sides; nothing if the node stays a leaf.
std::optional<uint32_t> BinaryBuilder::divide(const BuildTask& task, Extent& left, Extent& right) {
    const uint32_t count = task.end - task.begin;
    if (count == 1) return std::nullopt;
    if (count <= static_cast<uint32_t>(Bvh::kMaxLeafSize) &&
        no_split_beats_leaf(refs_ + task.begin, refs_ + task.end,
                            task.extent.box.bounds().surface_area()))
        return std::nullopt;  // a leaf, as the search below would decide

    Float4 scale;
    const Split best = cheapest_split(task, scale);

    // Up to kMaxLeafSize primitives make a leaf, tested together, four at once (Scene), for
    // about the cost of one test; unless the heuristic's split costs less still (large
    // primitives whose boxes together span far more than each does: the walls of a room;
    // docs/performance.md, design item 13). Never a median split: that is no saving.
    const bool sah_split = best.axis >= 0 && task.depth < static_cast<uint32_t>(kMedianSplitDepth);
    if (count <= static_cast<uint32_t>(Bvh::kMaxLeafSize) &&
        !(sah_split && best.cost < leaf_cost(count)))
        return std::nullopt;  // leaf

    const BuildRef* const split = sah_split ? partition_at_split(task, best, scale, left, right)
                                            : partition_at_median(task, left, right);
    return static_cast<uint32_t>(split - refs_);
}

// The task's primitives reordered at the heuristic's split: those in bins [0, best.bin] of its
// axis first.
BuildRef* BinaryBuilder::partition_at_split(const BuildTask& task, const Split& best,
                                            const Float4& scale, Extent& left, Extent& right) {
    const int axis = best.axis;
    const float lo = task.extent.centroids.lo[axis];
    assert(best.bin < kBins - 1);  // bin_at_most's condition: a bin follows the split's
    const auto bin_end = static_cast<float>(best.bin + 1);
    return partition(
        refs_ + task.begin, refs_ + task.end,
        [&](const Float4& centroid) {
            return bin_at_most(centroid[axis], lo, scale[axis], bin_end);
        },
        left, right);
}

// No usable split (all centroids coincide) or too deep: halve by count, along the longest axis
// of the centroids.
BuildRef* BinaryBuilder::partition_at_median(const BuildTask& task, Extent& left, Extent& right) {
    BuildRef* const first = refs_ + task.begin;
    BuildRef* const last = refs_ + task.end;
    const int axis = task.extent.centroids.bounds().longest_axis();
    BuildRef* const split = first + (task.end - task.begin) / 2;
    std::nth_element(first, split, last, [&](const BuildRef& a, const BuildRef& b) {
        return a.centroid(axis) < b.centroid(axis);
    });
    for (const BuildRef* r = first; r != split; ++r) left.add(*r);
    for (const BuildRef* r = split; r != last; ++r) right.add(*r);
    return split;
}

// Queues a node's two children on this thread, the left one first; but the larger to another
// thread, if one is idle and it is large enough.
void BinaryBuilder::queue_children(const BuildTask& left, const BuildTask& right,
                                   std::vector<BuildTask>& tasks) {
    const BuildTask& larger = left.end - left.begin >= right.end - right.begin ? left : right;
    bool handed = false;
    if (larger.end - larger.begin >= kSubtreeTask && workers_.claim()) {
        if (subtrees_handed_.fetch_add(1) < kMaxSubtrees)
            handed = workers_.start([this, larger] { subtree(larger); });
        else
            workers_.release();
    }
    if (!handed || &larger != &right) tasks.push_back(right);
    if (!handed || &larger != &left) tasks.push_back(left);
}

}  // namespace lessons::bvh_build
