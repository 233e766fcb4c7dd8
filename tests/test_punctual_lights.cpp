// Spot and directional lights against their closed forms, in every lesson that lights surfaces
// with them (docs/accuracy.md): a directional light of irradiance E gives a diffuse plane tilted
// by theta from it the radiance rho / pi E cos(theta) everywhere; a spot of axis intensity I
// gives the point at distance d, seen from the spot at angle alpha from its axis and lit at
// incidence theta, rho / pi I falloff(alpha) cos(theta) / d^2.
//
// Lessons 1, 3 (light and MIS estimators) and 4 take one light sample per pixel sample from a
// delta light, and a lone plane sends no light to itself, so their pixels are the closed form
// at the pixel centre, to rounding. Lessons 5 and 6 (vertex connection and merging) add light
// tracing, whose points land anywhere in a pixel, and merges: their image means are tested
// against the closed form's mean over the film, within their standard errors.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "01_ray_casting/ray_casting.h"
#include "03_reflection_equation/reflection_equation.h"
#include "04_rendering_equation/rendering_equation.h"
#include "05_bidirectional/bidirectional.h"
#include "06_photon_mapping/photon_mapping.h"
#include "render_statistics.h"
#include "test_util.h"

using namespace lessons;

namespace {

constexpr double kPiD = 3.14159265358979323846;
const Color kRho(0.2f, 0.5f, 0.8f);

// A floor (y = 0, facing up) of albedo kRho, 40 m across, seen from 3 m above, looking down
// and forward: every pixel sees the floor.
Scene floor_scene() {
    Scene scene;
    scene.add_quad(Quad(Vec3(-20, 0, -20), Vec3(0, 0, 40), Vec3(40, 0, 0)),
                   test::add_diffuse(scene, kRho));
    scene.width = 32;
    scene.height = 24;
    scene.camera = Camera(Vec3(0, 3, -2), Vec3(0, 0, 1), Vec3(0, 1, 0), 60.0f, 32.0f / 24.0f);
    return scene;
}

// The floor point a ray meets (y = 0), in double.
glm::dvec3 on_floor(const Ray& ray) {
    const glm::dvec3 o(ray.origin), d(ray.dir);
    return o + (-o.y / d.y) * d;
}

// The spots of these tests. The first: 2 m above the floor, pointing straight down, 30 degrees to
// its edge, fading over the outer half (in 1 - cos) of its cone. The second, listed after it (so
// that its index is not 0): tilted, so that its angle from the axis is not the angle of
// incidence, 20 degrees to its edge, fading over a fifth.
const Vec3 kSpotAt(0.3f, 2.0f, 1.5f);
const Color kSpotI(4.0f, 6.0f, 8.0f);
SpotCone spot_cone() {
    const float cos_outer = static_cast<float>(std::cos(30.0 * kPiD / 180.0));
    return {Vec3(0, -1, 0), cos_outer, cos_outer + 0.5f * (1.0f - cos_outer)};
}
PointLight tilted_spot() {
    const float cos_outer = static_cast<float>(std::cos(20.0 * kPiD / 180.0));
    return {Vec3(-1.0f, 2.5f, 3.0f), Color(3.0f, 2.0f, 5.0f),
            SpotCone{glm::normalize(Vec3(0.5f, -1, -0.3f)), cos_outer,
                     cos_outer + 0.2f * (1.0f - cos_outer)}};
}
std::vector<PointLight> spots() {
    return {{kSpotAt, kSpotI, spot_cone()}, tilted_spot()};
}

// The falloff in double, from its definition (SpotCone::falloff).
double falloff(const SpotCone& cone, double cos_alpha) {
    if (cos_alpha >= cone.cos_inner) return 1.0;
    if (cos_alpha <= cone.cos_outer) return 0.0;
    const double t = (cos_alpha - cone.cos_outer) / (double(cone.cos_inner) - cone.cos_outer);
    return t * t * (3.0 - 2.0 * t);
}

// The spots' closed form at floor point p: the sum of rho / pi I falloff(alpha) cos(theta) / d^2,
// alpha the angle from each spot's axis, theta the angle of incidence.
glm::dvec3 spot_radiance(const glm::dvec3& p) {
    glm::dvec3 sum(0.0);
    for (const PointLight& l : spots()) {
        const glm::dvec3 d = p - glm::dvec3(l.position);
        const double d2 = glm::dot(d, d);
        const double cos_alpha = glm::dot(d, glm::dvec3(l.cone->axis)) / std::sqrt(d2);
        const double cos_theta = -d.y / std::sqrt(d2);
        sum += glm::dvec3(kRho) / kPiD * glm::dvec3(l.intensity) *
               (falloff(*l.cone, cos_alpha) * cos_theta / d2);
    }
    return sum;
}

// The sun of these tests: its light travels down and forward, 60 degrees from the vertical.
const Vec3 kSunTravels = glm::normalize(Vec3(std::sin(1.0471976f), -0.5f, 0.0f));
const Color kSunE(2.0f, 3.0f, 1.0f);
glm::dvec3 sun_radiance() {
    return glm::dvec3(kRho) / kPiD * glm::dvec3(kSunE) * 0.5;  // cos 60 degrees
}

// The models that see a delta light with one light sample: lessons 1, 3 (light, MIS), 4. Lesson
// 1 sums over the lights; the others pick one light per sample, by power.
std::vector<std::pair<std::string, std::function<RenderResult(const Scene&)>>> exact_lessons() {
    auto run = [](const Scene& scene, const Model& model) {
        RenderSettings settings = test::quiet_settings(5, 1);
        settings.jitter = false;  // every sample at the pixel center
        return render_scene(scene, model, 64, settings);
    };
    return {
        {"lesson 1", [=](const Scene& s) { return run(s, RayCastingModel(s, {})); }},
        {"lesson 3 (light)",
         [=](const Scene& s) { return run(s, ReflectionModel(s, {Estimator::Light})); }},
        {"lesson 3 (mis)",
         [=](const Scene& s) { return run(s, ReflectionModel(s, {Estimator::Mis})); }},
        {"lesson 4", [=](const Scene& s) { return run(s, PathTracingModel(s, {})); }},
    };
}

// Every pixel of `r` against the closed form at its centre, to 1e-4 relative: exactly where every
// sample is the same (one light: the sample's variance is 0), and within the pixel's standard
// error where a sample picks one of several lights by power (Sidak over every channel of the
// four lessons).
void expect_closed_form_per_pixel(const std::string& name, const Scene& scene,
                                  const RenderResult& r,
                                  const std::function<glm::dvec3(const glm::dvec3&)>& expected) {
    int mismatches = 0;
    const double z = test::z_quantile(test::sidak(0.01, 4 * 3 * scene.width * scene.height));
    for (int y = 0; y < scene.height; ++y)
        for (int x = 0; x < scene.width; ++x) {
            const Ray ray =
                scene.camera.generate_ray(x + 0.5f, y + 0.5f, scene.width, scene.height);
            const glm::dvec3 want = expected(on_floor(ray));
            const Color got = r.image.at(x, y), var = r.variance.at(x, y);
            for (int c = 0; c < 3; ++c)
                if (std::fabs(got[c] - want[c]) > 1e-4 * want[c] + 1e-6 + z * std::sqrt(var[c]) &&
                    ++mismatches <= 3)
                    ADD_FAILURE() << name << ": pixel " << x << "," << y << " channel " << c << ": "
                                  << got[c] << ", expected " << want[c];
        }
    EXPECT_EQ(mismatches, 0) << name;
}

// The closed form's mean over the film (for jittered renders): 8 x 8 points per pixel.
double film_mean(const Scene& scene, const std::function<glm::dvec3(const glm::dvec3&)>& f) {
    double sum = 0.0;
    const int k = 8;
    for (int y = 0; y < scene.height * k; ++y)
        for (int x = 0; x < scene.width * k; ++x) {
            const Ray ray = scene.camera.generate_ray((x + 0.5f) / k, (y + 0.5f) / k, scene.width,
                                                      scene.height);
            sum += f(on_floor(ray)).x;
        }
    return sum / (double(scene.width) * scene.height * k * k);
}

}  // namespace

TEST(PunctualLights, ASunGivesAPlaneRhoOverPiECosThetaEverywhere) {
    Scene scene = floor_scene();
    scene.add_directional_light({kSunTravels, kSunE});
    scene.commit();
    for (const auto& [name, render] : exact_lessons()) {
        const RenderResult r = render(scene);
        expect_closed_form_per_pixel(name, scene, r,
                                     [](const glm::dvec3&) { return sun_radiance(); });
        for (const Color& v : r.variance.pixels)
            ASSERT_EQ(v, Color(0.0f)) << name << ": one light, every sample the same";
    }
}

TEST(PunctualLights, ASpotGivesRhoOverPiIFalloffCosOverDSquared) {
    Scene scene = floor_scene();
    for (const PointLight& l : spots()) scene.add_point_light(l);
    scene.commit();
    // The image holds the first spot's full cone, its fade and the dark beyond (the checks below
    // say so).
    int full = 0, fade = 0, dark = 0;
    for (int y = 0; y < scene.height; ++y)
        for (int x = 0; x < scene.width; ++x) {
            const Ray ray =
                scene.camera.generate_ray(x + 0.5f, y + 0.5f, scene.width, scene.height);
            const glm::dvec3 d = on_floor(ray) - glm::dvec3(kSpotAt);
            const double c = -d.y / glm::length(d);
            full += c >= spot_cone().cos_inner;
            dark += c <= spot_cone().cos_outer;
            fade += c > spot_cone().cos_outer && c < spot_cone().cos_inner;
        }
    EXPECT_GT(full, 20);
    EXPECT_GT(fade, 20);
    EXPECT_GT(dark, 20);
    for (const auto& [name, render] : exact_lessons()) {
        const RenderResult r = render(scene);
        expect_closed_form_per_pixel(name, scene, r, spot_radiance);
        if (name == "lesson 1") {
            EXPECT_EQ(r.variance.at(16, 12), Color(0.0f)) << "lesson 1 sums the lights";
        }
    }
}

TEST(PunctualLights, LessonsFiveAndSixAgreeWithTheSunsAndTheSpotsClosedFormsWithinTheirError) {
    // Lesson 5 weighs the light sample (s = 1) against light tracing (s = 2, t = 1), which starts
    // on the sun's disk (or in the spot's cone) and splats where it lands; lesson 6's vcm also
    // merges the light subpaths' photons at the floor. The image mean is the closed form's mean
    // over the film, within 4 standard errors (4 tests of two means). The merges blur the light
    // by their radius (0.05 m here): the sun's is uniform, and the spot's blur moves light only
    // across the edge of its cone, where the merges' weight is small beside the joins'.
    for (const bool sun : {true, false}) {
        Scene scene = floor_scene();
        if (sun) {
            scene.add_directional_light({kSunTravels, kSunE});
        } else {
            for (const PointLight& l : spots()) scene.add_point_light(l);
        }
        scene.commit();
        const double expected =
            sun ? sun_radiance().x
                : film_mean(scene, [](const glm::dvec3& p) { return spot_radiance(p); });
        PhotonOptions vcm;
        vcm.radius = 0.05f;
        for (const bool six : {false, true}) {
            const RenderResult r = six ? render_scene(scene, PhotonMappingModel(scene, vcm), 64,
                                                      test::quiet_settings(12, 1))
                                       : render_scene(scene, BidirectionalModel(scene, {}), 64,
                                                      test::quiet_settings(11, 1));
            const auto [mean, var] = test::image_mean(r.image, r.variance);
            const std::string name =
                std::string(six ? "lesson 6, " : "lesson 5, ") + (sun ? "the sun" : "the spot");
            EXPECT_NEAR(mean, expected, 4.0 * std::sqrt(var) + 1e-6 * expected)
                << name << ", se " << std::sqrt(var);
        }
    }
}
