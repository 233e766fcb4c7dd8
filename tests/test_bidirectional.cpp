// Lesson 5 against closed forms, against lesson 4, and against itself.
#include <gtest/gtest.h>

#include "bidirectional.h"
#include "io/scene_file.h"
#include "render_statistics.h"
#include "rendering_equation.h"
#include "test_util.h"

using namespace lessons;
using test::channels_that_agree;
using test::image_mean;

namespace {

// z-tests in this file: point-light caustic 2, furnace 3 + 3, strategies 9, light tracing 1,
// pixel-by-pixel image means 6, a lamp seen directly 6 (its outline's pixels: a family of their
// own).
const double kSignificance = test::sidak(0.01, 30);

RenderResult render_lesson5(const Scene& scene, const BidirOptions& options, int spp, uint64_t seed,
                            int threads = 0) {
    const LightSampler lights(scene);
    RenderSettings settings;
    settings.progress = false;
    settings.seed = seed;
    settings.threads = threads;
    return render_scene(scene, make_bidirectional_model(scene, lights, options), spp, settings);
}

RenderResult render_lesson4(const Scene& scene, const PathOptions& options, int spp,
                            uint64_t seed) {
    const LightSampler lights(scene);
    RenderSettings settings;
    settings.progress = false;
    settings.seed = seed;
    return render_scene(scene, make_path_tracing_model(scene, lights, options), spp, settings);
}


// |a - b| against the standard error of the difference (floored: an estimate with no variance,
// such as a furnace seen one segment deep, must then match to rounding).
double z_score(double a, double var_a, double b, double var_b = 0.0) {
    return std::fabs(a - b) / std::sqrt(std::max(var_a + var_b, 1e-14));
}

}  // namespace

TEST(Bidirectional, FurnaceIsLeOverOneMinusRhoWithAndWithoutADepthLimit) {
    // Every strategy meets here: every vertex is on the emitter, light subpaths start all over
    // the sphere, and the camera sees the inside directly (paths of one segment go to the camera
    // alone there: every pixel lies inside the emitter's image, mis.h). L = L_e / (1 - rho); with
    // at most k segments, L_e (1 - rho^k) / (1 - rho).
    for (float rho : {0.5f, 0.8f}) {
        for (int k : {0, 1, 3}) {
            if (rho == 0.5f && k == 3) continue;
            const Scene scene = test::furnace(rho, 1.0f);
            BidirOptions options;
            options.max_depth = k;
            const RenderResult r = render_lesson5(scene, options, 256, 1 + k);
            const auto [mean, var] = image_mean(r.image, r.variance);
            const double expected =
                k == 0 ? 1.0 / (1.0 - rho) : (1.0 - std::pow(rho, k)) / (1.0 - rho);
            EXPECT_LT(z_score(mean, var, expected), test::z_quantile(kSignificance))
                << "rho " << rho << ", depth " << k << ": " << mean << " against " << expected
                << " (standard error " << std::sqrt(var) << ")";
            EXPECT_EQ(r.nan_samples + r.inf_samples, 0u);
        }
    }
}

TEST(Bidirectional, PointLightSeenInAMirrorLightsTheFloorAsItsImageSourceDoes) {
    // A point light (I = 1 W/sr) 1 m above a small diffuse receiver (albedo 0.5) and 1 m below a
    // large horizontal mirror (R = 0.8): the receiver gets the light's I cos / d^2 and its mirror
    // image's R I cos' / d'^2 (the image 3 m above it), and it sees its own image at 4 m, which
    // adds R L A / 16 to a first approximation (0.03% here). The camera looks down at the
    // receiver's middle; every pixel is compared with the closed form at its pixel centre.
    // Lesson 5 finds both terms (the mirror path through light subpaths); lesson 4 cannot find
    // light that meets a point light after a mirror, and shows the direct term alone (and the
    // receiver's directly lit image in the mirror, which camera paths do find).
    Scene scene;
    const float rho = 0.5f, R = 0.8f, I = 1.0f;
    const uint32_t receiver = test::add_diffuse(scene, Color(rho));
    scene.add_quad(Quad(Vec3(-0.1f, 0, -0.1f), Vec3(0, 0, 0.2f), Vec3(0.2f, 0, 0)), receiver);
    Material mirror;
    mirror.name = "mirror";
    mirror.type = MaterialType::Mirror;
    mirror.reflectance = Color(R);
    scene.add_quad(Quad(Vec3(-5, 2, -5), Vec3(10, 0, 0), Vec3(0, 0, 10)),
                   scene.add_material(mirror));
    scene.add_point_light({Vec3(0, 1, 0), Color(I)});
    scene.width = scene.height = 8;
    scene.camera = Camera(Vec3(0, 0.5f, -0.5f), Vec3(0), Vec3(0, 1, 0), 6.0f, 1.0f);
    scene.commit();

    double direct = 0.0, total = 0.0;
    // The receiver's own image: its radiance, times R, over the solid angle 0.04 / 16.
    const double self_direct = R * (rho / kPi * I) * 0.04 / 16.0;
    const double self = R * (rho / kPi * (I + R * I / 9.0)) * 0.04 / 16.0;
    test::for_each_pixel_center(scene.camera, scene.width, scene.height, [&](int, int, Ray ray) {
        const Vec3 x = ray.origin + (-ray.origin.y / ray.dir.y) * ray.dir;  // on the plane y = 0
        ASSERT_LT(std::max(std::fabs(x.x), std::fabs(x.z)), 0.1f);          // on the receiver
        const double d1 = glm::length(Vec3(0, 1, 0) - x), d2 = glm::length(Vec3(0, 3, 0) - x);
        const double E_direct = I * (1.0 / d1) / (d1 * d1);
        const double E_image = R * I * (3.0 / d2) / (d2 * d2);
        direct += rho / kPi * (E_direct + self_direct) / 64.0;
        total += rho / kPi * (E_direct + E_image + self) / 64.0;
    });

    const RenderResult five = render_lesson5(scene, {}, 1024, 3);
    const auto [m5, v5] = image_mean(five.image, five.variance);
    EXPECT_LT(z_score(m5, v5, total), test::z_quantile(kSignificance))
        << "lesson 5: " << m5 << " (standard error " << std::sqrt(v5) << "), closed form " << total
        << " (direct alone " << direct << ")";

    const RenderResult four = render_lesson4(scene, {}, 1024, 4);
    const auto [m4, v4] = image_mean(four.image, four.variance);
    EXPECT_LT(z_score(m4, v4, direct), test::z_quantile(kSignificance))
        << "lesson 4: " << m4 << " (standard error " << std::sqrt(v4) << "), direct term "
        << direct;
    EXPECT_GT(z_score(m4, v4, total), 10.0) << "lesson 4 should miss the mirror's light";
}

TEST(Bidirectional, AgreesWithPathTracingPixelByPixelWhereThatIsUnbiased) {
    // Per-pixel z-test with variance images (at least 99.75% of the channels pass at 0.01,
    // Sidak-corrected), then the image means, on scenes without point-light caustics:
    //  - the Cornell box (diffuse, a one-sided lamp);
    //  - the box of Ray Tracing in One Weekend (a two-sided lamp lighting the ceiling through a
    //    one-unit gap, which light subpaths find and camera paths hardly do);
    //  - three spheres under a sky (the environment: s = 0 and s = 1 only);
    //  - Veach's glossy plates and spherical lights;
    //  - a low-poly sphere with interpolated normals (the adjoint shading-normal correction);
    //  - the box with a mirror and a glass sphere (chains of delta vertices in the weights), by
    //    its image mean only: there lesson 4 finds the caustics by chance, and its per-pixel
    //    values are so skewed that their sample variance is too low (at 4096 spp, 11 of 432
    //    channels failed, every one with lesson 4 below; lesson 5 against a render with pbrt's
    //    weights, which leave the chains out, passed on all 432).
    struct Case {
        const char* file;
        int size;
        bool per_pixel;
    };
    const Case cases[] = {{"/scenes/cornell_box.toml", 16, true},
                          {"/scenes/cornell_box_rtiow.toml", 16, true},
                          {"/scenes/sky.toml", 16, true},
                          {"/scenes/veach_mis.toml", 16, true},
                          {"/scenes/hard/lowpoly_sphere.toml", 16, true},
                          {"/scenes/cornell_spheres.toml", 12, false}};
    for (const auto& [file, size, per_pixel] : cases) {
        const Scene scene = load_scene(std::string(LESSONS_SOURCE_DIR) + file, {size, size});
        const RenderResult five = render_lesson5(scene, {}, 1024, 7);
        const RenderResult four = render_lesson4(scene, {}, 4096, 8);
        const auto [passed, tested] = channels_that_agree(five, four);
        if (per_pixel) {
            EXPECT_GE(passed, 0.9975 * tested) << passed << " of " << tested << " in " << file;
        }
        EXPECT_EQ(five.nan_samples + five.inf_samples, 0u) << file;
        const auto [m5, v5] = image_mean(five.image, five.variance);
        const auto [m4, v4] = image_mean(four.image, four.variance);
        EXPECT_LT(z_score(m5, v5, m4, v4), test::z_quantile(kSignificance))
            << m5 << " vs " << m4 << " in " << file;
    }
}

TEST(Bidirectional, EachStrategyAloneEstimatesAllTheLightOfItsPathLength) {
    // Unweighted, strategy (s, t) is an unbiased estimator of all the light carried by paths of
    // s + t - 1 segments (in this all-diffuse box every strategy can make every such path); the
    // weighted strategies of one length add up to the same light. Image means, z-tests against
    // the standard errors of both renders.
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {8, 8});
    BidirOptions weighted, unweighted;
    weighted.max_depth = unweighted.max_depth = 3;
    weighted.strategy_layers = unweighted.strategy_layers = 3;
    unweighted.unweighted_layers = true;
    const RenderResult w = render_lesson5(scene, weighted, 4096, 21);
    const RenderResult u = render_lesson5(scene, unweighted, 4096, 22);
    ASSERT_EQ(w.layers.size(), 10u);  // 2 + 3 + 4 strategies, and the longer paths
    for (int k = 1; k <= 3; ++k) {
        double total = 0.0, total_var = 0.0;
        for (int s = 0; s <= k; ++s) {
            const int layer = strategy_layer(s, k + 1 - s, 3);
            const auto [m, v] = image_mean(w.layers[layer], w.layer_variances[layer]);
            total += m;
            total_var += v;  // an upper bound: the layers of one sample are correlated
        }
        for (int s = 0; s <= k; ++s) {
            const int t = k + 1 - s, layer = strategy_layer(s, t, 3);
            const auto [m, v] = image_mean(u.layers[layer], u.layer_variances[layer]);
            EXPECT_LT(z_score(m, v, total, total_var), test::z_quantile(kSignificance))
                << "strategy (" << s << ", " << t << ") alone: " << m << " (standard error "
                << std::sqrt(v) << "), all strategies of " << k << " segments: " << total;
        }
    }
    // The weighted layers add up to the image (nothing is longer than 3 segments).
    for (size_t i = 0; i < w.image.pixels.size(); ++i) {
        float sum = 0.0f;
        for (const Image& layer : w.layers) sum += layer.pixels[i].x;
        EXPECT_NEAR(sum, w.image.pixels[i].x, 1e-4f * w.image.pixels[i].x + 1e-6f);
    }
}

TEST(Bidirectional, LightTracingAloneAgreesWithPathTracingOnTheCornellBox) {
    // The t = 1 strategies alone, unweighted, splatted through the camera's importance: every
    // pixel of an all-diffuse scene, and the lamp seen directly (s = 1, t = 1).
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {16, 16});
    BidirOptions tracing;
    tracing.light_tracing = true;
    const RenderResult lt = render_lesson5(scene, tracing, 4096, 31);
    const RenderResult pt = render_lesson4(scene, {}, 4096, 32);
    const auto [passed, tested] = channels_that_agree(lt, pt);
    EXPECT_GE(passed, 0.9975 * tested) << passed << " of " << tested;
    const auto [m1, v1] = image_mean(lt.image, lt.variance);
    const auto [m2, v2] = image_mean(pt.image, pt.variance);
    EXPECT_LT(z_score(m1, v1, m2, v2), test::z_quantile(kSignificance)) << m1 << " vs " << m2;
    EXPECT_GT(lt.splat_bytes, 0u);
}

TEST(Bidirectional, LightSubpathsLowerTheVarianceUnderTheCeilingOfTheRtiowBox) {
    // What lesson 4's --light-paths was for, and lesson 5 does: the RTIOW box's two-sided lamp
    // hangs one unit below the ceiling, which is lit almost only through that gap; camera
    // paths find the gap rarely, light subpaths start in it. Equal samples per pixel, the
    // variance of the pixels that see the ceiling.
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box_rtiow.toml", {16, 16});
    const RenderResult five = render_lesson5(scene, {}, 256, 41);
    const RenderResult four = render_lesson4(scene, {}, 256, 42);
    double v5 = 0.0, v4 = 0.0;
    for (int y = 0; y < 3; ++y)
        for (int x = 4; x < 12; ++x) {
            v5 += five.variance.pixels[y * 16 + x].x;
            v4 += four.variance.pixels[y * 16 + x].x;
        }
    EXPECT_LT(v5, 0.5 * v4) << "variance of the ceiling's pixels: " << v5 << " against " << v4;
}

namespace {

// A one-sided lamp of radiance 2 facing the camera, alone: all light is one segment long, and
// the lamp is parallel to the film, so its image there is the film positions of its corners
// joined by straight lines. `shape` is the lamp's [[shapes]] entry.
Scene lamp_facing_the_camera(const std::string& shape) {
    return build_scene(parse_scene_string(R"([image]
width = 24
height = 24
[camera]
position = [0, 0, -5]
look_at = [0, 0, 0]
fov = 40
[materials.lamp]
type = "diffuse"
albedo = [0, 0, 0]
emission = [2, 2, 2]
[[shapes]]
material = "lamp"
)" + shape,
                                          "lamp.toml"));
}

// The mean of a layer over the image, with its variance, against `expected`: a z-score.
double layer_z(const Image& layer, const Image& variance, double expected) {
    const auto [mean, var] = image_mean(layer, variance);
    return std::fabs(mean - expected) / std::sqrt(std::max(var, 1e-14));
}

}  // namespace

TEST(Bidirectional, ALampSeenDirectlyIsTheCamerasInsideItsImageAndSharedAtItsOutline) {
    // A pixel's expected value is 2 times the share of it that the lamp's image covers. Inside
    // the image the camera's rays take the whole weight (mis.h): exactly 2, no variance, nothing
    // from light tracing (checked one pixel in from the outline, so that a camera ray whose hit
    // rounds into the next pixel still finds the camera's weight there). At the outline the power
    // heuristic shares the light with light tracing: each pixel of a quad lamp against its closed
    // form (z-tests, Sidak-corrected), and the whole image, for a quad and a triangle. Unweighted,
    // light tracing alone and camera rays alone each still estimate all of the lamp's light.
    struct Case {
        const char* name;
        std::string shape;
        std::vector<Vec3> corners;  // the lamp's outline, in order
    };
    const Case cases[] = {
        {"quad",
         "type = \"quad\"  # emits along edge_u x edge_v = -z, towards the camera\n"
         "corner = [-1.13, -0.71, 0]\nedge_u = [0, 1.37, 0]\nedge_v = [1.91, 0, 0]\n",
         {{-1.13f, -0.71f, 0.0f},
          {-1.13f, 0.66f, 0.0f},
          {0.78f, 0.66f, 0.0f},
          {0.78f, -0.71f, 0.0f}}},
        {"triangle",
         "type = \"mesh\"\nvertices = [[-1.37, -0.93, 0], [0.11, 1.23, 0], [1.29, -0.61, 0]]\n"
         "faces = [[0, 1, 2]]  # normal (v1 - v0) x (v2 - v0) along -z, towards the camera\n",
         {{-1.37f, -0.93f, 0.0f}, {0.11f, 1.23f, 0.0f}, {1.29f, -0.61f, 0.0f}}}};
    for (const Case& c : cases) {
        const Scene scene = lamp_facing_the_camera(c.shape);
        std::vector<Vec2> film;  // the image's outline, in pixels
        for (const Vec3& p : c.corners)
            film.push_back(
                *scene.camera.raster_position(glm::normalize(p - scene.camera.position()), 24, 24));
        // Inside the convex outline: on the inner side of every edge (either winding).
        auto inside = [&](float x, float y) {
            int positive = 0, negative = 0;
            for (size_t i = 0; i < film.size(); ++i) {
                const Vec2 a = film[i], b = film[(i + 1) % film.size()];
                const float side = (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
                positive += side > 1e-3f;
                negative += side < -1e-3f;
            }
            return positive == static_cast<int>(film.size()) ||
                   negative == static_cast<int>(film.size());
        };
        double film_area = 0.0;  // in pixels (shoelace)
        for (size_t i = 0; i < film.size(); ++i) {
            const Vec2 a = film[i], b = film[(i + 1) % film.size()];
            film_area += 0.5 * (static_cast<double>(a.x) * b.y - static_cast<double>(b.x) * a.y);
        }
        const double expected_mean = 2.0 * std::fabs(film_area) / (24.0 * 24.0);

        BidirOptions weighted, unweighted;
        weighted.strategy_layers = unweighted.strategy_layers = 1;  // (0, 2), (1, 1), longer
        unweighted.unweighted_layers = true;
        const RenderResult w = render_lesson5(scene, weighted, 256, 51);
        const RenderResult u = render_lesson5(scene, unweighted, 256, 52);
        ASSERT_EQ(w.layers.size(), 3u);
        int deep_inside = 0;
        double traced_elsewhere = 0.0;
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) {
                bool deep = true;  // the pixel and its eight neighbours inside the image
                for (int j = -1; j <= 2; ++j)
                    for (int i = -1; i <= 2; ++i) deep = deep && inside(x + i, y + j);
                const size_t k = static_cast<size_t>(y) * 24 + x;
                if (deep) {
                    ++deep_inside;
                    EXPECT_EQ(w.image.pixels[k].x, 2.0f) << c.name << " " << x << ", " << y;
                    EXPECT_EQ(w.layers[1].pixels[k].x, 0.0f) << c.name << " " << x << ", " << y;
                    EXPECT_EQ(w.variance.pixels[k].x, 0.0f) << c.name << " " << x << ", " << y;
                    EXPECT_GT(u.layers[1].pixels[k].x, 0.0f) << c.name << " " << x << ", " << y;
                } else {
                    traced_elsewhere += w.layers[1].pixels[k].x;
                }
            }
        EXPECT_GE(deep_inside, 20) << c.name;
        EXPECT_GT(traced_elsewhere, 0.0) << c.name;  // light tracing keeps a share of the outline
        const double z_max = test::z_quantile(kSignificance);
        EXPECT_LT(layer_z(w.image, w.variance, expected_mean), z_max) << c.name;
        EXPECT_LT(layer_z(u.layers[0], u.layer_variances[0], expected_mean), z_max)
            << c.name << ": camera rays alone";
        EXPECT_LT(layer_z(u.layers[1], u.layer_variances[1], expected_mean), z_max)
            << c.name << ": light tracing alone";

        if (std::string(c.name) != "quad") continue;
        // Pixel by pixel where the quad's outline crosses: its image is a rectangle on the film.
        const float x0 = std::min(film[0].x, film[2].x), x1 = std::max(film[0].x, film[2].x);
        const float y0 = std::min(film[0].y, film[2].y), y1 = std::max(film[0].y, film[2].y);
        std::vector<std::pair<double, double>> outline;  // (value - closed form, variance)
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) {
                const double covered =
                    std::max(0.0f, std::min(x + 1.0f, x1) - std::max(x + 0.0f, x0)) *
                    std::max(0.0f, std::min(y + 1.0f, y1) - std::max(y + 0.0f, y0));
                const size_t k = static_cast<size_t>(y) * 24 + x;
                if (covered > 0.0 && covered < 1.0)
                    outline.push_back(
                        {w.image.pixels[k].x - 2.0 * covered, w.variance.pixels[k].x});
                else
                    EXPECT_NEAR(w.image.pixels[k].x, 2.0 * covered, covered > 0.0 ? 0.1 : 0.0)
                        << x << ", " << y;  // wholly covered or not at all
            }
        EXPECT_GE(outline.size(), 30u);
        const double z_pixel =
            test::z_quantile(test::sidak(0.01, static_cast<int>(outline.size())));
        for (const auto& [difference, variance] : outline)
            EXPECT_LT(std::fabs(difference) / std::sqrt(std::max(variance, 1e-14)), z_pixel)
                << difference << " (standard error " << std::sqrt(variance) << ")";
    }
}
