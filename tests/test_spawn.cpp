// Rays spawned from a hit must not re-hit the surface they leave, at every scale
// (docs/accuracy.md hard case 3, in the spirit of pbrt-v4's Triangle.Reintersect test).
#include <gtest/gtest.h>

#include "geometry/spawn.h"
#include "materials/optics.h"
#include "scene/scene.h"
#include "test_util.h"

using namespace lessons;

class SpawnAtScale : public ::testing::TestWithParam<float> {};

TEST_P(SpawnAtScale, NoSelfIntersectionOnTrianglesSpheresAndQuads) {
    const float scale = GetParam();
    Rng rng(static_cast<uint64_t>(std::log10(scale) + 100));
    int spawned = 0, self_hits = 0;
    for (int trial = 0; trial < 300; ++trial) {
        Scene scene;
        const uint32_t m = test::add_diffuse(scene, Color(0.5f));
        const Vec3 center = scale * test::random_in_box(rng, -1, 1);
        const float size = scale * (0.01f + rng.uniform());
        std::vector<Vec3> p;
        for (int k = 0; k < 3; ++k) p.push_back(center + size * test::random_unit_vector(rng));
        scene.add_mesh(p, {}, {}, {{{0, 1, 2}, m, false}});
        scene.add_sphere({center + Vec3(3 * size, 0, 0), size}, m);
        scene.add_quad(Quad(center - Vec3(3 * size, 0, 0), size * test::random_unit_vector(rng),
                            size * test::random_unit_vector(rng)),
                       m);
        scene.commit();
        for (int k = 0; k < 50; ++k) {
            // A ray from far away towards a random point of the scene's box.
            const Bounds3 b = scene.bounds();
            const Vec3 target =
                b.min + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * b.extent();
            const Vec3 origin = target + 4.0f * size * test::random_unit_vector(rng);
            const Ray ray{origin, glm::normalize(target - origin)};
            const std::optional<Hit> hit = scene.intersect(ray);
            if (!hit) continue;
            const SurfaceInteraction si = scene.interaction(ray, *hit);
            // Leave the surface in random directions on the side the ray came from (reflection)
            // and on the other side (transmission).
            for (int j = 0; j < 20; ++j) {
                Vec3 dir = test::random_unit_vector(rng);
                const Ray out = spawn_ray(si.surface_point(), dir);
                ++spawned;
                const std::optional<Hit> again = scene.intersect(out);
                if (!again || !(again->prim == hit->prim)) continue;
                // A flat shape cannot be re-hit at all by a ray leaving it. A sphere is re-hit
                // only by an inward ray, at the far end of the chord of length -2 r cos.
                const float cos_out = glm::dot(glm::normalize(dir), si.n_geo);
                if (hit->prim.kind() != ShapeKind::Sphere || cos_out >= 0.0f) {
                    ++self_hits;
                } else {
                    const float chord = -2.0f * size * cos_out;
                    if (again->shape.t < 0.5f * chord) ++self_hits;
                }
            }
        }
    }
    EXPECT_GT(spawned, 50000);
    EXPECT_EQ(self_hits, 0) << self_hits << " of " << spawned
                            << " spawned rays re-hit their surface";
}

INSTANTIATE_TEST_SUITE_P(Scales, SpawnAtScale,
                         ::testing::Values(1e-8f, 1e-4f, 1e-2f, 1.0f, 1e2f, 1e4f, 1e8f));

TEST(Spawn, ShadowRayBetweenTwoSurfacesHitsNeitherEnd) {
    Scene scene;
    const uint32_t m = test::add_diffuse(scene, Color(0.5f));
    scene.add_quad(Quad(Vec3(-1, 0, -1), Vec3(0, 0, 2), Vec3(2, 0, 0)), m);  // floor, up
    scene.add_quad(Quad(Vec3(-1, 3, -1), Vec3(2, 0, 0), Vec3(0, 0, 2)), m);  // ceiling, down
    scene.commit();
    Rng rng(5);
    for (int i = 0; i < 10000; ++i) {
        const Vec3 p(-1 + 2 * rng.uniform(), 0.0f, -1 + 2 * rng.uniform());
        const Vec3 q(-1 + 2 * rng.uniform(), 3.0f, -1 + 2 * rng.uniform());
        const Vec3 error = gamma_bound(4) * Vec3(2.0f, 3.0f, 2.0f);
        ASSERT_FALSE(scene.occluded(
            spawn_ray_between({p, error, Vec3(0, 1, 0)}, {q, error, Vec3(0, -1, 0)})));
    }
}

TEST(Spawn, OffsetIsFiniteAndMovesToTheRequestedSide) {
    for (float x : {0.0f, 1e-30f, -1e-8f, 1e-3f, 1.0f, -3e4f, 1e8f, -1e30f}) {
        const Vec3 p(x, -x, 0.5f * x);
        for (const Vec3& n : {Vec3(0, 0, 1), Vec3(0, 0, -1), glm::normalize(Vec3(1, -1, 1))}) {
            const SurfacePoint s{p, gamma_bound(4) * glm::abs(p), n};
            const Vec3 o = offset_ray_origin(s, n);
            ASSERT_TRUE(is_finite(o));
            EXPECT_GT(glm::dot(o - p, n), 0.0f) << "x = " << x;
            EXPECT_LT(glm::dot(offset_ray_origin(s, -n) - p, n), 0.0f) << "x = " << x;
        }
    }
}

class ThinSlabAtScale : public ::testing::TestWithParam<float> {};

TEST_P(ThinSlabAtScale, RefractedRaysNeverTunnelAndReflectedRaysNeverReturn) {
    // Two parallel quads of size s, 1e-4 s apart: a thin sheet of glass. A ray entering the top
    // face must reach the bottom face, and the reflected ray must escape.
    const float s = GetParam();
    const float gap = 1e-4f * s;
    Scene scene;
    const uint32_t m = test::add_diffuse(scene, Color(0.5f));
    scene.add_quad(Quad(Vec3(-s, 0, -s), Vec3(0, 0, 2 * s), Vec3(2 * s, 0, 0)), m);     // top, +y
    scene.add_quad(Quad(Vec3(-s, -gap, -s), Vec3(2 * s, 0, 0), Vec3(0, 0, 2 * s)), m);  // bottom
    scene.commit();
    Rng rng(static_cast<uint64_t>(std::log10(s) + 50));
    int tunnelled = 0, returned = 0, rays = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec3 d = test::random_unit_vector(rng);
        d.y = -std::fabs(d.y);
        if (d.y > -0.02f) continue;  // keep some grazing rays, but hit inside the quads
        const Vec3 target(0.5f * s * (2 * rng.uniform() - 1), 0.0f,
                          0.5f * s * (2 * rng.uniform() - 1));
        const Ray ray{target - 0.1f * s * d, d};
        const std::optional<Hit> hit = scene.intersect(ray);
        ASSERT_TRUE(hit);
        const SurfaceInteraction si = scene.interaction(ray, *hit);
        ++rays;
        const Vec3 n(0, 1, 0);
        const Vec3 refracted = *refract(si.wo, n, 1.5f);
        const std::optional<Hit> below = scene.intersect(spawn_ray(si.surface_point(), refracted));
        if (!below || below->prim == hit->prim) ++tunnelled;
        if (scene.intersect(spawn_ray(si.surface_point(), reflect(si.wo, n)))) ++returned;
    }
    EXPECT_GT(rays, 10000);
    EXPECT_EQ(tunnelled, 0) << "of " << rays;
    EXPECT_EQ(returned, 0) << "of " << rays;
}

INSTANTIATE_TEST_SUITE_P(Scales, ThinSlabAtScale,
                         ::testing::Values(1e-4f, 1e-2f, 1.0f, 1e2f, 1e4f));
