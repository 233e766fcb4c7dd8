// Bounding volume hierarchy over primitive indices and their bounding boxes.
//
// The BVH knows boxes and indices only; the caller intersects primitives through a callback, so
// traversal is one loop for every kind of shape, inlined, with no virtual dispatch per primitive.
//
// Build: top-down, binned surface-area heuristic (Wald 2007). At each node the centroids are
// binned along each axis; the split minimising
//     cost = C_trav + (A_left C(N_left) + A_right C(N_right)) / A_node
// is taken, with C(n) = ceil(n / 4) + n / 4 the cost of a leaf of n in units of one test and
// C_trav = 1. A node of more than four primitives is always split, so there C_trav does not
// change which split wins; one of at most four is split only where the best such split costs
// less than its leaf, C(n) (and never below depth 64, where splits go by the median): in a room,
// two walls in one leaf have a box the size of the room, while each wall alone has a flat box
// that only the rays crossing it enter. A leaf's triangles are tested together, four at once
// (TriangleBlock), for about the cost of one test, hence the ceil(n / 4); the n / 4 keeps the
// leaves of small scenes tight (bvh_build.h, leaf_cost).
// Layout: the binary tree is then collapsed into an 8-wide one (Dammertz et al., "Shallow
// Bounding Volume Hierarchies for Fast SIMD Ray Tracing of Incoherent Rays", 2008; Embree's
// BVH8): a node holds the boxes of up to eight children side by side, the x minima of all eight,
// then their x maxima, and so on, so that one vector instruction tests one slab of eight boxes.
// Leaves are not nodes: a child slot names its primitives directly, so reaching a leaf costs no
// extra fetch. A node is 256 bytes, four cache lines, aligned.
// Primitives: callbacks receive a position in primitive_order(), not the caller's index; the
// caller stores its primitive data in that order (Scene does), so a leaf's primitives lie side
// by side in memory.
// Traversal: front to back. A node's eight boxes are tested at once; the children hit are pushed
// farthest first, so the nearest is visited next. A closest-hit query drops stacked subtrees that
// start beyond the nearest hit found so far; an any-hit query stops at the first hit. Memory is
// asked for before it is needed: a node's child indices as it is entered, a stacked node as it is
// pushed, so that a miss overlaps work instead of following it.
#pragma once

#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "accel/large_pages.h"
#include "geometry/bounds.h"
#include "geometry/math.h"
#include "geometry/simd.h"

namespace lessons {

// Children per node: 8, so that a node's boxes fill 256-bit (AVX) registers. Without AVX the
// compiler splits each operation in two SSE halves; the code is the same.
constexpr int kBvhWidth = 8;
using BoxLanes = Float8;
static_assert(kBvhWidth == 8);

struct alignas(64) BvhNode {
    // bounds[2 axis] holds the eight children's minima along the axis, bounds[2 axis + 1] their
    // maxima. An unused slot has an empty box (min +inf, max -inf), which no ray enters.
    BoxLanes bounds[6];
    // Interior child: its node index. Leaf: kLeafBit | (count - 1) << kCountShift | first.
    uint32_t child[kBvhWidth];

    static constexpr uint32_t kLeafBit = 1u << 31;
    static constexpr int kCountShift = 28;
    static constexpr uint32_t kMaxFirst = (1u << kCountShift) - 1;
    static bool is_leaf(uint32_t c) { return (c & kLeafBit) != 0; }
    static uint32_t leaf_first(uint32_t c) { return c & kMaxFirst; }
    static uint32_t leaf_count(uint32_t c) { return ((c >> kCountShift) & 7u) + 1; }
    static uint32_t make_leaf(uint32_t first, uint32_t count) {
        return kLeafBit | (count - 1) << kCountShift | first;
    }
    Bounds3 child_bounds(int i) const {
        return {Vec3(bounds[0][i], bounds[2][i], bounds[4][i]),
                Vec3(bounds[1][i], bounds[3][i], bounds[5][i])};
    }
};
static_assert(sizeof(BvhNode) == 256);

// A ray prepared for box tests: reciprocal direction and which slab plane is entered first.
struct BoxRay {
    Vec3 origin, inv_dir;
    int dir_negative[3];
    explicit BoxRay(const Ray& ray) : origin(ray.origin) {
        for (int i = 0; i < 3; ++i) {
            inv_dir[i] = 1.0f / ray.dir[i];  // +-inf for a zero component, handled below
            dir_negative[i] = std::signbit(ray.dir[i]);  // also -0: its inverse is -inf
        }
    }
};

// Entry distances of the ray into a node's eight boxes within (0, t_max), and an 8-bit mask of the
// boxes it enters (bit i: child i). The slab test, on eight boxes at once. Conservative (Ize,
// "Robust BVH Ray Traversal", JCGT 2013): the exit distance is enlarged by 1 + 2 gamma(3) so that
// rounding never culls a box the ray grazes, and a 0 * inf = NaN from a ray lying in a slab plane
// is ignored by the comparisons (treated as inside): `t0 > t_near ? t0 : t_near` keeps t_near
// when t0 is NaN.
struct BoxHits {
    BoxLanes t;  // entry distances (meaningful where the mask bit is set)
    unsigned mask;
};
[[gnu::always_inline]] inline BoxHits box_entries(const BoxRay& r, const BvhNode& node,
                                                  float t_max) {
    constexpr float kRobustScale = 1.0f + 2.0f * gamma_bound(3);
    BoxLanes t_near = BoxLanes{} + 0.0f, t_far = BoxLanes{} + t_max;
    for (int axis = 0; axis < 3; ++axis) {
        const BoxLanes& lo = node.bounds[2 * axis + r.dir_negative[axis]];      // entered
        const BoxLanes& hi = node.bounds[2 * axis + 1 - r.dir_negative[axis]];  // left
        const BoxLanes t0 = (lo - r.origin[axis]) * r.inv_dir[axis];
        const BoxLanes t1 = (hi - r.origin[axis]) * r.inv_dir[axis] * kRobustScale;
        t_near = t0 > t_near ? t0 : t_near;
        t_far = t1 < t_far ? t1 : t_far;
    }
    return {t_near, lane_bits(t_near <= t_far)};
}

// The same test for one box (the hard-case tests use it): the box in one slot of a node.
inline float box_entry(const BoxRay& r, const Vec3& box_min, const Vec3& box_max, float t_max) {
    BvhNode node;
    for (int axis = 0; axis < 3; ++axis) {
        node.bounds[2 * axis] = BoxLanes{} + kInfinity;
        node.bounds[2 * axis + 1] = BoxLanes{} - kInfinity;
        node.bounds[2 * axis][0] = box_min[axis];
        node.bounds[2 * axis + 1][0] = box_max[axis];
    }
    const BoxHits hits = box_entries(r, node, t_max);
    return hits.mask & 1u ? hits.t[0] : kInfinity;
}

class Bvh {
public:
    static constexpr int kMaxLeafSize = 4;
    // Every leaf starts at a multiple of this in the primitive order, so that a caller storing
    // primitives in blocks of four (Scene's triangles) finds a leaf in exactly one block. The
    // gaps hold kPadding.
    static constexpr uint32_t kLeafAlignment = 4;
    static constexpr uint32_t kPadding = 0xFFFFFFFFu;
    // Deepest possible binary tree: SAH splits down to depth 64 (bvh_binary.cpp), then median splits,
    // at most 32 more levels for 2^32 primitives. The wide tree is no deeper, and a visit
    // pushes at most kBvhWidth - 1 more entries than it pops.
    static constexpr int kMaxDepth = 96;
    static constexpr int kStackSize = (kBvhWidth - 1) * kMaxDepth + 1;

    Bvh() = default;
    // Builds over primitives 0 .. boxes.size()-1 with the given bounding boxes, on up to
    // `threads` threads (0: every hardware thread). The tree is the same on any number.
    explicit Bvh(std::span<const Bounds3> boxes, int threads = 0);

    const LargePageVector<BvhNode>& nodes() const { return nodes_; }
    // Position k of the primitive order holds primitive primitive_order()[k] (or kPadding, in
    // the gaps before aligned leaves); the callbacks below receive positions.
    const std::vector<uint32_t>& primitive_order() const { return prim_index_; }
    // Moves the order out, for a caller that keeps its own copy of it (Scene, in its primitive
    // references): the BVH then holds only its nodes, and primitive_order() is empty.
    std::vector<uint32_t> take_primitive_order() { return std::move(prim_index_); }
    Bounds3 bounds() const { return bounds_; }
    size_t memory_bytes() const;

    // Closest hit. `intersect(first, end, t_max)` tests the primitives at positions [first, end)
    // (one leaf) and, on a nearer hit, records it and lowers t_max (a float&) to its distance,
    // returning true.
    template <class IntersectFn>
    bool closest_hit(const Ray& ray, IntersectFn&& intersect) const;

    // Any hit in (0, ray.t_max). `occluded(first, end)` returns true if a primitive at positions
    // [first, end) (one leaf) blocks the ray.
    template <class OccludedFn>
    bool any_hit(const Ray& ray, OccludedFn&& occluded) const;

private:
    // Asks for the four cache lines of a child kept for later, if it is a node, without waiting
    // for them: by the time it is popped they have usually arrived (docs/performance.md, design
    // item 11). A leaf's primitives are the caller's, so a leaf is left alone.
    void prefetch(uint32_t child) const {
        if (BvhNode::is_leaf(child)) return;
        const char* bytes = reinterpret_cast<const char*>(&nodes_[child]);
        for (int line = 0; line < 4; ++line) __builtin_prefetch(bytes + 64 * line);
    }

    LargePageVector<BvhNode> nodes_;  // nodes_[0] is the root (large_pages.h)
    std::vector<uint32_t> prim_index_;
    Bounds3 bounds_;
};

template <class IntersectFn>
bool Bvh::closest_hit(const Ray& ray, IntersectFn&& intersect) const {
    // A ray with a NaN or infinite coordinate would enter every box, empty slots included
    // (the slab test ignores NaN): it hits nothing.
    if (nodes_.empty() || !is_finite(ray.origin) || !is_finite(ray.dir)) return false;
    const BoxRay box_ray(ray);
    float t_max = ray.t_max;
    bool found = false;
    struct Entry {
        uint32_t child;  // a node index or a leaf, as in BvhNode::child
        float t;         // where the ray enters its box
    };
    Entry stack[kStackSize];
    int top = 0;
    uint32_t current = 0;  // the root
    for (;;) {
        if (BvhNode::is_leaf(current)) {
            const uint32_t first = BvhNode::leaf_first(current);
            found |= intersect(first, first + BvhNode::leaf_count(current), t_max);
        } else {
            const BvhNode& node = nodes_[current];
            // The box test reads the node's first three cache lines; the child indices, in the
            // fourth, are needed only after it. Ask for them now, so that their miss overlaps
            // the box test's instead of following it (docs/performance.md, design item 11).
            __builtin_prefetch(node.child);
            const BoxHits hits = box_entries(box_ray, node, t_max);
            if (hits.mask != 0) {
                // Visit the nearest child next; push the others farthest first, so that they
                // are popped in order of distance (an insertion sort of at most seven, among
                // this node's children only: the traversal stays depth first, which bounds the
                // stack).
                const int base = top;  // this node's entries start here
                int nearest = std::countr_zero(hits.mask);
                for (unsigned m = hits.mask & (hits.mask - 1); m != 0; m &= m - 1) {
                    int i = std::countr_zero(m);
                    if (hits.t[i] < hits.t[nearest]) std::swap(i, nearest);
                    int j = top++;
                    for (; j > base && stack[j - 1].t < hits.t[i]; --j) stack[j] = stack[j - 1];
                    stack[j] = {node.child[i], hits.t[i]};
                    prefetch(node.child[i]);  // wasted only if a nearer hit drops it later
                }
                current = node.child[nearest];  // read at once, next turn: no need to ask ahead
                continue;
            }
        }
        // Pop, skipping subtrees that start beyond the nearest hit found since they were pushed.
        do {
            if (top == 0) return found;
            --top;
        } while (stack[top].t > t_max);
        current = stack[top].child;
    }
}

template <class OccludedFn>
bool Bvh::any_hit(const Ray& ray, OccludedFn&& occluded) const {
    if (nodes_.empty() || !is_finite(ray.origin) || !is_finite(ray.dir)) return false;
    const BoxRay box_ray(ray);
    uint32_t stack[kStackSize];
    int top = 0;
    uint32_t current = 0;  // the root
    for (;;) {
        if (BvhNode::is_leaf(current)) {
            const uint32_t first = BvhNode::leaf_first(current);
            if (occluded(first, first + BvhNode::leaf_count(current))) return true;
        } else {
            const BvhNode& node = nodes_[current];
            __builtin_prefetch(node.child);  // as in closest_hit
            const unsigned mask = box_entries(box_ray, node, ray.t_max).mask;
            if (mask != 0) {
                // Any order will do; go on with one child, keep the others for later.
                for (unsigned m = mask & (mask - 1); m != 0; m &= m - 1) {
                    const uint32_t child = node.child[std::countr_zero(m)];
                    stack[top++] = child;
                    prefetch(child);
                }
                current = node.child[std::countr_zero(mask)];
                continue;
            }
        }
        if (top == 0) return false;
        current = stack[--top];
    }
}

}  // namespace lessons
