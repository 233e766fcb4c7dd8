// Lesson 3 against closed forms: every estimator converges to rho / pi * E, with E from
// Lambert's polygon formula, the sphere's configuration factor, or the uniform sky; and the
// five estimators agree with each other on the Cornell box.
#include <gtest/gtest.h>

#include "03_reflection_equation/reflection_equation.h"
#include "driver/app.h"
#include "io/scene_file.h"
#include "statistics.h"
#include "test_util.h"

using namespace lessons;

namespace {

const Estimator kEstimators[] = {Estimator::Uniform, Estimator::Cosine, Estimator::Brdf,
                                 Estimator::Light, Estimator::Mis};
// z-tests in this file: 3 scenes x 5 points x 5 estimators, plus 4 x 3 image comparisons.
const double kSignificance = test::sidak(0.01, 100);

// The lesson's estimate of the radiance seen along `ray`: mean and standard error of n samples.
test::MeanAndError estimate(const Scene& scene, const Ray& ray, Estimator e, int n, uint64_t seed) {
    const LightSampler lights(scene);
    ReflectionOptions options;
    options.estimator = e;
    std::vector<double> values;
    for (int i = 0; i < n; ++i) {
        Rng rng(seed, 0, static_cast<uint64_t>(i));
        values.push_back(reflection_equation(scene, lights, ray, rng, options).x);
    }
    return test::mean_and_error(values);
}

uint32_t add_emitter(Scene& scene, float radiance) {
    Material m;
    m.name = "lamp";
    m.emission = Color(radiance);
    return scene.add_material(m);
}

// A camera ray from above that lands on plane point (x, 0, z).
Ray ray_to(float x, float z) {
    const Vec3 target(x, 0.0f, z), origin(x + 0.3f, 3.0f, z - 4.0f);
    return Ray{origin, glm::normalize(target - origin)};
}

}  // namespace

TEST(ReflectionEquation, EveryEstimatorMatchesLambertsPolygonFormula) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/quad_light_plane.toml", {8, 8});
    const double rho = 0.5, L = 5.0;
    const std::vector<glm::dvec3> lamp = {{-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, {-1, 2, 1}};
    const std::pair<float, float> points[] = {
        {0, 0}, {0.7f, -0.4f}, {1.5f, 1.5f}, {-3, 2}, {4, -4}};
    for (const auto& [x, z] : points) {
        const double expected =
            rho / kPi * test::lambert_polygon_irradiance(lamp, {x, 0, z}, {0, 1, 0}, L);
        for (Estimator e : kEstimators) {
            const auto [mean, se] = estimate(scene, ray_to(x, z), e, 40000, 1);
            EXPECT_NEAR(mean, expected, test::z_quantile(kSignificance) * se + 1e-6)
                << estimator_name(e) << " at (" << x << ", " << z << "), expected " << expected
                << ", standard error " << se;
        }
    }
}

TEST(ReflectionEquation, EveryEstimatorMatchesTheSphereLightConfigurationFactor) {
    // A sphere light of radius R whose center is d above the point: E = pi L (R / d)^2.
    Scene scene;
    scene.add_quad(Quad(Vec3(-50, 0, -50), Vec3(0, 0, 100), Vec3(100, 0, 0)),
                   test::add_diffuse(scene, Color(0.5f)));
    const float R = 0.5f, d = 2.0f, L = 4.0f;
    scene.add_sphere({Vec3(0, d, 0), R}, add_emitter(scene, L));
    scene.commit();
    const double expected = 0.5 / kPi * kPi * L * (R / d) * (R / d);
    for (Estimator e : kEstimators) {
        const auto [mean, se] = estimate(scene, ray_to(0, 0), e, 40000, 2);
        EXPECT_NEAR(mean, expected, test::z_quantile(kSignificance) * se + 1e-6)
            << estimator_name(e) << ", standard error " << se;
    }
}

TEST(ReflectionEquation, EveryEstimatorSeesTheUniformSky) {
    // An unoccluded Lambertian plane under a sky of radiance L: E = pi L, so L_o = rho L.
    Scene scene;
    scene.add_quad(Quad(Vec3(-50, 0, -50), Vec3(0, 0, 100), Vec3(100, 0, 0)),
                   test::add_diffuse(scene, Color(0.6f)));
    scene.background = Color(2.0f);
    scene.commit();
    for (Estimator e : kEstimators) {
        const auto [mean, se] = estimate(scene, ray_to(0.5f, 0.5f), e, 20000, 3);
        EXPECT_NEAR(mean, 0.6 * 2.0, test::z_quantile(kSignificance) * se + 1e-5)
            << estimator_name(e);
    }
}

TEST(ReflectionEquation, TheFiveEstimatorsAgreeOnTheCornellBox) {
    // Each estimator renders the same small image; the image means must agree within their
    // standard errors (from the per-pixel variance of the mean).
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {24, 24});
    const LightSampler lights(scene);
    std::vector<std::pair<double, double>> results;  // mean, variance of the mean
    for (Estimator e : kEstimators) {
        ReflectionOptions options;
        options.estimator = e;
        RenderSettings settings;
        settings.progress = false;
        settings.seed = 10 + static_cast<int>(e);
        const RenderResult r = render_scene(scene, ReflectionModel(scene, options), 256, settings);
        double mean = 0.0, variance = 0.0;
        const double n = static_cast<double>(r.image.pixels.size());
        for (size_t i = 0; i < r.image.pixels.size(); ++i) {
            mean += luminance(r.image.pixels[i]) / n;
            const Color& v = r.variance.pixels[i];
            // Luminance is linear: its variance is sum of w_c^2 var_c (channels treated as
            // independent, a conservative simplification for positively correlated channels).
            variance +=
                (0.2126 * 0.2126 * v.x + 0.7152 * 0.7152 * v.y + 0.0722 * 0.0722 * v.z) / (n * n);
        }
        EXPECT_EQ(r.nan_samples + r.inf_samples, 0u) << estimator_name(e);
        results.emplace_back(mean, variance);
    }
    const auto [mis_mean, mis_var] = results.back();
    EXPECT_GT(mis_mean, 0.01);
    for (size_t i = 0; i + 1 < results.size(); ++i) {
        const double z =
            std::fabs(results[i].first - mis_mean) / std::sqrt(results[i].second + mis_var);
        EXPECT_LT(z, test::z_quantile(kSignificance)) << estimator_name(kEstimators[i]) << " mean "
                                                      << results[i].first << " vs mis " << mis_mean;
    }
}

TEST(ReflectionEquation, PointLightsNeedLightSamplingAndTheNotesSaySo) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/whitted_1979.toml", {16, 12});
    const LightSampler lights(scene);
    ReflectionOptions brdf;
    brdf.estimator = Estimator::Brdf;
    std::string notes;
    for (const std::string& n : ReflectionModel(scene, brdf).notes) notes += n + "\n";
    EXPECT_NE(notes.find("point and directional lights are invisible to the brdf estimator"),
              std::string::npos)
        << notes;
    // With light sampling, a point on the floor lit by the point light gets I cos / d^2 rho / pi
    // (plus the sky): strictly more than the sky alone, which is all the BRDF estimator sees.
    const Ray down{Vec3(2.0f, 1.0f, -3.0f), Vec3(0, -1, 0)};
    const auto with_light = estimate(scene, down, Estimator::Mis, 4000, 4);
    const auto without = estimate(scene, down, Estimator::Brdf, 4000, 4);
    EXPECT_GT(with_light.mean,
              without.mean + 10 * (with_light.standard_error + without.standard_error));
}
