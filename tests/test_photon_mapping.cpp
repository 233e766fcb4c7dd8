// Lesson 6's groundwork: the photon grid against a brute-force scan, the kernels' integrals,
// the photons' determinism, and the kernel's bias in closed form (docs/accuracy.md, "Density
// estimation").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <vector>

#include "06_photon_mapping/density.h"
#include "06_photon_mapping/kernel.h"
#include "06_photon_mapping/photon_map.h"
#include "06_photon_mapping/photons.h"
#include "06_photon_mapping/radius.h"
#include "io/scene_file.h"
#include "lights/lights.h"
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

namespace {

// A point light of intensity I (W/sr) at height h above the middle of a diffuse floor of albedo
// rho, 200 m square: the floor's irradiance is E(x) = I h / (h^2 + x^2)^(3/2) at distance x from
// the foot of the light. The camera looks straight down (it only gives the scene a camera).
Scene point_light_over_a_floor(double I, double h, double rho, bool light_below = false) {
    const auto grey = [](double v) {
        const std::string c = std::to_string(v);
        return "[" + c + ", " + c + ", " + c + "]";
    };
    const std::string height = std::to_string(light_below ? -h : h);
    return build_scene(parse_scene_string(R"([image]
width = 16
height = 16
[camera]
position = [0, 3, 0]
look_at = [0, 0, 0]
up = [0, 0, 1]
fov = 40
[materials.floor]
type = "diffuse"
albedo = )" + grey(rho) + R"(
[[shapes]]
type = "quad"
material = "floor"
corner = [-100, 0, -100]
edge_u = [0, 0, 200]
edge_v = [200, 0, 0]
[[lights]]
type = "point"
position = [0, )" + height + R"(, 0]
intensity = )" + grey(I) + "\n",
                                          "point_light_over_a_floor.toml"));
}

// The floor's hit below (x, 2, z), seen from straight above.
SurfaceInteraction floor_point(const Scene& scene, double x, double z) {
    const Ray ray{Vec3(static_cast<float>(x), 2.0f, static_cast<float>(z)), Vec3(0, -1, 0)};
    const std::optional<Hit> hit = scene.intersect(ray);
    EXPECT_TRUE(hit.has_value());
    return scene.interaction(ray, *hit);
}

}  // namespace

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
    size_t vertices = 0;
    for (size_t j = 0; j < 3000; ++j) {
        const std::span<const Vertex> a = one.subpath(j), c = three.subpath(j);
        ASSERT_EQ(a.size(), c.size()) << "subpath " << j;
        for (size_t k = 0; k < a.size(); ++k) {
            EXPECT_EQ(a[k].p, c[k].p);
            EXPECT_EQ(a[k].beta, c[k].beta);
            EXPECT_EQ(a[k].pdf_fwd, c[k].pdf_fwd);
        }
        vertices += a.size();
    }
    EXPECT_TRUE(one.subpath(3000).empty());
    for (const Photon& photon : one.photons) {
        const Vertex& v = one.vertex_of(photon);
        EXPECT_GE(photon.vertex, 1u);
        EXPECT_EQ(v.p, photon.p);
        EXPECT_EQ(v.beta, photon.beta);
        EXPECT_FALSE(v.bsdf->is_delta());
    }
    EXPECT_GE(one.bytes(), vertices * sizeof(Vertex) + one.photons.size() * sizeof(Photon));
    // Another iteration draws other numbers.
    const LightPaths next = trace_photons(b, 7, 6, 3000, 8, 3, 1);
    EXPECT_NE(next.photons.front().p, one.photons.front().p);
}

TEST(Photons, FromAPointLightCarryItsPowerAndOnlyLightFromTheirSideCounts) {
    // One point light: every photon at y_1 carries beta = 4 pi I (the light is always chosen).
    // The same floor lit from below: photons land on its underside, under the very points seen
    // from above, and none of them counts there (density.h: the normal on the lit side).
    const double I = 2.0;
    for (const bool below : {false, true}) {
        const Scene scene = point_light_over_a_floor(I, 1.0, 0.5, below);
        const LightSampler lights(scene);
        const Bidir b{scene, lights, scene.camera, scene.width, scene.height};
        const LightPaths paths = trace_photons(b, 11, 0, 20000, 2, -1);
        ASSERT_GT(paths.photons.size(), 9000u);
        for (const Photon& p : paths.photons)
            ASSERT_NEAR(p.beta.x, 4.0 * kPi * I, 1e-5 * 4.0 * kPi * I);
        const PhotonGrid grid(paths.photons, 0.3f);
        const SurfaceInteraction si = floor_point(scene, 0.0, 0.0);
        const Bsdf bsdf(scene.material(si.material), si);
        const RadianceEstimate e =
            reflected_radiance(grid, si, bsdf, si.wo, Kernel::Constant, paths.count);
        int near = 0;
        grid.for_each_within(si.p, [&](const Photon&) { ++near; });
        EXPECT_GT(near, 100);
        if (below) {
            EXPECT_EQ(e.photons, 0u);
            EXPECT_EQ(e.L.x, 0.0f);
        } else {
            EXPECT_EQ(e.photons, static_cast<uint32_t>(near));
            EXPECT_GT(e.L.x, 0.0f);
        }
    }
}

TEST(PhotonRadius, IsTwoPixelFootprintsAtTheMedianDistanceWithinTheScenesLimits) {
    // The camera 3 m above the floor, looking straight down with a 40 degree field: the grid's
    // rays meet the floor at distances from 3 to 3 / cos(theta) at the image's corners, so the
    // radius lies between 2 a 3 and 2 a 3 / cos(theta_corner), a the pixel's side at distance 1.
    const Scene scene = point_light_over_a_floor(1.0, 1.0, 0.5);
    const float a = pixel_side_at_unit_distance(scene.camera, 16, 16);
    EXPECT_NEAR(a, 2.0 * std::tan(20.0 * kPi / 180.0) / 16.0, 1e-6);
    const double cos_corner =
        1.0 / std::sqrt(1.0 + 2.0 * std::pow(std::tan(20.0 * kPi / 180.0), 2));
    const float r = default_photon_radius(scene);
    EXPECT_GE(r, 2.0f * a * 3.0f * 0.9999f);
    EXPECT_LE(r, 2.0f * a * 3.0f / cos_corner);
    // The limits: at most 5% of the scene box's diagonal, at least 1e-4 of it.
    const float diagonal = glm::length(scene.bounds().extent());
    EXPECT_FLOAT_EQ(default_photon_radius(scene, 1000.0f), 0.05f * diagonal);
    EXPECT_FLOAT_EQ(default_photon_radius(scene, 1e-6f), 1e-4f * diagonal);
}

namespace {

// The irradiance of the point light over the floor, E(x) = I h / (h^2 + x^2)^(3/2).
double floor_irradiance(double I, double h, double x) {
    return I * h / std::pow(h * h + x * x, 1.5);
}

// E convolved with the kernel over the disk of radius r about the floor point (x, 0): the
// expectation of the photon estimate of irradiance at fixed r. In polar coordinates (s, phi)
// about the point, int_0^r K(s) int_0^2pi E(|(x + s cos phi, s sin phi)|) d(phi) s ds, both by
// adaptive Simpson.
double convolved_irradiance(Kernel kernel, double r, double I, double h, double x) {
    return test::adaptive_simpson(
        [&](double s) {
            const double ring = test::adaptive_simpson(
                [&](double phi) {
                    const double u = x + s * std::cos(phi), v = s * std::sin(phi);
                    return floor_irradiance(I, h, std::sqrt(u * u + v * v));
                },
                0.0, 2.0 * kPi, 1e-12, 12);
            return kernel_weight(kernel, static_cast<float>(s * s), static_cast<float>(r)) * ring *
                   s;
        },
        0.0, r, 1e-12, 12);
}

}  // namespace

TEST(PhotonDensity, AFixedRadiusEstimatesTheIrradianceConvolvedWithTheKernel) {
    // A point light (I = 1 W/sr) 1 m above a diffuse floor (rho = 0.5). At a fixed radius
    // r = 0.4 m the photon estimate of the reflected radiance, rho / pi times irradiance, has
    // expectation rho / pi times E convolved with the kernel over the disk (kernel.h), which near
    // the light's foot, where E curves most (its Laplacian is -6 I / h^4 at x = 0), is several
    // percent below E itself: to leading order by r^2/8 (constant) or r^2/12 (Epanechnikov)
    // times the Laplacian. 64 independent iterations of 50000 photons (only direct light:
    // max_vertices 2), each estimating at x = 0 and at x = 0.8 m (where the Laplacian nearly
    // vanishes, and the convolution hardly changes E); the mean of the iterations against the
    // convolved value, z-tests with the standard error from the iterations' spread (4 tests, 0.01
    // with Sidak correction); and at x = 0 the mean against E(0) unconvolved must be rejected
    // by many standard errors.
    const double I = 1.0, h = 1.0, rho = 0.5;
    const float r = 0.4f;
    const int iterations = 64, photons_per_iteration = 50000;
    const Scene scene = point_light_over_a_floor(I, h, rho);
    const LightSampler lights(scene);
    const Bidir b{scene, lights, scene.camera, scene.width, scene.height};
    const double xs[] = {0.0, 0.8};
    const Kernel kernels[] = {Kernel::Constant, Kernel::Epanechnikov};
    double sum[2][2] = {}, sum2[2][2] = {};
    for (int k = 0; k < iterations; ++k) {
        const LightPaths paths = trace_photons(b, 2024, k, photons_per_iteration, 2, -1);
        const PhotonGrid grid(paths.photons, r);
        for (int i = 0; i < 2; ++i) {
            const SurfaceInteraction si = floor_point(scene, xs[i], 0.0);
            const Bsdf bsdf(scene.material(si.material), si);
            for (int j = 0; j < 2; ++j) {
                const double L =
                    reflected_radiance(grid, si, bsdf, si.wo, kernels[j], paths.count).L.x;
                sum[i][j] += L;
                sum2[i][j] += L * L;
            }
        }
    }
    const double z_max = test::z_quantile(test::sidak(0.01, 4));
    for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 2; ++j) {
            const double mean = sum[i][j] / iterations;
            const double variance = (sum2[i][j] - iterations * mean * mean) / (iterations - 1);
            const double standard_error = std::sqrt(std::max(variance, 1e-14) / iterations);
            const double expected = rho / kPi * floor_irradiance(I, h, xs[i]);
            const double convolved = rho / kPi * convolved_irradiance(kernels[j], r, I, h, xs[i]);
            const double z_convolved = std::fabs(mean - convolved) / standard_error;
            const double z_unconvolved = std::fabs(mean - expected) / standard_error;
            std::printf(
                "x = %.1f, %-12s: rho/pi E %.6f, convolved %.6f, measured %.6f "
                "(standard error %.6f): z %.2f against the convolved value, %.1f against "
                "E\n",
                xs[i], kernel_name(kernels[j]), expected, convolved, mean, standard_error,
                z_convolved, z_unconvolved);
            EXPECT_LT(z_convolved, z_max) << "x = " << xs[i] << ", " << kernel_name(kernels[j])
                                          << ": " << mean << " against the convolved " << convolved
                                          << " (standard error " << standard_error << ")";
            if (i == 0) {
                EXPECT_GT(z_unconvolved, 10.0)
                    << kernel_name(kernels[j]) << ": the kernel's bias at the light's foot should "
                    << "be many standard errors (" << mean << " against E's " << expected << ")";
            }
        }
    }
}

TEST(PhotonDensity, APhotonIsWeightedByTheCosineAtItsOwnSurface) {
    // A smooth-shaded mesh (density.h): x lies on a facet whose geometric normal n_g leans 30
    // degrees from its shading normal n_s = +y, and a photon from the neighbouring facet, whose
    // normal n_p is +y, arrives at x nearly tangent to x's facet (wi . n_g = 0.03, wi . n_p =
    // 0.53). The photon's density holds |wi . n_p|, so its term is K f beta |wi . n_s| /
    // |wi . n_p|, here K f beta exactly; dividing by x's |wi . n_g| instead would make it 17
    // times that.
    const Scene scene = point_light_over_a_floor(1.0, 1.0, 0.5);
    SurfaceInteraction si = floor_point(scene, 0.0, 0.0);
    si.n_shading = Vec3(0, 1, 0);
    si.n_geo = glm::normalize(Vec3(0.5f, 0.8660254f, 0));
    si.wo = Vec3(0, 1, 0);
    const Bsdf bsdf(scene.material(si.material), si);
    Photon p;
    p.p = si.p + Vec3(0.01f, 0, 0);
    p.wi = glm::normalize(Vec3(-0.85f, 0.5268f, 0));
    p.n = Vec3(0, 1, 0);
    p.beta = Color(2.0f);
    p.vertex = 1;
    const float r = 0.1f;
    ASSERT_LT(glm::dot(p.wi, si.n_geo), 0.05f);
    const std::optional<Color> term = photon_term(p, si, bsdf, si.wo, Kernel::Constant, r);
    ASSERT_TRUE(term.has_value());
    const Vec3 d = p.p - si.p;
    const Color f = bsdf.eval(si.wo, p.wi);
    ASSERT_GT(f.x, 0.0f);
    const float expected = kernel_weight(Kernel::Constant, glm::dot(d, d), r) * f.x * p.beta.x *
                           std::fabs(glm::dot(p.wi, si.n_shading)) / std::fabs(glm::dot(p.wi, p.n));
    EXPECT_NEAR(term->x, expected, 1e-5f * expected);
}
