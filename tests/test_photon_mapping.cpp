// Lesson 6's groundwork: the photon grid against a brute-force scan, the kernels' integrals,
// the photons' determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "io/scene_file.h"
#include "kernel.h"
#include "lights/lights.h"
#include "photon_map.h"
#include "photons.h"
#include "statistics.h"
#include "test_util.h"

using namespace lessons;

namespace {

// The indices (Photon::path) of the photons within r of x, in the order the grid visits them.
std::vector<uint32_t> grid_query(const PhotonGrid& grid, const Vec3& x) {
    std::vector<uint32_t> found;
    grid.for_each_within(x, [&](const Photon& p) { found.push_back(p.path); });
    return found;
}

// The same by looking at every photon, with the distance test the grid documents.
std::vector<uint32_t> brute_force(const std::vector<Photon>& photons, const Vec3& x, float r) {
    std::vector<uint32_t> found;
    for (const Photon& p : photons) {
        const Vec3 d = p.p - x;
        if (glm::dot(d, d) < r * r) found.push_back(p.path);
    }
    return found;
}

// Photons numbered by Photon::path: random ones in a box straddling the origin, a plane of them
// (photons lie on surfaces), and a lattice of spacing r about negative coordinates (so that many
// lie exactly r, 2r, ... from each other and from the queries).
std::vector<Photon> test_photons(Rng& rng, size_t random_count, float r) {
    std::vector<Photon> photons;
    auto add = [&](const Vec3& p) {
        Photon photon;
        photon.p = p;
        photon.path = static_cast<uint32_t>(photons.size());
        photons.push_back(photon);
    };
    for (size_t k = 0; k < random_count; ++k) add(test::random_in_box(rng, -3.0f, 5.0f));
    for (size_t k = 0; k < random_count / 4; ++k) {
        const Vec3 q = test::random_in_box(rng, -2.0f, 2.0f);
        add(Vec3(q.x, -1.25f, q.z));
    }
    for (int i = -4; i <= 1; ++i)
        for (int j = -4; j <= 1; ++j)
            for (int k = -3; k <= 0; ++k) add(Vec3(i * r - 2.0f, j * r - 1.0f, k * r));
    return photons;
}

}  // namespace

TEST(PhotonGrid, FindsExactlyThePhotonsABruteForceScanFinds) {
    // For several radii and bucket counts (the default, and few enough that many cells share a
    // bucket, and two of a query's eight cells often do), at random points, at the photons
    // themselves, at r from them along an axis, and at the floats nearest the cells' boundaries
    // (the grid's cells are 2r (1 + 2^-10) wide from the photons' lowest corner: photon_map.h),
    // and their neighbours: the same photons, each once.
    Rng rng(61);
    for (const float r : {0.05f, 0.3f, 1.0f, 2.7f}) {
        const std::vector<Photon> photons = test_photons(rng, 12000, r);
        Bounds3 box;
        for (const Photon& p : photons) box.expand(p.p);
        std::vector<Vec3> queries;
        for (int k = 0; k < 600; ++k) queries.push_back(test::random_in_box(rng, -4.0f, 6.0f));
        for (int k = 0; k < 300; ++k) {
            const Vec3 p = photons[rng.next_u32() % photons.size()].p;
            queries.push_back(p);
            queries.push_back(p + Vec3(r, 0, 0));
            queries.push_back(p - Vec3(0, 0, r));
        }
        const double cell = 2.0 * r * (1.0 + 0x1p-10);
        for (int k = -2; k < 12; ++k) {
            const Vec3 corner(static_cast<float>(box.min.x + k * cell),
                              static_cast<float>(box.min.y + k * cell),
                              static_cast<float>(box.min.z + (k / 2) * cell));
            for (const float step : {-1.0f, 0.0f, 1.0f}) {
                Vec3 q = corner;
                if (step != 0.0f)
                    for (int a = 0; a < 3; ++a) q[a] = std::nextafter(q[a], step * kInfinity);
                queries.push_back(q);
                queries.push_back(Vec3(q.x, photons[k + 20].p.y, photons[k + 40].p.z));
            }
        }
        const PhotonGrid grids[] = {PhotonGrid(photons, r), PhotonGrid(photons, r, 0, 8),
                                    PhotonGrid(photons, r, 0, 1)};
        for (const Vec3& x : queries) {
            std::vector<uint32_t> expected = brute_force(photons, x, r);
            std::sort(expected.begin(), expected.end());
            for (const PhotonGrid& grid : grids) {
                std::vector<uint32_t> found = grid_query(grid, x);
                std::sort(found.begin(), found.end());  // duplicates would stay
                ASSERT_EQ(found, expected) << "r " << r << " at " << x.x << ", " << x.y << ", "
                                           << x.z << " (" << grid.size() << " photons)";
            }
        }
    }
}

TEST(PhotonGrid, IsTheSameForAnyNumberOfThreadsAndSaysItsMemory) {
    // Enough photons that the buckets are computed on several threads (parts of 65536).
    Rng rng(62);
    const std::vector<Photon> photons = test_photons(rng, 200000, 0.1f);
    const PhotonGrid one(photons, 0.1f, 1), many(photons, 0.1f, 4);
    ASSERT_EQ(one.size(), photons.size());
    ASSERT_EQ(many.size(), photons.size());
    EXPECT_EQ(
        std::memcmp(one.photons().data(), many.photons().data(), photons.size() * sizeof(Photon)),
        0);
    for (int k = 0; k < 200; ++k) {
        const Vec3 x = test::random_in_box(rng, -3.0f, 5.0f);
        EXPECT_EQ(grid_query(one, x), grid_query(many, x));  // in the same order too
    }
    // The photons and one offset per bucket (the smallest power of two >= the count, plus 1).
    EXPECT_GE(one.bytes(), photons.size() * sizeof(Photon) + 262145 * sizeof(uint32_t));
    EXPECT_LT(one.bytes(), 2 * (photons.size() * sizeof(Photon) + 262145 * sizeof(uint32_t)));
    EXPECT_THROW(PhotonGrid(photons, 0.0f), std::invalid_argument);
}

TEST(Kernel, EachIntegratesToOneOverTheDisk) {
    // Over the disk of radius r, two ways: a radial integral 2 pi int_0^r K(s) s ds by adaptive
    // Simpson, and the midpoint rule on a 1000 x 1000 grid over the enclosing square (which
    // knows nothing of the kernel's symmetry; its error is the disk's ragged rim, about 1e-4).
    for (const Kernel kernel : {Kernel::Constant, Kernel::Epanechnikov}) {
        for (const float r : {0.01f, 1.0f, 37.0f}) {
            const double radial = test::adaptive_simpson(
                [&](double s) {
                    return 2.0 * kPi * s * kernel_weight(kernel, static_cast<float>(s * s), r);
                },
                0.0, r, 1e-9, 20);
            EXPECT_NEAR(radial, 1.0, 1e-5) << kernel_name(kernel) << ", r " << r;
            const int n = 1000;
            const double h = 2.0 * r / n;
            double grid = 0.0;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    const double x = -r + (i + 0.5) * h, y = -r + (j + 0.5) * h;
                    grid += kernel_weight(kernel, static_cast<float>(x * x + y * y), r) * h * h;
                }
            EXPECT_NEAR(grid, 1.0, 2e-3) << kernel_name(kernel) << ", r " << r;
        }
        EXPECT_EQ(kernel_weight(kernel, 1.0f, 1.0f), 0.0f);  // 0 on the rim and outside
        EXPECT_EQ(kernel_weight(kernel, 4.0f, 1.0f), 0.0f);
    }
}

TEST(Photons, AreTheSameForAnyNumberOfThreadsAndNameTheirVertices) {
    // The Cornell box (an area light, diffuse walls, several bounces): 3000 subpaths of
    // iteration 5 on 1 and 3 threads give the same photons, subpaths and vertices; each photon's
    // vertex is where it lies, never y_0 and never a delta vertex.
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {16, 16});
    const LightSampler lights(scene);
    const Bidir b{scene, lights, scene.camera, scene.width, scene.height};
    const LightPaths one = trace_photons(b, 7, 5, 3000, 8, 3, 1);
    const LightPaths three = trace_photons(b, 7, 5, 3000, 8, 3, 3);
    ASSERT_EQ(one.count, 3000);
    ASSERT_EQ(one.photons.size(), three.photons.size());
    ASSERT_GT(one.photons.size(), 3000u);  // several bounces each, on average
    EXPECT_EQ(
        std::memcmp(one.photons.data(), three.photons.data(), one.photons.size() * sizeof(Photon)),
        0);
    EXPECT_EQ(one.start, three.start);
    ASSERT_EQ(one.vertices.size(), three.vertices.size());
    for (size_t k = 0; k < one.vertices.size(); ++k) {
        EXPECT_EQ(one.vertices[k].p, three.vertices[k].p);
        EXPECT_EQ(one.vertices[k].beta, three.vertices[k].beta);
        EXPECT_EQ(one.vertices[k].pdf_fwd, three.vertices[k].pdf_fwd);
    }
    for (const Photon& photon : one.photons) {
        const Vertex& v = one.vertex_of(photon);
        EXPECT_GE(photon.vertex, 1u);
        EXPECT_EQ(v.p, photon.p);
        EXPECT_EQ(v.beta, photon.beta);
        EXPECT_FALSE(v.bsdf->is_delta());
    }
    EXPECT_GE(one.bytes(),
              one.vertices.size() * sizeof(Vertex) + one.photons.size() * sizeof(Photon));
    // Another iteration draws other numbers.
    const LightPaths next = trace_photons(b, 7, 6, 3000, 8, 3, 1);
    EXPECT_NE(next.photons.front().p, one.photons.front().p);
}
