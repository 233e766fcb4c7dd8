// Binned-SAH construction of the BVH (traversal is in bvh.h).
#include "bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace lessons {

namespace {

constexpr int kBins = 16;
constexpr float kTraversalCost = 1.0f;  // relative to one primitive intersection
constexpr int kMedianSplitDepth = 64;   // deeper than this, split at the median (see kStackSize)

struct Bin {
    Bounds3 bounds;
    uint32_t count = 0;
};

struct BuildTask {
    uint32_t node, begin, end, depth;
};

struct Split {
    int axis = -1;
    int bin = 0;  // primitives in bins [0, bin] go left
    float cost = kInfinity;
};

int bin_of(float centroid, float lo, float scale) {
    const float b = (centroid - lo) * scale;
    if (!(b > 0.0f)) return 0;  // also catches NaN
    if (!(b < static_cast<float>(kBins))) return kBins - 1;
    return static_cast<int>(b);
}

}  // namespace

Bvh::Bvh(std::span<const Bounds3> boxes) {
    const uint32_t n = static_cast<uint32_t>(boxes.size());
    if (n == 0) return;
    prim_index_.resize(n);
    std::iota(prim_index_.begin(), prim_index_.end(), 0u);
    std::vector<Vec3> centroids(n);
    for (uint32_t i = 0; i < n; ++i) centroids[i] = boxes[i].centroid();

    nodes_.reserve(2 * n);
    nodes_.push_back({});
    std::vector<BuildTask> tasks{{0, 0, n, 0}};
    while (!tasks.empty()) {
        const BuildTask task = tasks.back();
        tasks.pop_back();
        const uint32_t count = task.end - task.begin;

        Bounds3 node_box, centroid_box;
        for (uint32_t i = task.begin; i < task.end; ++i) {
            node_box.expand(boxes[prim_index_[i]]);
            centroid_box.expand(centroids[prim_index_[i]]);
        }
        BvhNode& node = nodes_[task.node];
        node.box_min = node_box.min;
        node.box_max = node_box.max;
        node.first = task.begin;
        node.count = count;
        if (count == 1) continue;

        // Find the cheapest binned SAH split over the three axes.
        Split best;
        const float node_area = node_box.surface_area();
        for (int axis = 0; axis < 3; ++axis) {
            const float lo = centroid_box.min[axis], hi = centroid_box.max[axis];
            if (!(hi > lo)) continue;
            const float scale = kBins / (hi - lo);
            if (!std::isfinite(scale)) continue;  // extent below float resolution
            std::array<Bin, kBins> bins{};
            for (uint32_t i = task.begin; i < task.end; ++i) {
                const uint32_t p = prim_index_[i];
                Bin& b = bins[bin_of(centroids[p][axis], lo, scale)];
                b.bounds.expand(boxes[p]);
                ++b.count;
            }
            // Sweep from the right to get the area and count of every right-hand side.
            std::array<float, kBins> right_area{};
            std::array<uint32_t, kBins> right_count{};
            Bounds3 acc;
            uint32_t acc_count = 0;
            for (int b = kBins - 1; b > 0; --b) {
                acc.expand(bins[b].bounds);
                acc_count += bins[b].count;
                right_area[b] = acc.surface_area();
                right_count[b] = acc_count;
            }
            acc = Bounds3{};
            acc_count = 0;
            for (int b = 0; b < kBins - 1; ++b) {
                acc.expand(bins[b].bounds);
                acc_count += bins[b].count;
                if (acc_count == 0 || right_count[b + 1] == 0) continue;
                const float cost = kTraversalCost + (acc.surface_area() * acc_count +
                                                     right_area[b + 1] * right_count[b + 1]) /
                                                        node_area;
                if (cost < best.cost) best = {axis, b, cost};
            }
        }

        const bool small = count <= static_cast<uint32_t>(kMaxLeafSize);
        if (small && (best.axis < 0 || best.cost >= static_cast<float>(count))) continue;  // leaf

        uint32_t mid;
        auto* first = prim_index_.data() + task.begin;
        auto* last = prim_index_.data() + task.end;
        if (best.axis >= 0 && task.depth < static_cast<uint32_t>(kMedianSplitDepth)) {
            const int axis = best.axis;
            const float lo = centroid_box.min[axis];
            const float scale = kBins / (centroid_box.max[axis] - lo);
            auto* split = std::partition(first, last, [&](uint32_t p) {
                return bin_of(centroids[p][axis], lo, scale) <= best.bin;
            });
            mid = static_cast<uint32_t>(split - prim_index_.data());
        } else {
            // No usable split (all centroids coincide) or too deep: halve by count.
            const int axis = centroid_box.longest_axis();
            mid = task.begin + count / 2;
            std::nth_element(first, prim_index_.data() + mid, last, [&](uint32_t a, uint32_t b) {
                return centroids[a][axis] < centroids[b][axis];
            });
        }

        const uint32_t left = static_cast<uint32_t>(nodes_.size());
        nodes_.push_back({});
        nodes_.push_back({});
        nodes_[task.node].first = left;  // re-index: push_back may have moved `node`
        nodes_[task.node].count = 0;
        tasks.push_back({left + 1, mid, task.end, task.depth + 1});
        tasks.push_back({left, task.begin, mid, task.depth + 1});
    }
    nodes_.shrink_to_fit();
}

Bounds3 Bvh::bounds() const {
    if (nodes_.empty()) return {};
    return {nodes_[0].box_min, nodes_[0].box_max};
}

size_t Bvh::memory_bytes() const {
    return nodes_.capacity() * sizeof(BvhNode) + prim_index_.capacity() * sizeof(uint32_t);
}

}  // namespace lessons
