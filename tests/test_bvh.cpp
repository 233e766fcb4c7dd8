// The BVH must return exactly what a brute-force loop over every primitive returns.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "accel/bvh.h"
#include "accel/parallel.h"
#include "io/input_file.h"
#include "scene/scene.h"
#include "test_util.h"

using namespace lessons;

namespace {

// Nearest hit by testing every primitive.
std::optional<Hit> brute_force(const Scene& scene, const Ray& ray) {
    std::optional<Hit> best;
    float t_max = ray.t_max;
    const WatertightRay wr(ray);
    auto consider = [&](PrimRef prim, bool hit, const ShapeHit& h) {
        if (hit && h.t < t_max) {
            t_max = h.t;
            best = Hit{h, prim};
        }
    };
    for (uint32_t i = 0; i < scene.spheres().size(); ++i) {
        ShapeHit h;
        Ray r = ray;
        r.t_max = t_max;
        consider(PrimRef(ShapeKind::Sphere, i), intersect_sphere(scene.spheres()[i], r, h), h);
    }
    for (uint32_t i = 0; i < scene.quads().size(); ++i) {
        ShapeHit h;
        Ray r = ray;
        r.t_max = t_max;
        consider(PrimRef(ShapeKind::Quad, i), intersect_quad(scene.quads()[i], r, h), h);
    }
    for (uint32_t i = 0; i < scene.triangles().size(); ++i) {
        const Triangle& t = scene.triangles()[i];
        ShapeHit h;
        consider(PrimRef(ShapeKind::Triangle, i),
                 intersect_triangle(wr, scene.positions()[t.v[0]], scene.positions()[t.v[1]],
                                    scene.positions()[t.v[2]], t_max, h),
                 h);
    }
    return best;
}

Scene random_scene(uint64_t seed, int spheres, int quads, int triangles, float extent) {
    Rng rng(seed);
    Scene scene;
    const uint32_t m = test::add_diffuse(scene, Color(0.5f));
    for (int i = 0; i < spheres; ++i)
        scene.add_sphere(
            {test::random_in_box(rng, -extent, extent), extent * (0.002f + 0.05f * rng.uniform())},
            m);
    for (int i = 0; i < quads; ++i) {
        const Vec3 c = test::random_in_box(rng, -extent, extent);
        scene.add_quad(Quad(c, 0.1f * extent * test::random_unit_vector(rng),
                            0.1f * extent * test::random_unit_vector(rng)),
                       m);
    }
    std::vector<Vec3> positions;
    std::vector<Triangle> tris;
    for (int i = 0; i < triangles; ++i) {
        const Vec3 c = test::random_in_box(rng, -extent, extent);
        const float size = extent * (0.005f + 0.1f * rng.uniform());
        for (int k = 0; k < 3; ++k) positions.push_back(c + size * test::random_unit_vector(rng));
        const uint32_t b = static_cast<uint32_t>(3 * i);
        tris.push_back({{b, b + 1, b + 2}, m, false});
    }
    scene.add_mesh(positions, {}, {}, tris);
    scene.commit();
    return scene;
}

}  // namespace

class BvhAgainstBruteForce : public ::testing::TestWithParam<int> {};

TEST_P(BvhAgainstBruteForce, ClosestAndAnyHitAreExactlyTheBruteForceAnswers) {
    const int seed = GetParam();
    const float extent = seed % 2 ? 1.0f : 1000.0f;
    const Scene scene = random_scene(seed, 200, 100, 2000, extent);
    Rng rng(seed + 100);
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        Ray ray{test::random_in_box(rng, -1.5f * extent, 1.5f * extent),
                test::random_unit_vector(rng)};
        if (i % 3 == 0) ray.t_max = extent * rng.uniform();  // segments, as shadow rays are
        const std::optional<Hit> expected = brute_force(scene, ray);
        const std::optional<Hit> got = scene.intersect(ray);
        ASSERT_EQ(expected.has_value(), got.has_value()) << "ray " << i;
        if (expected) {
            ++hits;
            ASSERT_EQ(expected->shape.t, got->shape.t) << "ray " << i;
            // (Two primitives at exactly the same distance may differ in which one is reported;
            // the distance may not.)
        }
        ASSERT_EQ(scene.occluded(ray), expected.has_value()) << "ray " << i;
        // Scene::meets, one primitive without the BVH: the one hit is met, and some primitive is
        // met exactly when the segment is blocked.
        if (got) {
            ASSERT_TRUE(scene.meets(got->prim, ray)) << "ray " << i;
        }
        if (i % 50 == 0) {
            bool met = false;
            for (uint32_t k = 0; k < scene.spheres().size(); ++k)
                met |= scene.meets(PrimRef(ShapeKind::Sphere, k), ray);
            for (uint32_t k = 0; k < scene.quads().size(); ++k)
                met |= scene.meets(PrimRef(ShapeKind::Quad, k), ray);
            for (uint32_t k = 0; k < scene.triangles().size(); ++k)
                met |= scene.meets(PrimRef(ShapeKind::Triangle, k), ray);
            ASSERT_EQ(met, expected.has_value()) << "ray " << i;
        }
    }
    EXPECT_GT(hits, 1000);  // the test exercised hits, not only misses
}

INSTANTIATE_TEST_SUITE_P(RandomScenes, BvhAgainstBruteForce, ::testing::Values(1, 2, 3, 4));

TEST(Bvh, EveryPrimitiveIsInExactlyOneLeafAndBoxesNest) {
    const Scene scene = random_scene(9, 50, 50, 5000, 10.0f);
    const Bvh& bvh = scene.bvh();
    std::vector<int> seen(scene.primitive_count(), 0);
    // Walk the 8-wide tree from the root: each slot's box lies inside its parent's box.
    std::vector<std::pair<uint32_t, Bounds3>> todo = {{0u, bvh.bounds()}};
    int nodes = 0;
    while (!todo.empty()) {
        const auto [index, parent_box] = todo.back();
        todo.pop_back();
        ++nodes;
        const BvhNode& n = bvh.nodes()[index];
        for (int i = 0; i < kBvhWidth; ++i) {
            const Bounds3 box = n.child_bounds(i);
            if (box.min.x > box.max.x) continue;  // an unused slot
            for (int a = 0; a < 3; ++a) {
                EXPECT_LE(parent_box.min[a], box.min[a]);
                EXPECT_GE(parent_box.max[a], box.max[a]);
            }
            if (BvhNode::is_leaf(n.child[i])) {
                const uint32_t first = BvhNode::leaf_first(n.child[i]);
                EXPECT_LE(BvhNode::leaf_count(n.child[i]),
                          static_cast<uint32_t>(Bvh::kMaxLeafSize));
                for (uint32_t k = first; k < first + BvhNode::leaf_count(n.child[i]); ++k) {
                    const PrimRef p = scene.primitive_at(k);
                    size_t before = 0;  // the primitives of the kinds before p's
                    if (p.kind() != ShapeKind::Sphere) before += scene.spheres().size();
                    if (p.kind() == ShapeKind::Triangle) before += scene.quads().size();
                    ++seen[before + p.index()];
                }
            } else {
                todo.push_back({n.child[i], box});
            }
        }
    }
    EXPECT_EQ(nodes, static_cast<int>(bvh.nodes().size()));  // every node reached exactly once
    for (int s : seen) EXPECT_EQ(s, 1);
}

// Two walls of a room, the floor and the back wall, each of two triangles (whose boxes are the
// wall's): a leaf of all four would have the box of the whole room, which every ray inside
// enters; the SAH gives each wall a leaf of its own, with a flat box, where that costs less. A
// small node of primitives that lie together stays one leaf.
TEST(Bvh, TheWallsOfARoomGetALeafEachAndCompactPrimitivesShareOne) {
    auto leaf_sizes = [](const std::vector<Bounds3>& boxes) {
        const Bvh bvh(boxes);
        std::vector<uint32_t> sizes;
        for (const BvhNode& n : bvh.nodes())
            for (int i = 0; i < kBvhWidth; ++i) {
                const Bounds3 box = n.child_bounds(i);
                if (box.min.x <= box.max.x && BvhNode::is_leaf(n.child[i]))
                    sizes.push_back(BvhNode::leaf_count(n.child[i]));
            }
        std::sort(sizes.begin(), sizes.end());
        return sizes;
    };
    // A room 1 wide, 2 deep and 2 high: the walls' boxes have areas 4 and 4, their union 16, so
    // two leaves cost 1 + (4 C(2) + 4 C(2)) / 16 = 1.75, less than C(4) = 2. (In a cube the two
    // are equal, and the leaf stays.)
    const Bounds3 floor{Vec3(0, 0, 0), Vec3(1, 0, 2)}, back{Vec3(0, 0, 2), Vec3(1, 2, 2)};
    EXPECT_EQ(leaf_sizes({floor, floor, back, back}), (std::vector<uint32_t>{2, 2}));
    // Four small boxes side by side in a row: one leaf.
    std::vector<Bounds3> row;
    for (int i = 0; i < 4; ++i)
        row.push_back({Vec3(0.1f * i, 0, 0), Vec3(0.1f * i + 0.1f, 0.1f, 0.1f)});
    EXPECT_EQ(leaf_sizes(row), (std::vector<uint32_t>{4}));
}

namespace {

// 200,000 boxes: enough for the parallel binning of the top nodes (from 65,536 primitives) and
// for many subtrees handed to other threads (from 4,096). Clustered sizes and places, and a
// tenth of the boxes coinciding, so that ties and median splits occur too. Arithmetic only (no
// library functions), so the boxes are the same bits on every machine.
std::vector<Bounds3> clustered_boxes() {
    Rng rng(12);
    std::vector<Bounds3> boxes;
    for (int i = 0; i < 200000; ++i) {
        if (i % 10 == 9) {
            const Bounds3 copy = boxes[static_cast<size_t>(rng.uniform() * i)];
            boxes.push_back(copy);
            continue;
        }
        const Vec3 c = test::random_in_box(rng, -10.0f, 10.0f) * (i % 3 == 0 ? 0.01f : 1.0f);
        const float hx = rng.uniform(), hy = rng.uniform(), hz = rng.uniform();
        const Vec3 half = Vec3(hx, hy, hz) * 0.05f;  // in this order: a call's arguments have none
        boxes.push_back({c - half, c + half});
    }
    return boxes;
}

// A hash of the nodes' members (a node's padding is never written) and the primitive order.
uint64_t tree_hash(const Bvh& bvh) {
    uint64_t h = kFnvStart;
    for (const BvhNode& n : bvh.nodes()) {
        h = fnv1a(h, n.bounds, sizeof n.bounds);
        h = fnv1a(h, n.child, sizeof n.child);
    }
    const std::vector<uint32_t>& order = bvh.primitive_order();
    return fnv1a(h, order.data(), order.size() * sizeof(uint32_t));
}

}  // namespace

// The build shares its work among threads (subtrees, the binning of large nodes, the cut), and the
// tree must not depend on how: the same nodes, bit for bit, and the same primitive order on 1, 2
// and 5 threads.
TEST(Bvh, TheTreeIsTheSameOnAnyNumberOfThreads) {
    const std::vector<Bounds3> boxes = clustered_boxes();
    const Bvh one(boxes, 1);
    for (int threads : {2, 5}) {
        const Bvh many(boxes, threads);
        ASSERT_EQ(one.nodes().size(), many.nodes().size()) << threads << " threads";
        size_t differing = 0;  // the members' bytes (a node's padding is never written)
        for (size_t i = 0; i < one.nodes().size(); ++i) {
            const BvhNode &a = one.nodes()[i], &b = many.nodes()[i];
            differing += std::memcmp(a.bounds, b.bounds, sizeof a.bounds) != 0 ||
                         std::memcmp(a.child, b.child, sizeof a.child) != 0;
        }
        EXPECT_EQ(differing, 0u) << threads << " threads";
        EXPECT_EQ(one.primitive_order(), many.primitive_order()) << threads << " threads";
    }
}

// The build's speed work (docs/performance.md, design item 15) is meant to leave the tree as it
// was, bit for bit: this pins it. The hash is that of the tree built by 49cc826 and by every
// commit since that changed only how fast the same tree is built; the same with GCC and Clang,
// at -O0 and -O2, with and without -march=native and the sanitizers. A change that means to
// change the tree updates the hash, and says why, with the speed and quality it measured.
TEST(Bvh, TheTreeOfAFixedSetOfBoxesIsPinned) {
    const Bvh bvh(clustered_boxes(), 2);
    EXPECT_EQ(bvh.nodes().size(), 36312u);
    EXPECT_EQ(tree_hash(bvh), 0x89518da097a19aabull);
}

// The build steps' split into parts (accel/parallel.h): every index in exactly one part, the
// parts in order, and an exception on another thread comes back to the caller once all parts
// are done.
TEST(ParallelParts, EveryIndexOnceAndAnExceptionReachesTheCaller) {
    std::vector<int> seen(1000, 0), part_of(1000, -1);
    parallel_parts(1000, 4, 1, [&](size_t begin, size_t end, int part) {
        for (size_t i = begin; i < end; ++i) {
            ++seen[i];
            part_of[i] = part;
        }
    });
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), 1000);
    EXPECT_TRUE(std::is_sorted(part_of.begin(), part_of.end()));
    EXPECT_EQ(part_of.back(), 3);
    std::vector<int> done(4, 0);
    EXPECT_THROW(parallel_parts(1000, 4, 1,
                                [&](size_t, size_t, int part) {
                                    done[static_cast<size_t>(part)] = 1;
                                    if (part == 2) throw std::runtime_error("part 2");
                                }),
                 std::runtime_error);
    EXPECT_EQ(done, (std::vector<int>{1, 1, 1, 1}));  // the other parts still ran
}

TEST(Bvh, ManyIdenticalPrimitivesBuildAndTraverse) {
    // All centroids equal: no SAH split exists; the build must still terminate and work.
    Scene scene;
    const uint32_t m = test::add_diffuse(scene, Color(0.5f));
    for (int i = 0; i < 1000; ++i) scene.add_sphere({Vec3(0), 1.0f}, m);
    scene.commit();
    const std::optional<Hit> hit = scene.intersect(Ray{Vec3(0, 0, -5), Vec3(0, 0, 1)});
    ASSERT_TRUE(hit);
    EXPECT_FLOAT_EQ(hit->shape.t, 4.0f);
}

TEST(Bvh, EmptySceneMissesEverything) {
    Scene scene;
    scene.commit();
    EXPECT_FALSE(scene.intersect(Ray{Vec3(0), Vec3(0, 0, 1)}));
    EXPECT_FALSE(scene.occluded(Ray{Vec3(0), Vec3(0, 0, 1)}));
}

TEST(Bvh, AxisAlignedRaysInsideSlabPlanesAreNotCulled) {
    // A ray lying exactly in the plane of a box face (direction component 0, origin on the
    // face): 0 * inf = NaN in the slab test must not cull the box (docs/accuracy.md hard case 2).
    Scene scene;
    const uint32_t m = test::add_diffuse(scene, Color(0.5f));
    // A flat triangle in the plane y = 0: its box has zero height.
    scene.add_mesh({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)}, {}, {}, {{{0, 1, 2}, m, false}});
    scene.add_sphere({Vec3(5, 5, 5), 0.1f}, m);  // a second primitive, so there is a tree
    scene.commit();
    EXPECT_TRUE(scene.intersect(Ray{Vec3(0.2f, 1.0f, 0.2f), Vec3(0, -1, 0)}));
    EXPECT_TRUE(scene.intersect(Ray{Vec3(0.2f, -1.0f, 0.2f), Vec3(0, 1, 0)}));
}

// The BVH's node array and the leaf blocks live in LargePageVector: from 2 MiB up, on a 2 MiB
// boundary (where the system can back them with 2 MiB pages), and below, aligned as the type
// asks. Growing across the threshold keeps the contents.
TEST(LargePages, ArraysFrom2MiBStartOn2MiBBoundariesAndKeepTheirContents) {
    LargePageVector<BvhNode> nodes;
    const size_t per_page = kLargePageBytes / sizeof(BvhNode);
    for (size_t i = 0; i < 3 * per_page + 5; ++i) {
        BvhNode n{};
        n.child[0] = static_cast<uint32_t>(i);
        nodes.push_back(n);
        const auto address = reinterpret_cast<uintptr_t>(nodes.data());
        ASSERT_EQ(address % alignof(BvhNode), 0u) << "at size " << nodes.size();
        if (nodes.capacity() * sizeof(BvhNode) >= kLargePageBytes) {
            ASSERT_EQ(address % kLargePageBytes, 0u) << "at size " << nodes.size();
        }
    }
    for (size_t i = 0; i < nodes.size(); ++i) ASSERT_EQ(nodes[i].child[0], i);
}
