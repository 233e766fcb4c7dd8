// The construction of the BVH (traversal is in bvh.h), on one thread or several, in three steps:
// the primitives' boxes copied for the build, the binary tree built over them by the binned
// surface area heuristic (bvh_binary.cpp, bvh_sah.cpp), then collapsed into 8-wide nodes along
// the cut of least cost (bvh_wide.cpp). What the steps share is in bvh_build.h.
#include "accel/bvh.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "accel/bvh_build.h"
#include "accel/parallel.h"

namespace lessons {

using namespace bvh_build;  // (in this file only: the build's steps)

namespace {

// The passes over every primitive give each thread at least this many.
constexpr size_t kMinPart = 16384;

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
    collapse_to_wide(binary.get(), builder.nodes_taken(), n >= kMinPart ? threads : 1, build_order,
                     nodes_, prim_index_);
    nodes_.shrink_to_fit();
    prim_index_.shrink_to_fit();
    if (prim_index_.size() > BvhNode::kMaxFirst)
        throw std::length_error("too many primitives for one BVH: " + std::to_string(n));
}

size_t Bvh::memory_bytes() const {
    return nodes_.capacity() * sizeof(BvhNode) + prim_index_.capacity() * sizeof(uint32_t);
}

}  // namespace lessons
