// Lesson 4 against closed forms and against itself: the furnace, pbrt's point light in a sphere,
// Russian roulette, MIS against the plain estimator, and lesson 3 against lesson 4's bounces.
#include <gtest/gtest.h>

#include "app.h"
#include "reflection_equation.h"
#include "rendering_equation.h"
#include "scene_file.h"
#include "statistics.h"
#include "test_util.h"

using namespace lessons;

namespace {

// z-tests in this file (furnace 4 x 3 + 4 x 3, point light 2, roulette 1, light paths 2, lesson 3
// vs 4 1, Kronecker sampler 2 x 3).
const double kSignificance = test::sidak(0.01, 36);

// The estimators of lesson 4: plain path tracing, with next-event estimation (and MIS), and with
// light-path connections as well.
struct Strategies {
    const char* name;
    bool next_event, light_paths;
    PathOptions options() const {
        PathOptions o;
        o.next_event = next_event;
        o.light_paths = light_paths;
        return o;
    }
};
constexpr Strategies kStrategies[] = {{"BSDF sampling only", false, false},
                                      {"next-event estimation", true, false},
                                      {"next-event estimation and light paths", true, true}};

test::MeanAndError estimate(const Scene& scene, const Ray& ray, const PathOptions& options, int n,
                            uint64_t seed) {
    const LightSampler lights(scene);
    std::vector<double> values;
    for (int i = 0; i < n; ++i) {
        Rng rng(seed, 0, static_cast<uint64_t>(i));
        values.push_back(path_trace(scene, lights, ray, rng, options).x);
    }
    return test::mean_and_error(values);
}

Scene furnace(float rho, float Le) {
    Scene scene;
    Material m;
    m.name = "furnace";
    m.albedo.value = Color(rho);
    m.emission = Color(Le);
    m.two_sided = true;
    scene.add_sphere({Vec3(0), 1.0f}, scene.add_material(m));
    scene.commit();
    return scene;
}

// Image mean and variance of the mean, from a render's per-pixel variances.
std::pair<double, double> image_mean(const Image& image, const Image& variance) {
    double mean = 0.0, var = 0.0;
    const double n = static_cast<double>(image.pixels.size());
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        mean += image.pixels[i].x / n;
        var += variance.pixels[i].x / (n * n);
    }
    return {mean, var};
}

// Two renders of one scene by lesson 4 with other options, sample counts and seeds.
std::pair<RenderResult, RenderResult> render_both(const Scene& scene, const PathOptions& a,
                                                  int spp_a, const PathOptions& b, int spp_b,
                                                  uint64_t seed) {
    const LightSampler lights(scene);
    RenderSettings settings;
    settings.progress = false;
    settings.seed = seed;
    RenderResult first =
        render_scene(scene, make_path_tracing_model(scene, lights, a), spp_a, settings);
    settings.seed = seed + 1;
    RenderResult second =
        render_scene(scene, make_path_tracing_model(scene, lights, b), spp_b, settings);
    return {std::move(first), std::move(second)};
}

// The per-pixel z-test of two renders of one scene with their variance images (Mitsuba's
// test_renders): how many of the channels agree at 0.01, Sidak-corrected over all of them, and
// how many were tested. A channel with no variance in either must be equal.
std::pair<int, int> channels_that_agree(const RenderResult& a, const RenderResult& b) {
    const int tested = static_cast<int>(a.image.pixels.size()) * 3;
    const double z_max = test::z_quantile(test::sidak(0.01, tested));
    int passed = 0;
    for (size_t i = 0; i < a.image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const double d = a.image.pixels[i][c] - b.image.pixels[i][c];
            const double v = a.variance.pixels[i][c] + b.variance.pixels[i][c];
            passed += v > 0.0 ? std::fabs(d) / std::sqrt(v) < z_max : std::fabs(d) < 1e-6;
        }
    }
    return {passed, tested};
}

}  // namespace

TEST(RenderingEquation, FurnaceIsLeOverOneMinusRho) {
    const Ray ray{Vec3(0.1f, -0.2f, 0.0f), glm::normalize(Vec3(0.3f, 0.4f, 1.0f))};
    for (float rho : {0.3f, 0.5f, 0.8f, 0.95f}) {
        const Scene scene = furnace(rho, 1.0f);
        for (const Strategies& strategies : kStrategies) {
            const auto [mean, se] = estimate(scene, ray, strategies.options(), 20000, 1);
            EXPECT_NEAR(mean, 1.0 / (1.0 - rho), test::z_quantile(kSignificance) * se + 1e-5)
                << "rho " << rho << " with " << strategies.name;
        }
    }
}

TEST(RenderingEquation, FurnaceWithDepthCappedAtKSumsKTerms) {
    const Ray ray{Vec3(0), Vec3(0, 0, 1)};
    const Scene scene = furnace(0.8f, 1.0f);
    for (int k : {1, 2, 3, 6}) {
        for (const Strategies& strategies : kStrategies) {
            PathOptions options = strategies.options();
            options.max_depth = k;
            const auto [mean, se] = estimate(scene, ray, options, 20000, 2);
            const double expected = (1.0 - std::pow(0.8, k)) / (1.0 - 0.8);
            EXPECT_NEAR(mean, expected, test::z_quantile(kSignificance) * se + 1e-5)
                << "depth " << k << " with " << strategies.name;
        }
    }
}

TEST(RenderingEquation, PointLightOfIntensityPiInAUnitSphereOfAlbedoHalfGivesOne) {
    // pbrt's check: E = pi / 1^2 on the wall, direct L = rho E / pi = 0.5, and the interior of a
    // sphere multiplies by 1 / (1 - rho): L = 1 everywhere.
    Scene scene;
    scene.add_sphere({Vec3(0), 1.0f}, test::add_diffuse(scene, Color(0.5f)));
    scene.add_point_light({Vec3(0), Color(kPi)});
    scene.commit();
    for (const Ray& ray : {Ray{Vec3(0), Vec3(0, 0, 1)},
                           Ray{Vec3(0.2f, 0.1f, 0), glm::normalize(Vec3(-1, 0.3f, 0.2f))}}) {
        const auto [mean, se] = estimate(scene, ray, PathOptions{}, 20000, 3);
        EXPECT_NEAR(mean, 1.0, test::z_quantile(kSignificance) * se + 1e-5);
    }
}

TEST(RenderingEquation, RussianRouletteChangesTheVarianceNotTheMean) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {24, 24});
    const LightSampler lights(scene);
    RenderSettings settings;
    settings.progress = false;
    PathOptions with, without;
    with.roulette_after = 0;
    without.roulette_after = -1;
    settings.seed = 1;
    const RenderResult a =
        render_scene(scene, make_path_tracing_model(scene, lights, with), 128, settings);
    settings.seed = 2;
    const RenderResult b =
        render_scene(scene, make_path_tracing_model(scene, lights, without), 128, settings);
    const auto [ma, va] = image_mean(a.image, a.variance);
    const auto [mb, vb] = image_mean(b.image, b.variance);
    EXPECT_LT(std::fabs(ma - mb) / std::sqrt(va + vb), test::z_quantile(kSignificance))
        << ma << " vs " << mb;
    EXPECT_GT(va, vb);  // roulette trades variance for shorter paths
    EXPECT_LT(a.stats.rays, b.stats.rays);
}

TEST(RenderingEquation, MisAndThePlainEstimatorAgreePixelByPixel) {
    // Per-pixel z-test with variance images (Mitsuba's test_renders): at least 99.75% of the
    // pixels pass at 0.01, Sidak-corrected over the pixels.
    // The plain estimator finds the small Cornell lamp only by chance, so its per-pixel values
    // are very skewed: with too few samples, a dark pixel's sample mean *and* sample variance
    // are both low, and the z-test fails although nothing is biased (at 32 x 32 pixels and
    // 2048 samples, 35 of 3072 channels failed, every one with plain below MIS, while the image
    // means agreed to 0.4%). 8192 samples per pixel make the normal approximation hold.
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {16, 16});
    PathOptions mis, plain;
    plain.next_event = false;
    const auto [a, b] = render_both(scene, mis, 1024, plain, 8192, 3);
    const auto [passed, tested] = channels_that_agree(a, b);
    EXPECT_GE(passed, 0.9975 * tested) << passed << " of " << tested;
    EXPECT_EQ(a.nan_samples + b.nan_samples + a.inf_samples + b.inf_samples, 0u);
}

TEST(RenderingEquation, LightPathsAgreeWithNextEventEstimationPixelByPixel) {
    // The three strategies' weights must sum to one on every path: a wrong weight shows as a
    // bias in some pixels. The same per-pixel z-test as above, then the image means, on
    //  - the Cornell box of Ray Tracing in One Weekend: its lamp, one unit below the ceiling,
    //    emits on both sides, so the ceiling above it is lit through a one-unit gap, the case
    //    light paths are for;
    //  - a low-poly sphere with interpolated normals under a one-sided lamp and a sky: light
    //    paths land on shading normals that differ from the facets', and the sky starts none.
    const std::pair<const char*, int> cases[] = {{"/scenes/cornell_box_rtiow.toml", 16},
                                                 {"/scenes/hard/lowpoly_sphere.toml", 20}};
    PathOptions nee, light_paths;
    light_paths.light_paths = true;
    for (const auto& [file, size] : cases) {
        const Scene scene = load_scene(std::string(LESSONS_SOURCE_DIR) + file, {size, size});
        const auto [a, b] = render_both(scene, light_paths, 2048, nee, 4096, 7);
        const auto [passed, tested] = channels_that_agree(a, b);
        EXPECT_GE(passed, 0.9975 * tested) << passed << " of " << tested << " in " << file;
        EXPECT_EQ(a.nan_samples + a.inf_samples, 0u) << file;
        const auto [ma, va] = image_mean(a.image, a.variance);
        const auto [mb, vb] = image_mean(b.image, b.variance);
        EXPECT_LT(std::fabs(ma - mb) / std::sqrt(va + vb), test::z_quantile(kSignificance))
            << ma << " vs " << mb << " in " << file;
    }
}

TEST(RenderingEquation, LightPathsSeeInterpolatedNormalsAsCameraPathsDo) {
    // A floor of two triangles whose vertex normals all lean 40 degrees towards +x, a small lamp
    // above it and a wall behind it, seen from the front: much of the wall's light comes from
    // the floor, where a light path lands on a shading normal far from the geometric one. The
    // connection must then scale f_Y by cos(shading) / cos(geometric) towards the lamp, or the
    // wall's pixels drift from what next-event estimation gives (without it, 102 of 192
    // channels agreed). It also caught connections to triangles that their own triangle
    // blocked (78 of 192 agreed, with flat normals too): the shadow ray now ignores Y's own
    // primitive, as next-event estimation's ignores the light's.
    Scene scene;
    const uint32_t white = test::add_diffuse(scene, Color(0.8f));
    const Vec3 n = glm::normalize(Vec3(std::sin(0.7f), std::cos(0.7f), 0.0f));
    scene.add_mesh({Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(1, 0, 1), Vec3(-1, 0, 1)}, {n, n, n, n},
                   {}, {{{0, 2, 1}, white, true}, {{0, 3, 2}, white, true}});
    scene.add_quad(Quad(Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 2, 0)), white);  // the wall
    Material lamp;
    lamp.name = "lamp";
    lamp.emission = Color(20.0f);
    scene.add_quad(Quad(Vec3(-0.1f, 1.0f, -0.1f), Vec3(0.2f, 0, 0), Vec3(0, 0, 0.2f)),
                   scene.add_material(lamp));
    scene.width = scene.height = 8;
    scene.camera = Camera(Vec3(0, 1, -3), Vec3(0, 0.8f, 1), Vec3(0, 1, 0), 40.0f, 1.0f);
    scene.commit();
    PathOptions nee, light_paths;
    light_paths.light_paths = true;
    const auto [a, b] = render_both(scene, light_paths, 1 << 16, nee, 1 << 16, 11);
    const auto [passed, tested] = channels_that_agree(a, b);
    EXPECT_GE(passed, 0.99 * tested) << passed << " of " << tested;
}

TEST(RenderingEquation, LightPathsLowerTheVarianceUnderTheCeilingOfTheRtiowBox) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box_rtiow.toml", {16, 16});
    const LightSampler lights(scene);
    PathOptions nee, light_paths;
    light_paths.light_paths = true;
    // And the point of them: less variance per sample where the light from above the lamp
    // arrives. One camera ray to the back wall just below the ceiling, 40000 samples each: the
    // standard errors were 0.00064 and 0.00132 (a variance 4.3 times smaller), and 0.00034
    // against 0.00042 at (450, 300) on the same wall.
    const Vec3 eye(278, 278, -800);
    const Ray ray{eye, glm::normalize(Vec3(278, 520, 555) - eye)};
    std::vector<double> with, without;
    Rng rng(9);
    for (int i = 0; i < 40000; ++i) {
        with.push_back(path_trace(scene, lights, ray, rng, light_paths).x);
        without.push_back(path_trace(scene, lights, ray, rng, nee).x);
    }
    const test::MeanAndError w = test::mean_and_error(with), wo = test::mean_and_error(without);
    EXPECT_LT(w.standard_error, 0.75 * wo.standard_error);
}

TEST(RenderingEquation, LessonThreeEqualsEmissionPlusTheFirstBounce) {
    // Lesson 3 computes L_e + direct light; lesson 4's bounce layers 0 and 1 are E and K E.
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {24, 24});
    const LightSampler lights(scene);
    RenderSettings settings;
    settings.progress = false;
    settings.seed = 5;
    const RenderResult direct = render_scene(
        scene, make_reflection_model(scene, lights, ReflectionOptions{}), 256, settings);
    PathOptions layered;
    layered.bounce_layers = 2;
    settings.seed = 6;
    const Model model = make_path_tracing_model(scene, lights, layered);
    const RenderResult path = render_scene(scene, model, 256, settings);
    ASSERT_EQ(path.layers.size(), 3u);  // bounce0, bounce1, bounce2plus
    Image first_two(24, 24);
    for (size_t i = 0; i < first_two.pixels.size(); ++i)
        first_two.pixels[i] = path.layers[0].pixels[i] + path.layers[1].pixels[i];
    // The layer variances are not kept; the total's variance bounds theirs from above here.
    const auto [m3, v3] = image_mean(direct.image, direct.variance);
    const auto [m4, v4] = image_mean(first_two, path.variance);
    EXPECT_LT(std::fabs(m3 - m4) / std::sqrt(v3 + v4), test::z_quantile(kSignificance))
        << m3 << " vs " << m4;
    // And the layers add up to the image.
    for (size_t i = 0; i < first_two.pixels.size(); ++i)
        EXPECT_NEAR(first_two.pixels[i].x + path.layers[2].pixels[i].x, path.image.pixels[i].x,
                    1e-4f * path.image.pixels[i].x + 1e-6f);
}

TEST(RenderingEquation, TheKroneckerSamplerIsUnbiased) {
    // Rng::kronecker (--sampler kronecker) correlates the samples of one pixel, never their
    // distribution: each value is uniform because of the pixel's random shift. Pixels have
    // independent shifts, so pixel means are independent: the z-test runs over pixels.
    const Ray ray{Vec3(0.1f, -0.2f, 0.0f), glm::normalize(Vec3(0.3f, 0.4f, 1.0f))};
    for (float rho : {0.5f, 0.8f}) {
        const Scene scene = furnace(rho, 1.0f);
        const LightSampler lights(scene);
        for (const Strategies& strategies : kStrategies) {
            const PathOptions options = strategies.options();
            std::vector<double> pixel_means;
            for (uint64_t pixel = 0; pixel < 4000; ++pixel) {
                double sum = 0.0;
                for (uint64_t s = 0; s < 8; ++s) {
                    Rng rng = Rng::kronecker(11, pixel, s);
                    sum += path_trace(scene, lights, ray, rng, options).x;
                }
                pixel_means.push_back(sum / 8.0);
            }
            const auto [mean, se] = test::mean_and_error(pixel_means);
            EXPECT_NEAR(mean, 1.0 / (1.0 - rho), test::z_quantile(kSignificance) * se + 1e-5)
                << "rho " << rho << " with " << strategies.name;
        }
    }
}
