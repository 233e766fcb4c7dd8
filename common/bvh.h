// Bounding volume hierarchy over primitive indices and their bounding boxes.
//
// The BVH knows boxes and indices only; the caller intersects primitives through a callback, so
// traversal is one loop for every kind of shape, inlined, with no virtual dispatch per primitive.
//
// Build: top-down, binned surface-area heuristic (Wald 2007). At each node the centroids are
// binned along each axis; the split minimising
//     cost = C_trav + (A_left N_left + A_right N_right) / A_node      (C_isect = 1)
// is taken, or a leaf is made when that is cheaper than splitting.
// Layout: nodes are flattened into an array of 32-byte records; the two children of an interior
// node are stored side by side, so one index names both.
// Traversal: front to back. Both children's boxes are tested, the nearer is visited first and the
// farther pushed; a closest-hit query skips boxes beyond the nearest hit found so far, an any-hit
// query stops at the first hit.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bounds.h"
#include "math.h"

namespace lessons {

struct BvhNode {
    Vec3 box_min;
    uint32_t first;  // interior: index of the left child (right = first + 1); leaf: first primitive
    Vec3 box_max;
    uint32_t count;  // number of primitives in a leaf; 0 for an interior node
};
static_assert(sizeof(BvhNode) == 32);

// A ray prepared for box tests: reciprocal direction and which slab plane is entered first.
struct BoxRay {
    Vec3 origin, inv_dir;
    int dir_negative[3];
    explicit BoxRay(const Ray& ray) : origin(ray.origin) {
        for (int i = 0; i < 3; ++i) {
            inv_dir[i] = 1.0f / ray.dir[i];  // +-inf for a zero component, handled below
            dir_negative[i] = ray.dir[i] < 0.0f || std::signbit(ray.dir[i]);
        }
    }
};

// Entry distance of the ray into box [box_min, box_max] within (0, t_max), or +inf on a miss.
// Conservative (Ize, "Robust BVH Ray Traversal", JCGT 2013): the exit distance is enlarged by
// 1 + 2 gamma(3) so that rounding never culls a box the ray grazes, and a 0 * inf = NaN from a
// ray lying in a slab plane is ignored by the comparisons (treated as inside).
[[gnu::always_inline]] inline float box_entry(const BoxRay& r, const Vec3& box_min,
                                              const Vec3& box_max, float t_max) {
    constexpr float kRobustScale = 1.0f + 2.0f * gamma_bound(3);
    float t_near = 0.0f, t_far = t_max;
    for (int i = 0; i < 3; ++i) {
        const float lo = r.dir_negative[i] ? box_max[i] : box_min[i];
        const float hi = r.dir_negative[i] ? box_min[i] : box_max[i];
        const float t0 = (lo - r.origin[i]) * r.inv_dir[i];
        const float t1 = (hi - r.origin[i]) * r.inv_dir[i] * kRobustScale;
        t_near = t0 > t_near ? t0 : t_near;
        t_far = t1 < t_far ? t1 : t_far;
    }
    return t_near <= t_far ? t_near : kInfinity;
}

class Bvh {
public:
    static constexpr int kMaxLeafSize = 4;
    // Deepest possible tree: SAH splits down to depth 64 (bvh.cpp), then median splits, at most
    // 32 more levels for 2^32 primitives. Traversal stacks hold one entry per level.
    static constexpr int kStackSize = 128;

    Bvh() = default;
    // Builds over primitives 0 .. boxes.size()-1 with the given bounding boxes.
    explicit Bvh(std::span<const Bounds3> boxes);

    const std::vector<BvhNode>& nodes() const { return nodes_; }
    const std::vector<uint32_t>& primitive_order() const { return prim_index_; }
    Bounds3 bounds() const;
    size_t memory_bytes() const;

    // Closest hit. `intersect(prim, t_max)` tests primitive `prim` and, on a nearer hit, records
    // it and lowers t_max (a float&) to its distance, returning true.
    template <class IntersectFn>
    bool closest_hit(const Ray& ray, IntersectFn&& intersect) const;

    // Any hit in (0, ray.t_max). `occluded(prim)` returns true if primitive `prim` blocks the ray.
    template <class OccludedFn>
    bool any_hit(const Ray& ray, OccludedFn&& occluded) const;

private:
    std::vector<BvhNode> nodes_;
    std::vector<uint32_t> prim_index_;
};

template <class IntersectFn>
bool Bvh::closest_hit(const Ray& ray, IntersectFn&& intersect) const {
    if (nodes_.empty()) return false;
    const BoxRay box_ray(ray);
    float t_max = ray.t_max;
    bool found = false;
    uint32_t stack[kStackSize];
    int top = 0;
    uint32_t node_index = 0;
    if (box_entry(box_ray, nodes_[0].box_min, nodes_[0].box_max, t_max) == kInfinity) return false;
    for (;;) {
        const BvhNode& node = nodes_[node_index];
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i)
                found |= intersect(prim_index_[i], t_max);
        } else {
            const BvhNode& left = nodes_[node.first];
            const BvhNode& right = nodes_[node.first + 1];
            float t_left = box_entry(box_ray, left.box_min, left.box_max, t_max);
            float t_right = box_entry(box_ray, right.box_min, right.box_max, t_max);
            uint32_t near = node.first, far = node.first + 1;
            if (t_right < t_left) {
                std::swap(t_left, t_right);
                std::swap(near, far);
            }
            if (t_left != kInfinity) {
                if (t_right != kInfinity) stack[top++] = far;
                node_index = near;
                continue;
            }
        }
        // Pop, skipping subtrees whose boxes now lie beyond the nearest hit.
        for (;;) {
            if (top == 0) return found;
            node_index = stack[--top];
            const BvhNode& n = nodes_[node_index];
            if (box_entry(box_ray, n.box_min, n.box_max, t_max) != kInfinity) break;
        }
    }
}

template <class OccludedFn>
bool Bvh::any_hit(const Ray& ray, OccludedFn&& occluded) const {
    if (nodes_.empty()) return false;
    const BoxRay box_ray(ray);
    const float t_max = ray.t_max;
    uint32_t stack[kStackSize];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const BvhNode& node = nodes_[stack[--top]];
        if (box_entry(box_ray, node.box_min, node.box_max, t_max) == kInfinity) continue;
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i)
                if (occluded(prim_index_[i])) return true;
        } else {
            stack[top++] = node.first + 1;
            stack[top++] = node.first;
        }
    }
    return false;
}

}  // namespace lessons
