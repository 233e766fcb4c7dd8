// Binned-SAH construction of the BVH (traversal is in bvh.h), on one thread or several.
#include "accel/bvh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cassert>
#include <cmath>
#include <exception>
#include <list>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>

#include "accel/parallel.h"

namespace lessons {

namespace {

constexpr int kBins = 16;
constexpr float kTraversalCost = 1.0f;  // relative to one primitive intersection
constexpr int kMedianSplitDepth = 64;   // deeper than this, split at the median (see kStackSize)
// A subtree of at least this many primitives may be built by another thread, and a node of at
// least kParallelBinning primitives is binned by every idle thread at once (up to 16). Below, a
// thread's start costs more than it saves.
constexpr uint32_t kSubtreeTask = 4096;
constexpr uint32_t kParallelBinning = 1u << 16;
// A thread takes nodes from the shared array kNodeChunk at a time, so that two threads never
// write nodes in the same cache line (nor the shared counter at every node): measured, taking
// them two at a time made the build on two threads do 50% more work than on one. The array has
// room for every subtree's last chunk, partly unused: at most kMaxSubtrees subtrees are handed
// to other threads.
constexpr uint32_t kNodeChunk = 256;
// The passes over every primitive give each thread at least this many.
constexpr size_t kMinPart = 16384;
constexpr uint32_t kMaxSubtrees = 1024;

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

struct BuildTask {
    uint32_t node, begin, end, depth;
    Extent extent;  // of primitives [begin, end)
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

// A centroid's bin along an axis whose centroids start at lo, with `scale` bins per unit, is the
// integer part of b = (centroid - lo) scale, clamped to [0, kBins - 1]; a NaN b (from a NaN
// coordinate) is in bin 0 (Bins::bins_of). Whether that bin is at most `bin`, for a bin before
// the last (a split's: some occupied bin follows it), by one comparison: b <= 0 or NaN is bin 0;
// b in [0, kBins) is in bin trunc(b), at most `bin` exactly where b < bin + 1 (a float,
// exactly); b >= kBins is in the last bin, beyond `bin`, and there b >= bin + 1 too.
bool bin_at_most(float centroid, float lo, float scale, float bin_end) {
    return !((centroid - lo) * scale >= bin_end);  // bin_end = bin + 1
}

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

// Starts threads for parts of the build while some of the allowed ones are idle, and joins them.
class Workers {
public:
    explicit Workers(int threads) : idle_(build_threads(threads) - 1) {}
    // Takes an idle thread, if there is one, for the caller to start with start().
    bool claim() {
        int n = idle_.load(std::memory_order_relaxed);
        while (n > 0)
            if (idle_.compare_exchange_weak(n, n - 1)) return true;
        return false;
    }
    void release() { idle_.fetch_add(1); }
    // Runs work() on a new thread (claimed before), which becomes idle again when it returns.
    // Returns false, with the claim released, if the system refuses a thread (or memory for
    // it): the caller then does the work itself. Threads that have finished are joined here, so
    // that their stacks go back as the build goes on. An exception thrown by work() (memory
    // running out) is kept, and join_all() throws it.
    template <class Work>
    bool start(Work work) {
        std::lock_guard<std::mutex> lock(mutex_);
        try {
            for (auto t = started_.begin(); t != started_.end();) {
                if (t->done->load()) {
                    t->thread.join();
                    t = started_.erase(t);
                } else {
                    ++t;
                }
            }
            started_.emplace_back();  // before the thread: a thread is never left unowned
            Started& entry = started_.back();
            entry.done = std::make_shared<std::atomic<bool>>(false);
            try {
                entry.thread = std::thread([this, work, done = entry.done] {
                    try {
                        work();
                    } catch (...) {
                        std::lock_guard<std::mutex> failed(mutex_);
                        if (!failure_) failure_ = std::current_exception();
                    }
                    release();
                    done->store(true);
                });
            } catch (...) {
                started_.pop_back();
                throw;
            }
            return true;
        } catch (const std::exception&) {  // std::system_error, std::bad_alloc
            release();
            return false;
        }
    }
    // Joins every thread started, including those started by threads started; then throws what
    // any of them threw.
    void join_all() {
        for (;;) {
            std::thread t;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                if (started_.empty()) break;
                t = std::move(started_.back().thread);
                started_.pop_back();
            }
            t.join();
        }
        if (failure_) std::rethrow_exception(failure_);
    }

private:
    struct Started {
        std::thread thread;
        std::shared_ptr<std::atomic<bool>> done;
    };
    std::atomic<int> idle_;
    std::mutex mutex_;
    std::list<Started> started_;
    std::exception_ptr failure_;  // the first exception a started thread threw
};

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

// The binary tree over `refs`, reordering them so that every node's primitives are contiguous;
// node 0 is the root. Subtrees are built by as many threads as allowed, each into nodes it takes
// from a shared counter: which thread builds what, and the nodes' numbering, vary from run to
// run, but every node's primitives, box and split do not (binning merges per-thread bins by
// minima, maxima and sums, whose results do not depend on the order), so the tree collapsed
// from node 0 (Collapse, depth first) is the same bits on any number of threads.
class BinaryBuilder {
public:
    BinaryBuilder(BuildRef* refs, uint32_t count, int threads)
        : refs_(refs), count_(count),
          nodes_(new BinaryNode[2 * size_t{count} + size_t{kNodeChunk} * (kMaxSubtrees + 1)]),
          workers_(threads) {}

    // Every node of the tree, at most 2 n - 1; node 0 is the root.
    std::unique_ptr<BinaryNode[]> build(const Extent& root) {
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
    // After build(): at least the number of nodes used (some chunks' ends are unused).
    uint32_t nodes_taken() const { return next_node_.load(); }

private:
    void subtree(BuildTask root);
    Split cheapest_split(const BuildTask& task, Float4& scale);

    BuildRef* const refs_;
    const uint32_t count_;
    std::unique_ptr<BinaryNode[]> nodes_;
    std::atomic<uint32_t> next_node_{1};  // the first node of the next chunk
    std::atomic<uint32_t> subtrees_handed_{0};
    Workers workers_;
};

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

// The cost of splitting a node of area node_area in two: kTraversalCost + weight / node_area,
// where the weight is the sum over the two sides of area x leaf_cost(count).
float side_weight(float area, uint32_t count) { return area * leaf_cost(count); }
float split_cost(float weight, float node_area) { return kTraversalCost + weight / node_area; }

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
    BuildRef* const first = refs_ + task.begin;
    BuildRef* const last = refs_ + task.end;
    const uint32_t count = task.end - task.begin;
    const float node_area = task.extent.box.bounds().surface_area();
    Bins bins;
    int helpers = 0;
    while (count >= kParallelBinning && helpers < 15 && workers_.claim()) ++helpers;
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
        } claims{workers_, helpers};
        std::vector<Bins> partial(static_cast<size_t>(helpers + 1));
        parallel_parts(count, helpers + 1, 1, [&](size_t begin, size_t end, int part) {
            partial[part].add(first + begin, first + end, lo, scale);
        });
        for (const Bins& p : partial) bins.add(p);
    }

    // The sweep visits occupied bins only: most nodes hold a few primitives (the leaves'
    // parents, and the leaves, which may still be split), and sweeping all 16 bins of each axis
    // took half the build's time there. A split after an empty bin costs what the split before
    // it costs, and the first of equal costs is kept, so skipping it changes nothing: the
    // answer is that of the full sweep, bit for bit.
    Split best;
    float best_weight = kInfinity;
    for (int axis = 0; axis < 3; ++axis) {
        if (!usable[axis]) continue;
        const uint32_t occupied = bins.occupied(axis);
        // Sweep from the right to get the weight (area x leaf cost) of every right-hand side,
        // each stored at the right side's first occupied bin. A side is itself a bin (its box
        // and count), grown bin by bin.
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
    return best;
}

// Builds the subtree of `root` (whose node index is taken), handing the larger child of a node to
// an idle thread whenever there is one and the child is large enough.
void BinaryBuilder::subtree(BuildTask root) {
    uint32_t next = 0, chunk_end = 0;  // this subtree's nodes still free in its chunk
    std::vector<BuildTask> tasks{root};
    while (!tasks.empty()) {
        const BuildTask task = tasks.back();
        tasks.pop_back();
        const uint32_t count = task.end - task.begin;
        BuildRef* const first = refs_ + task.begin;
        BuildRef* const last = refs_ + task.end;

        BinaryNode& node = nodes_[task.node];
        const Bounds3 node_box = task.extent.box.bounds();
        for (int axis = 0; axis < 3; ++axis) {
            node.lo[axis] = node_box.min[axis];
            node.hi[axis] = node_box.max[axis];
        }
        node.first = task.begin;
        node.count = count;
        if (count == 1) continue;
        if (count <= static_cast<uint32_t>(Bvh::kMaxLeafSize) &&
            no_split_beats_leaf(first, last, node_box.surface_area()))
            continue;  // a leaf, as the search below would decide

        Float4 scale;
        const Split best = cheapest_split(task, scale);

        // Up to kMaxLeafSize primitives make a leaf, tested together, four at once (Scene), for
        // about the cost of one test; unless the heuristic's split costs less still (large
        // primitives whose boxes together span far more than each does: the walls of a room;
        // docs/performance.md, design item 13). Never a median split: that is no saving.
        const bool sah_split =
            best.axis >= 0 && task.depth < static_cast<uint32_t>(kMedianSplitDepth);
        if (count <= static_cast<uint32_t>(Bvh::kMaxLeafSize) &&
            !(sah_split && best.cost < leaf_cost(count)))
            continue;  // leaf

        BuildRef* split;
        Extent left, right;
        if (sah_split) {
            const int axis = best.axis;
            const float lo = task.extent.centroids.lo[axis];
            assert(best.bin < kBins - 1);  // bin_at_most's condition: a bin follows the split's
            const auto bin_end = static_cast<float>(best.bin + 1);
            split = partition(
                first, last,
                [&](const Float4& centroid) {
                    return bin_at_most(centroid[axis], lo, scale[axis], bin_end);
                },
                left, right);
        } else {
            // No usable split (all centroids coincide) or too deep: halve by count.
            const int axis = task.extent.centroids.bounds().longest_axis();
            split = first + count / 2;
            std::nth_element(first, split, last, [&](const BuildRef& a, const BuildRef& b) {
                return a.centroid(axis) < b.centroid(axis);
            });
            for (const BuildRef* r = first; r != split; ++r) left.add(*r);
            for (const BuildRef* r = split; r != last; ++r) right.add(*r);
        }
        const auto mid = static_cast<uint32_t>(split - refs_);

        if (next == chunk_end) {
            next = next_node_.fetch_add(kNodeChunk, std::memory_order_relaxed);
            chunk_end = next + kNodeChunk;
        }
        const uint32_t children = next;
        next += 2;
        node.first = children;
        node.count = 0;
        BuildTask left_task{children, task.begin, mid, task.depth + 1, left};
        BuildTask right_task{children + 1, mid, task.end, task.depth + 1, right};
        // The larger child to another thread, if one is idle; else both here, left first.
        BuildTask& larger = mid - task.begin >= task.end - mid ? left_task : right_task;
        bool handed = false;
        if (larger.end - larger.begin >= kSubtreeTask && workers_.claim()) {
            if (subtrees_handed_.fetch_add(1) < kMaxSubtrees)
                handed = workers_.start([this, larger] { subtree(larger); });
            else
                workers_.release();
        }
        if (!handed || &larger != &right_task) tasks.push_back(right_task);
        if (!handed || &larger != &left_task) tasks.push_back(left_task);
    }
}

}  // namespace

Bvh::Bvh(std::span<const Bounds3> boxes, int threads) {
    const uint32_t n = static_cast<uint32_t>(boxes.size());
    if (n == 0) return;
    if (boxes.size() > BvhNode::kMaxFirst)
        throw std::length_error("too many primitives for one BVH: " + std::to_string(boxes.size()));
    threads = build_threads(threads);
    std::unique_ptr<BuildRef[]> refs(new BuildRef[n]);  // not initialised: filled below
    std::vector<Extent> extents(static_cast<size_t>(part_count(n, threads, kMinPart)));
    parallel_parts(n, threads, kMinPart, [&](size_t begin, size_t end, int part) {
        for (size_t i = begin; i < end; ++i) {
            refs[i] = BuildRef::of(boxes[i], static_cast<uint32_t>(i));
            extents[part].add(refs[i]);
        }
    });
    Extent root;
    for (const Extent& e : extents) root.add(e);
    BinaryBuilder builder(refs.get(), n, threads);
    const std::unique_ptr<BinaryNode[]> binary = builder.build(root);

    // Collapse the binary tree into wide nodes.
    bounds_ = binary[0].box();
    std::vector<uint32_t> build_order(n);
    parallel_parts(n, threads, kMinPart, [&](size_t begin, size_t end, int) {
        for (size_t i = begin; i < end; ++i) build_order[i] = refs[i].prim();
    });
    refs.reset();
    prim_index_.reserve(n + n / 2);
    const WideCut cut(binary.get(), builder.nodes_taken(), n >= kMinPart ? threads : 1);
    Collapse collapse{binary.get(), cut, build_order, nodes_, prim_index_};
    // The root is always a wide node, even over a single leaf.
    nodes_.reserve(builder.nodes_taken() / 3 + 1);
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
