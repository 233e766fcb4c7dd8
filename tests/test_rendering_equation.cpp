// Lesson 4 against closed forms and against itself: the furnace, pbrt's point light in a sphere,
// Russian roulette, MIS against the plain estimator, and lesson 3 against lesson 4's bounces.
#include <gtest/gtest.h>

#include "03_reflection_equation/reflection_equation.h"
#include "04_rendering_equation/rendering_equation.h"
#include "driver/app.h"
#include "io/scene_file.h"
#include "render_statistics.h"
#include "test_util.h"

using namespace lessons;
using test::channels_that_agree;
using test::image_mean;

namespace {

// z-tests in this file (furnace 4 x 2 + 4 x 2, point light 2, roulette 1, lesson 3 vs 4 1,
// Kronecker sampler 2 x 2).
const double kSignificance = test::sidak(0.01, 24);

// The estimators of lesson 4: plain path tracing, and with next-event estimation (and MIS).
struct Strategies {
    const char* name;
    bool next_event;
    PathOptions options() const {
        PathOptions o;
        o.next_event = next_event;
        return o;
    }
};
constexpr Strategies kStrategies[] = {{"BSDF sampling only", false},
                                      {"next-event estimation", true}};

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

// Two renders of one scene by lesson 4 with other options, sample counts and seeds.
std::pair<RenderResult, RenderResult> render_both(const Scene& scene, const PathOptions& a,
                                                  int spp_a, const PathOptions& b, int spp_b,
                                                  uint64_t seed) {
    const LightSampler lights(scene);
    RenderSettings settings;
    settings.progress = false;
    settings.seed = seed;
    RenderResult first = render_scene(scene, PathTracingModel(scene, a), spp_a, settings);
    settings.seed = seed + 1;
    RenderResult second = render_scene(scene, PathTracingModel(scene, b), spp_b, settings);
    return {std::move(first), std::move(second)};
}

}  // namespace

TEST(RenderingEquation, FurnaceIsLeOverOneMinusRho) {
    const Ray ray{Vec3(0.1f, -0.2f, 0.0f), glm::normalize(Vec3(0.3f, 0.4f, 1.0f))};
    for (float rho : {0.3f, 0.5f, 0.8f, 0.95f}) {
        const Scene scene = test::furnace(rho, 1.0f);
        for (const Strategies& strategies : kStrategies) {
            const auto [mean, se] = estimate(scene, ray, strategies.options(), 20000, 1);
            EXPECT_NEAR(mean, 1.0 / (1.0 - rho), test::z_quantile(kSignificance) * se + 1e-5)
                << "rho " << rho << " with " << strategies.name;
        }
    }
}

TEST(RenderingEquation, FurnaceWithDepthCappedAtKSumsKTerms) {
    const Ray ray{Vec3(0), Vec3(0, 0, 1)};
    const Scene scene = test::furnace(0.8f, 1.0f);
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
    const RenderResult a = render_scene(scene, PathTracingModel(scene, with), 128, settings);
    settings.seed = 2;
    const RenderResult b = render_scene(scene, PathTracingModel(scene, without), 128, settings);
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

TEST(RenderingEquation, LessonThreeEqualsEmissionPlusTheFirstBounce) {
    // Lesson 3 computes L_e + direct light; lesson 4's bounce layers 0 and 1 are E and K E.
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {24, 24});
    const LightSampler lights(scene);
    RenderSettings settings;
    settings.progress = false;
    settings.seed = 5;
    const RenderResult direct =
        render_scene(scene, ReflectionModel(scene, ReflectionOptions{}), 256, settings);
    PathOptions layered;
    layered.bounce_layers = 2;
    settings.seed = 6;
    const auto model = PathTracingModel(scene, layered);
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

TEST(RenderingEquation, TheStratifiedSamplersAreUnbiased) {
    // Rng::kronecker and Rng::sobol (--sampler kronecker, sobol) correlate the samples of one
    // pixel, never their distribution: each value is uniform because of the pixel's random
    // shift or scramble. Pixels have independent ones, so pixel means are independent: the
    // z-test runs over pixels.
    const Ray ray{Vec3(0.1f, -0.2f, 0.0f), glm::normalize(Vec3(0.3f, 0.4f, 1.0f))};
    for (const bool sobol : {false, true})
        for (float rho : {0.5f, 0.8f}) {
            const Scene scene = test::furnace(rho, 1.0f);
            const LightSampler lights(scene);
            for (const Strategies& strategies : kStrategies) {
                const PathOptions options = strategies.options();
                std::vector<double> pixel_means;
                for (uint64_t pixel = 0; pixel < 4000; ++pixel) {
                    double sum = 0.0;
                    for (uint64_t s = 0; s < 8; ++s) {
                        Rng rng = sobol ? Rng::sobol(11, pixel, s) : Rng::kronecker(11, pixel, s);
                        sum += path_trace(scene, lights, ray, rng, options).x;
                    }
                    pixel_means.push_back(sum / 8.0);
                }
                const auto [mean, se] = test::mean_and_error(pixel_means);
                EXPECT_NEAR(mean, 1.0 / (1.0 - rho), test::z_quantile(kSignificance) * se + 1e-5)
                    << "rho " << rho << " with " << strategies.name
                    << (sobol ? ", sobol" : ", kronecker");
            }
        }
}

TEST(RenderingEquation, ClampedBounceLayersStillAddUpToTheImage) {
    // --clamp scales a bright sample down; its bounce layers are scaled by the same factor, so
    // the layers of a clamped render add up to its (biased) image as they do without a clamp.
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_spheres.toml", {16, 16});
    const LightSampler lights(scene);
    PathOptions layered;
    layered.bounce_layers = 3;
    RenderSettings settings;
    settings.progress = false;
    settings.clamp = 0.5f;
    const RenderResult r = render_scene(scene, PathTracingModel(scene, layered), 64, settings);
    ASSERT_GT(r.clamped_samples, 0u);
    for (size_t i = 0; i < r.image.pixels.size(); ++i) {
        float sum = 0.0f;
        for (const Image& layer : r.layers) sum += layer.pixels[i].x;
        EXPECT_NEAR(sum, r.image.pixels[i].x, 1e-4f * r.image.pixels[i].x + 1e-6f) << i;
    }
}
