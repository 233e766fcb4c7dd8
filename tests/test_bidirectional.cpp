// Lesson 5 against closed forms, against lesson 4, and against itself.
#include <gtest/gtest.h>

#include "04_rendering_equation/rendering_equation.h"
#include "05_bidirectional/bidirectional.h"
#include "05_bidirectional/mis.h"
#include "given_paths.h"
#include "io/scene_file.h"
#include "render_statistics.h"
#include "scene/scene.h"
#include "test_util.h"

using namespace lessons;
using test::channels_that_agree;
using test::image_mean;

namespace {

// z-tests in this file: point-light caustic 2, furnace 3 + 3, strategies 9, light tracing 1 + 3
// (and its negative control 1), pixel-by-pixel image means 6, a lamp seen directly 6 (its
// outline's pixels: a family of their own), a light almost never chosen 2.
const double kSignificance = test::sidak(0.01, 36);

RenderResult render_lesson5(const Scene& scene, const BidirOptions& options, int spp, uint64_t seed,
                            int threads = 0) {
    const LightSampler lights(scene);
    RenderSettings settings;
    settings.progress = false;
    settings.seed = seed;
    settings.threads = threads;
    return render_scene(scene, BidirectionalModel(scene, options), spp, settings);
}

RenderResult render_lesson4(const Scene& scene, const PathOptions& options, int spp,
                            uint64_t seed) {
    const LightSampler lights(scene);
    RenderSettings settings;
    settings.progress = false;
    settings.seed = seed;
    return render_scene(scene, PathTracingModel(scene, options), spp, settings);
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

namespace {

void expect_weights_sum_to_one(const Bidir& b, const std::vector<test::GivenPath>& paths) {
    for (const test::GivenPath& path : paths) {
        const test::WeightSum w = test::weights_of_every_strategy(b, path);
        EXPECT_GE(w.strategies, 1) << path.name;
        EXPECT_NEAR(w.sum, 1.0, 1e-5) << path.name << " (" << w.terms << ")";
    }
}

}  // namespace

TEST(Bidirectional, MisWeightsOfEveryStrategySumToOne) {
    // The power heuristic's weights of one path, over the strategies that can make it, sum to 1
    // (Veach 1997, eq. 9.4 and 10.9): the estimator is unbiased only then. Each path is made from
    // both ends (subpaths_along), split at every s and weighed as connect() weighs it, in a room
    // with every kind of light and vertex the weights treat apart: a one-sided rectangle (sampled
    // by solid angle, also seen from near its plane), a sphere lamp, the back of a two-sided lamp,
    // a point light, a glossy wall, two flat mirrors, a glass ball; then a uniform sky and an
    // environment map with a sun; a lamp listed after a light 1e9 times brighter; and a lamp
    // seen directly, inside its image (the camera alone) and at its outline (shared). The
    // weights are checked against each other and against this test's own list of the
    // strategies that can run; a density wrong the same way in every strategy would pass.
    const test::Room room = test::room_with_every_kind_of_vertex();
    ASSERT_EQ(room.scene.area_lights().size(), 3u);
    const LightSampler lights(room.scene);
    const Bidir b{room.scene, lights, room.scene.camera, room.scene.width, room.scene.height};
    expect_weights_sum_to_one(b, test::paths_in_the_room(room));

    // The sky: uniform, then a map with a sun 1e9 times its other texels, turned by 30 degrees.
    for (const bool map : {false, true}) {
        const Scene open = test::open_sky(map);
        const LightSampler sky_lights(open);
        const Bidir sb{open, sky_lights, open.camera, open.width, open.height};
        expect_weights_sum_to_one(sb, test::paths_under_the_sky());
    }

    // A lamp after one 1e9 times brighter in the table the lights are chosen from (point lights
    // come first): its share of the power, about 1e-10, is below a float's resolution near 1.
    const test::FaintLamp pair = test::faint_lamp_after_a_bright_light();
    const LightSampler pair_lights(pair.scene);
    const Bidir pb{pair.scene, pair_lights, pair.scene.camera, pair.scene.width, pair.scene.height};
    expect_weights_sum_to_one(pb, test::paths_of_the_faint_lamp(pair));

    // A lamp seen directly (one segment): inside its image the camera alone (s = 0: 1, s = 1:
    // 0, mis.h), at the outline the power heuristic.
    const Scene facing = lamp_facing_the_camera(
        "type = \"quad\"\ncorner = [-1.13, -0.71, 0]\n"
        "edge_u = [0, 1.37, 0]\nedge_v = [1.91, 0, 0]\n");
    const LightSampler facing_lights(facing);
    const Bidir fb{facing, facing_lights, facing.camera, facing.width, facing.height};
    const Vec3 toward_camera(0, 0, -1);
    const uint32_t lamp = facing.area_lights()[0].material;
    for (const bool inside : {true, false}) {
        const Vec3 p = inside ? Vec3(0.1f, 0.1f, 0) : Vec3(0.775f, 0.3f, 0);
        const test::GivenPath seen{
            inside ? "a lamp seen directly, inside" : "at the lamp's outline",
            test::on_area_light(facing, lamp, p, toward_camera),
            {}};
        const test::WeightSum w = test::weights_of_every_strategy(fb, seen);
        EXPECT_EQ(w.strategies, 2) << seen.name;
        EXPECT_NEAR(w.sum, 1.0, 1e-5) << seen.name << " (" << w.terms << ")";
        if (inside)
            EXPECT_EQ(w.first, 1.0f) << seen.name << ": the camera's alone";
        else
            EXPECT_TRUE(w.first > 0.0f && w.first < 1.0f) << seen.name << ": shared";
    }
}

TEST(Bidirectional, ALightThatIsAlmostNeverChosenKeepsItsLight) {
    // A light whose share of the power is far below a float's resolution is still chosen now and
    // then (sampling/discrete.h), and its light, found almost only by camera paths that hit it,
    // keeps its whole weight (mis.cpp): lesson 5 agrees with lesson 4 pixel by pixel. Two cases:
    //  - a faint lamp (power pi W) lighting a floor, listed after a point light 1e8 times more
    //    powerful whose light never leaves the black ball around it;
    //  - a dim sky, an environment map with a sun 1e9 times brighter than each other texel just
    //    above the horizon (the texels after it in its row come after it in its column table),
    //    the sun hidden by a black wall.
    // Both lost light when a share rounded to 0 was weighed as if it could be sampled (measured
    // before the fix: lesson 5's mean 0.2% of lesson 4's on the faint lamp, 2.29e-5 against
    // 0.0119; under the map 0.485 against 0.515, the light of the texels after the sun).
    for (const bool sky : {false, true}) {
        Scene scene;
        Material floor, black, lamp;
        floor.name = "floor";
        floor.albedo.value = Color(0.5f);
        black.name = "black";
        black.albedo.value = Color(0.0f);
        lamp.name = "lamp";
        lamp.albedo.value = Color(0.0f);
        lamp.emission = Color(1.0f);
        const uint32_t f = scene.add_material(floor), k = scene.add_material(black);
        scene.add_quad(Quad(Vec3(-4, 0, -4), Vec3(0, 0, 8), Vec3(8, 0, 0)), f);
        scene.add_sphere({Vec3(0, 0.5f, 0), 0.5f}, f);
        if (sky) {
            // The sun at texel (5, 3): just above the horizon, phi from 112.5 to 135 degrees; the
            // texels after it in its row (phi 135 to 360) have shares of 1e-9 each.
            std::vector<Color> texels(16 * 8, Color(1.0f));
            texels[3 * 16 + 5] = Color(1e9f);
            scene.environment_map =
                std::make_shared<const EnvironmentMap>(16, 8, texels, 0.0f, 1.0f);
            // A black wall 15 m away across the sun's directions, wide and high enough to hide
            // it from every point of the floor.
            const float phi = 123.75f * kPi / 180.0f;
            const Vec3 across(-std::sin(phi), 0, std::cos(phi));
            const Vec3 centre = 15.0f * Vec3(std::cos(phi), 0, std::sin(phi));
            scene.add_quad(
                Quad(centre - 9.0f * across - Vec3(0, 1, 0), 18.0f * across, Vec3(0, 11, 0)), k);
        } else {
            scene.add_quad(Quad(Vec3(-1, 2, -1.5f), Vec3(1, 0, 0), Vec3(0, 0, 1)),
                           scene.add_material(lamp));
            scene.add_point_light({Vec3(2.5f, 0.5f, 2.5f), Color(1e8f / 4.0f)});
            scene.add_sphere({Vec3(2.5f, 0.5f, 2.5f), 0.2f}, k);
        }
        scene.width = scene.height = 12;
        scene.camera = Camera(Vec3(0, 1.5f, -4), Vec3(0, 0.4f, 0), Vec3(0, 1, 0), 45.0f, 1.0f);
        scene.commit();
        const RenderResult five = render_lesson5(scene, {}, 1024, 61);
        const RenderResult four = render_lesson4(scene, {}, 2048, 62);
        const auto [passed, tested] = channels_that_agree(five, four);
        EXPECT_GE(passed, 0.9975 * tested) << passed << " of " << tested << (sky ? " (sky)" : "");
        const auto [m5, v5] = image_mean(five.image, five.variance);
        const auto [m4, v4] = image_mean(four.image, four.variance);
        EXPECT_GT(m4, 0.01) << (sky ? "sky" : "lamp");  // the image is not black
        EXPECT_LT(z_score(m5, v5, m4, v4), test::z_quantile(kSignificance))
            << m5 << " vs " << m4 << (sky ? " (sky)" : " (lamp)");
        EXPECT_EQ(five.nan_samples + five.inf_samples, 0u);
    }
}

TEST(Bidirectional, APointLightSeenDirectlyIsItsIntensityOverTheFilmAreaOfItsPixel) {
    // Only strategy (1, 1) can draw a point light seen directly: the light subpath's first vertex
    // joined to the camera. Its pixel gets W I / d^2 with the camera's importance W = 1 /
    // (A_pixel cos^3 theta) (camera.h; A_pixel the film's area per pixel at distance 1), exactly
    // (the only light is always chosen and always lands there); every other pixel gets nothing.
    // On a film whose aspect is not 1, the light off its axis, with the whole estimator and
    // with light tracing alone.
    const float I = 3.0f;
    Scene scene;
    const Vec3 light(0.7f, -0.4f, 3.0f);
    scene.add_point_light({light, Color(I)});
    scene.width = 40;
    scene.height = 24;
    scene.camera = Camera(Vec3(0.1f, 0, 0), Vec3(0.1f, 0, 1), Vec3(0, 1, 0), 50.0f, 40.0f / 24.0f);
    scene.commit();
    const Vec3 to_light = light - scene.camera.position();
    const double d2 = glm::dot(to_light, to_light);
    const Vec3 dir = glm::normalize(to_light);
    const double cos_theta = glm::dot(dir, scene.camera.forward());
    const double a_pixel = scene.camera.image_plane_area() / (40.0 * 24.0);
    const double expected = I / (d2 * a_pixel * cos_theta * cos_theta * cos_theta);
    const Vec2 raster = *scene.camera.raster_position(dir, 40, 24);
    const size_t lit = static_cast<size_t>(raster.y) * 40 + static_cast<size_t>(raster.x);
    for (const bool alone : {false, true}) {
        BidirOptions options;
        options.light_tracing = alone;
        options.strategy_layers = alone ? 0 : 1;
        const RenderResult r = render_lesson5(scene, options, 4, 71);
        for (size_t k = 0; k < r.image.pixels.size(); ++k) {
            const double v = r.image.pixels[k].x;
            if (k == lit)
                EXPECT_NEAR(v, expected, 1e-5 * expected) << (alone ? "light tracing" : "bdpt");
            else
                EXPECT_EQ(v, 0.0) << "pixel " << k;
        }
        if (!alone) {  // the layer of strategy (1, 1) holds all of it
            ASSERT_EQ(r.layers.size(), 3u);
            EXPECT_EQ(r.layers[1].pixels[lit].x, r.image.pixels[lit].x);
        }
    }
}
namespace {

// The scene without its sky (the light that light tracing can find: no light subpath starts at
// the environment).
Scene without_sky(Scene scene) {
    scene.background = Color(0.0f);
    scene.environment_map = nullptr;
    return scene;
}

}  // namespace

TEST(Bidirectional, LightTracingAloneAgreesWithPathTracingForEveryLampKind) {
    // Light tracing alone (the t = 1 strategies, unweighted), against lesson 4 pixel by pixel and
    // in the mean, where light tracing can make every path: a two-sided lamp standing on a floor
    // (light leaves both sides, and the camera sees both), a sphere lamp under a sky (light
    // tracing shows the lamp's light alone, lesson 4 without the sky), and a low-poly sphere
    // with interpolated normals, where the light side needs the adjoint shading-normal correction
    // (Veach 1997, 5.3) and the BSDF as the camera's side sees it (Bsdf::seen_from: near the
    // silhouette the shading-normal fallback depends on the direction towards the camera, not
    // the one the light came from; without it 15 of 576 channels failed, light tracing there
    // about half of lesson 4). Light subpaths without the correction (`--naive adjoint`) fail
    // both in the mean and per pixel: the negative control (measured: 471 of 576 channels
    // agree, the means 15 standard errors apart).
    const std::string two_sided = R"([image]
width = 16
height = 12
[camera]
position = [2.5, 1.6, -3]
look_at = [0, 0.4, 0]
fov = 50
[materials.floor]
type = "diffuse"
albedo = [0.6, 0.5, 0.4]
[materials.lamp]
type = "diffuse"
albedo = [0, 0, 0]
emission = [3, 3, 3]
two_sided = true
[[shapes]]
type = "quad"
material = "floor"
corner = [-3, 0, -3]
edge_u = [0, 0, 6]
edge_v = [6, 0, 0]
[[shapes]]
type = "quad"
material = "lamp"
corner = [-0.4, 0.1, 0]
edge_u = [0.8, 0, 0]
edge_v = [0, 0.6, 0.3]
)";
    const std::string sphere = R"([image]
width = 16
height = 12
[camera]
position = [0, 1.5, -3]
look_at = [0, 0.3, 0]
fov = 50
[background]
radiance = [0.2, 0.25, 0.3]
[materials.floor]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[materials.lamp]
type = "diffuse"
albedo = [0, 0, 0]
emission = [4, 3, 2]
[[shapes]]
type = "quad"
material = "floor"
corner = [-3, 0, -3]
edge_u = [0, 0, 6]
edge_v = [6, 0, 0]
[[shapes]]
type = "sphere"
material = "lamp"
center = [0.3, 0.6, 0.2]
radius = 0.25
)";
    struct Case {
        const char* name;
        Scene scene;
    };
    std::vector<Case> cases;
    cases.push_back(
        {"two-sided lamp", build_scene(parse_scene_string(two_sided, "two_sided.toml"))});
    cases.push_back({"sphere lamp", build_scene(parse_scene_string(sphere, "sphere.toml"))});
    // The low-poly sphere of scenes/hard/lowpoly_sphere.toml, lit by a lamp above the camera
    // (there, the sky and a lamp behind it: light tracing finds no sky light, and that lamp lights
    // only a grazing crescent of what the camera sees, which light paths reach too rarely for a
    // per-pixel test at this size).
    const std::string lowpoly = R"([image]
width = 16
height = 12
[camera]
position = [0, 0.3, -4]
look_at = [0, 0, 0]
fov = 40
[materials.clay]
type = "diffuse"
albedo = [0.8, 0.5, 0.3]
[materials.lamp]
type = "diffuse"
albedo = [0, 0, 0]
emission = [20, 20, 20]
[[shapes]]
type = "mesh"
file = ")" + std::string(LESSONS_SOURCE_DIR) +
                                R"(/scenes/hard/meshes/lowpoly_sphere_smooth.obj"
material = "clay"
[[shapes]]
type = "quad"
material = "lamp"
corner = [-0.5, 2.5, -2.5]
edge_u = [1, 0, 0]
edge_v = [0, 0, 1]
)";
    cases.push_back({"low-poly sphere", build_scene(parse_scene_string(lowpoly, "lowpoly.toml"))});
    BidirOptions tracing;
    tracing.light_tracing = true;
    for (Case& c : cases) {
        const bool has_sky = c.scene.has_environment();
        {
            const LightSampler lights(c.scene);
            const auto model = BidirectionalModel(c.scene, tracing);
            EXPECT_EQ(has_sky, !model.biased_because.empty()) << c.name;  // "cannot show the sky"
        }
        // Many samples for so small an image: at a lamp's edge and at the sphere's silhouette a
        // pixel can get its light from a sliver so thin that 4096 samples are likely to miss it
        // (and then their variance estimate is 0 too), for either estimator.
        const RenderResult lt = render_lesson5(c.scene, tracing, 16384, 81);
        const RenderResult pt = render_lesson4(without_sky(c.scene), {}, 16384, 82);
        const auto [passed, tested] = channels_that_agree(lt, pt);
        EXPECT_GE(passed, 0.9975 * tested) << passed << " of " << tested << " in " << c.name;
        const auto [m1, v1] = image_mean(lt.image, lt.variance);
        const auto [m2, v2] = image_mean(pt.image, pt.variance);
        EXPECT_LT(z_score(m1, v1, m2, v2), test::z_quantile(kSignificance))
            << m1 << " vs " << m2 << " in " << c.name;
        EXPECT_EQ(lt.nan_samples + lt.inf_samples, 0u) << c.name;
        if (std::string(c.name) != "low-poly sphere") continue;
        Scene naive = c.scene;
        naive.naive.no_adjoint_correction = true;
        const RenderResult wrong = render_lesson5(naive, tracing, 16384, 81);
        const auto [mw, vw] = image_mean(wrong.image, wrong.variance);
        const auto [failed_passed, failed_tested] = channels_that_agree(wrong, pt);
        EXPECT_LT(failed_passed, 0.9975 * failed_tested)
            << "without the correction: " << failed_passed << " of " << failed_tested;
        EXPECT_GT(z_score(mw, vw, m2, v2), test::z_quantile(kSignificance))
            << "without the correction: " << mw << " vs " << m2;
    }
}
