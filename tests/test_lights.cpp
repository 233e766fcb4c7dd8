// Light sampling: each light's directions against the density that MIS will use (chi-square),
// irradiance against closed forms, one-sidedness, and choice by power.
#include <gtest/gtest.h>

#include "lights/lights.h"
#include "sampling/sampling.h"
#include "scene/environment.h"
#include "statistics.h"
#include "test_util.h"

using namespace lessons;

namespace {

const double kSignificance = test::sidak(0.01, 64);

uint32_t add_emitter(Scene& scene, const Color& radiance, bool two_sided = false) {
    Material m;
    m.name = "lamp";
    m.emission = radiance;
    m.two_sided = two_sided;
    return scene.add_material(m);
}

// Chi-square test of the light sampler's directions from point p against sampler.pdf(), the
// density found by tracing each direction to the light (or to the environment).
test::Chi2Result check_light_directions(const Scene& scene, const Vec3& p, uint64_t seed) {
    const LightSampler sampler(scene);
    Rng rng(seed);
    const SurfacePoint at{p, Vec3(0.0f), Vec3(0, 0, 1)};
    return test::chi2_test_directions(
        [&](Vec3& w) {
            const auto s = sampler.sample(at, rng.uniform(), {rng.uniform(), rng.uniform()});
            if (!s) return false;
            w = s->wi;
            return true;
        },
        [&](const Vec3& w) -> double {
            const Ray ray{p, w};
            const std::optional<Hit> hit = scene.intersect(ray);
            if (!hit) return sampler.environment_pdf(w);
            return sampler.pdf(p, scene.interaction(ray, *hit));
        },
        1000000, kSignificance, 40, 80);
}

// Irradiance at a point facing n, estimated by light sampling: the mean of L cos / pdf.
test::MeanAndError irradiance_by_light_sampling(const Scene& scene, const Vec3& p, const Vec3& n,
                                                int samples, uint64_t seed) {
    const LightSampler sampler(scene);
    Rng rng(seed);
    const SurfacePoint at{p, Vec3(0.0f), n};
    std::vector<double> values;
    for (int i = 0; i < samples; ++i) {
        const auto s = sampler.sample(at, rng.uniform(), {rng.uniform(), rng.uniform()});
        double v = 0.0;
        if (s && !scene.occluded(s->shadow_ray, s->emitter))
            v = luminance(s->radiance) * std::max(0.0f, glm::dot(n, s->wi)) / s->pdf;
        values.push_back(v);
    }
    return test::mean_and_error(values);
}

}  // namespace

TEST(Lights, QuadLightDirectionsMatchTheirDensity) {
    Scene scene;
    scene.add_quad(Quad(Vec3(-1, 1, -1), Vec3(2, 0, 0), Vec3(0, 0.3f, 2)),
                   add_emitter(scene, Color(5)));
    scene.commit();
    for (const Vec3& p : {Vec3(0.2f, 0, 0.1f), Vec3(-3, -2, 1)}) {
        const auto r = check_light_directions(scene, p, 1);
        EXPECT_TRUE(r.passed) << r.report;
        EXPECT_NEAR(r.pdf_integral, 1.0, 5e-3) << r.report;
    }
}

TEST(Lights, TriangleLightDirectionsMatchTheirDensity) {
    Scene scene;
    const uint32_t m = add_emitter(scene, Color(5), true);
    scene.add_mesh({Vec3(-1, 1, -1), Vec3(1.5f, 1.2f, -0.5f), Vec3(0, 0.8f, 1.5f)}, {}, {},
                   {{{0, 1, 2}, m, false}});
    scene.commit();
    const auto r = check_light_directions(scene, Vec3(0, 0, 0), 2);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 5e-3) << r.report;
}

TEST(Lights, SphereLightDirectionsMatchTheirDensityNearAndFar) {
    for (float distance : {1.3f, 4.0f, 40.0f}) {
        Scene scene;
        scene.add_sphere({Vec3(0, distance, 0), 1.0f}, add_emitter(scene, Color(2)));
        scene.commit();
        const auto r = check_light_directions(scene, Vec3(0), 3);
        EXPECT_TRUE(r.passed) << "distance " << distance << ": " << r.report;
        EXPECT_NEAR(r.pdf_integral, 1.0, 5e-3) << distance;
    }
}

TEST(Lights, EnvironmentDirectionsMatchTheirDensity) {
    Scene scene;
    scene.background = Color(0.5f);
    scene.commit();
    const auto r = check_light_directions(scene, Vec3(0), 4);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3);
}

TEST(Lights, QuadLightIrradianceMatchesLambertsPolygonFormula) {
    Scene scene;
    const float L = 3.0f;
    const Vec3 corner(-0.5f, 2, -0.3f), eu(1.2f, 0, 0.2f), ev(0.1f, -0.2f, 0.9f);
    scene.add_quad(Quad(corner, eu, ev), add_emitter(scene, Color(L)));  // faces down
    scene.commit();
    ASSERT_LT(scene.quads()[0].normal.y, 0.0f);
    for (const Vec3& n : {Vec3(0, 1, 0), glm::normalize(Vec3(0.5f, 1, 0.2f))}) {
        const glm::dvec3 c(corner), u(eu), v(ev);
        const double expected = test::lambert_polygon_irradiance({c, c + u, c + u + v, c + v},
                                                                 glm::dvec3(0.0), glm::dvec3(n), L);
        const auto [mean, se] = irradiance_by_light_sampling(scene, Vec3(0), n, 200000, 5);
        EXPECT_NEAR(mean, expected, test::z_quantile(kSignificance) * se)
            << "expected " << expected;
    }
}

TEST(Lights, SphereLightIrradianceIsPiLTimesRSquaredOverDSquared) {
    // Configuration factor of a sphere above the horizon (Howell's catalogue): F = (R / d)^2,
    // so E = pi L (R / d)^2 on a surface facing it.
    for (float d : {1.5f, 3.0f, 30.0f}) {
        Scene scene;
        const float R = 1.0f, L = 2.0f;
        scene.add_sphere({Vec3(0, d, 0), R}, add_emitter(scene, Color(L)));
        scene.commit();
        const auto [mean, se] =
            irradiance_by_light_sampling(scene, Vec3(0), Vec3(0, 1, 0), 200000, 6);
        const double expected = kPi * L * (R / d) * (R / d);
        EXPECT_NEAR(mean, expected, test::z_quantile(kSignificance) * se + 1e-6 * expected) << d;
    }
}

TEST(Lights, EnvironmentAndPointLightIrradiance) {
    Scene scene;
    scene.background = Color(0.7f);
    scene.add_point_light({Vec3(1, 2, 0), Color(10.0f)});
    scene.commit();
    // E = pi L_env (the unoccluded sky) + I cos / d^2 (the point light).
    const double expected = kPi * 0.7 + 10.0 * (2.0 / std::sqrt(5.0)) / 5.0;
    const auto [mean, se] = irradiance_by_light_sampling(scene, Vec3(0), Vec3(0, 1, 0), 400000, 7);
    EXPECT_NEAR(mean, expected, test::z_quantile(kSignificance) * se);
}

TEST(Lights, OneSidedLightsAreDarkBehindAndTwoSidedAreNot) {
    for (bool two_sided : {false, true}) {
        Scene scene;
        // Faces +y (cross((0,0,1),(1,0,0)) = +y); the shading point is below it.
        scene.add_quad(Quad(Vec3(-1, 1, -1), Vec3(0, 0, 2), Vec3(2, 0, 0)),
                       add_emitter(scene, Color(1.0f), two_sided));
        scene.commit();
        const LightSampler sampler(scene);
        Rng rng(8);
        int produced = 0;
        for (int i = 0; i < 1000; ++i)
            produced += sampler
                            .sample({Vec3(0), Vec3(0.0f), Vec3(0, 1, 0)}, rng.uniform(),
                                    {rng.uniform(), rng.uniform()})
                            .has_value();
        EXPECT_EQ(produced, two_sided ? 1000 : 0);
    }
}

TEST(Lights, TheSceneListsItsLightsPointsFirstThenAreasThenTheEnvironment) {
    // Scene::lights(), the one list the light sampler, lesson 1, the studio and the export
    // read: every point light, every emissive primitive, and the sky only when it is not black
    // (set after commit() too: the list is made when asked).
    Scene scene;
    const uint32_t lamp = add_emitter(scene, Color(1.0f));
    scene.add_quad(Quad(Vec3(0, 2, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)), lamp);
    scene.add_sphere({Vec3(3, 0, 0), 0.5f}, lamp);
    scene.add_point_light({Vec3(0, 1, 0), Color(1.0f)});
    scene.add_point_light({Vec3(0, 3, 0), Color(0.0f)});  // black: listed, never chosen
    scene.commit();
    auto kinds = [&] {
        std::string s;
        for (const LightRef& l : scene.lights()) {
            s += l.kind == LightKind::Point ? 'P' : l.kind == LightKind::Area ? 'A' : 'E';
            s += std::to_string(l.index) + ' ';
        }
        return s;
    };
    EXPECT_EQ(kinds(), "P0 P1 A0 A1 ");
    EXPECT_EQ(LightSampler(scene).size(), 3u);
    scene.background = Color(0.2f);
    EXPECT_EQ(kinds(), "P0 P1 A0 A1 E0 ");
    EXPECT_EQ(LightSampler(scene).size(), 4u);
}

TEST(Lights, LightsAreChosenInProportionToTheirPower) {
    Scene scene;
    scene.add_point_light({Vec3(0, 1, 0), Color(1.0f)});
    scene.add_point_light({Vec3(0, 2, 0), Color(3.0f)});
    scene.commit();
    const LightSampler sampler(scene);
    Rng rng(9);
    const int n = 100000;
    int second = 0;
    for (int i = 0; i < n; ++i) {
        const auto s =
            sampler.sample({Vec3(0), Vec3(0.0f), Vec3(0, 1, 0)}, rng.uniform(), {0.5f, 0.5f});
        ASSERT_TRUE(s);
        EXPECT_TRUE(s->is_delta);
        second += s->wi.y > 0.0f && s->radiance.x == 3.0f / 4.0f;
        EXPECT_FLOAT_EQ(s->pdf, s->radiance.x == 3.0f / 4.0f ? 0.75f : 0.25f);
    }
    EXPECT_NEAR(second, 0.75 * n, 5 * std::sqrt(n * 0.75 * 0.25));
}

TEST(Lights, EmissionSamplesCarryThePowerOfTheLightsAndMatchTheirDensities) {
    // Light subpaths start with sample_emission(): L_e cos / (p_A p_dir) averages to the power the
    // area lights emit, pi L A per emitting side, plus 4 pi I for the point light (I / (p p_dir),
    // no cosine), and emission_pdf() / point_emission_pdf() give each sample's own densities
    // back (lesson 5's weights rely on it).
    Scene scene;
    scene.add_quad(Quad(Vec3(-1, 1, -1), Vec3(2, 0, 0), Vec3(0, 0, 2)),
                   add_emitter(scene, Color(2.0f), true));  // area 4, both sides
    scene.add_sphere({Vec3(3, 0, 0), 0.5f}, add_emitter(scene, Color(1.0f)));
    scene.add_mesh({Vec3(0, -2, 0), Vec3(1, -2, 0), Vec3(0, -2, 1)}, {}, {},
                   {{{0, 1, 2}, add_emitter(scene, Color(3.0f)), false}});  // area 1/2
    scene.add_point_light({Vec3(0, 5, 0), Color(10.0f)});
    scene.commit();
    const LightSampler sampler(scene);
    const double expected = kPi * (2.0 * 4.0 * 2.0 + 1.0 * kPi + 3.0 * 0.5) + 4.0 * kPi * 10.0;
    Rng rng(21);
    std::vector<double> power;
    int back_of_quad = 0, quad = 0, point = 0;
    for (int i = 0; i < 200000; ++i) {
        const auto e = sampler.sample_emission(rng.uniform(), {rng.uniform(), rng.uniform()},
                                               {rng.uniform(), rng.uniform()});
        ASSERT_TRUE(e);  // no environment here: every light starts a subpath
        if (e->is_delta()) {
            ++point;
            EXPECT_EQ(e->point, Vec3(0, 5, 0));
            EXPECT_NEAR(glm::length(e->ray.dir), 1.0f, 1e-5f);
            power.push_back(luminance(e->radiance) / (e->pdf_area * e->pdf_dir));
            const LightSampler::EmissionPdf pdf = sampler.point_emission_pdf(0, e->ray.dir);
            EXPECT_FLOAT_EQ(pdf.area, e->pdf_area);
            EXPECT_FLOAT_EQ(pdf.dir, e->pdf_dir);
            continue;
        }
        const float cos_q = glm::dot(e->normal, e->ray.dir);
        ASSERT_GT(cos_q, 0.0f);  // leaves on the side it names
        power.push_back(luminance(e->radiance) * cos_q / (e->pdf_area * e->pdf_dir));
        const PrimRef prim = *e->emitter;
        const LightSampler::EmissionPdf pdf = sampler.emission_pdf(
            prim, prim.kind() == ShapeKind::Quad ? Vec3(0, -1, 0) : e->normal, e->ray.dir);
        EXPECT_NEAR(pdf.area, e->pdf_area, 1e-5f * e->pdf_area);
        EXPECT_NEAR(pdf.dir, e->pdf_dir, 1e-5f * e->pdf_dir);
        if (prim.kind() == ShapeKind::Quad) {
            ++quad;
            back_of_quad += e->normal.y > 0.0f;
            EXPECT_NEAR(e->point.y, 1.0f, 1e-6f);
        }
    }
    EXPECT_GT(point, 0);
    // Lights chosen by power make every sample carry the same power (a standard error of 0, up
    // to rounding).
    const test::MeanAndError m = test::mean_and_error(power);
    EXPECT_NEAR(m.mean, expected,
                test::z_quantile(kSignificance) * m.standard_error + 1e-6 * expected)
        << "standard error " << m.standard_error;
    EXPECT_NEAR(back_of_quad, 0.5 * quad, 5 * std::sqrt(0.25 * quad));
}

TEST(Lights, AreaAndSolidAngleDensitiesConvertBothWays) {
    // p_omega = p_A d^2 / |cos| and back; zero where the patch is seen edge-on or at distance 0.
    for (float cos_theta : {1.0f, -0.5f, 1e-3f})
        for (float d2 : {1e-12f, 1.0f, 1e8f}) {
            const float p_omega = area_to_solid_angle_pdf(0.25f, d2, cos_theta);
            EXPECT_FLOAT_EQ(p_omega, 0.25f * d2 / std::fabs(cos_theta));
            EXPECT_FLOAT_EQ(solid_angle_to_area_pdf(p_omega, d2, cos_theta), 0.25f);
        }
    EXPECT_EQ(area_to_solid_angle_pdf(1.0f, 1.0f, 0.0f), 0.0f);
    EXPECT_EQ(solid_angle_to_area_pdf(1.0f, 0.0f, 1.0f), 0.0f);
}

TEST(Lights, SamplesAreFiniteAtTheEndsOfTheUnitSquare) {
    Scene scene;
    scene.add_sphere({Vec3(0, 1e4f, 0), 1.0f}, add_emitter(scene, Color(1e6f)));  // tiny, far
    scene.add_quad(Quad(Vec3(-1, 1, -1), Vec3(2, 0, 0), Vec3(0, 0, 2)),
                   add_emitter(scene, Color(1), true));
    scene.background = Color(0.1f);
    scene.commit();
    const LightSampler sampler(scene);
    const float ends[] = {0.0f, 0.5f, 0x1.fffffep-1f};
    for (float c : ends)
        for (float a : ends)
            for (float b : ends) {
                const auto s = sampler.sample({Vec3(0), Vec3(0.0f), Vec3(0, 1, 0)}, c, {a, b});
                if (!s) continue;
                EXPECT_TRUE(is_finite(s->radiance) && is_finite(s->wi) && std::isfinite(s->pdf));
                EXPECT_GT(s->pdf, 0.0f);
            }
}

TEST(Lights, RectangleLightsAreSampledBySolidAngleNearTheirPlane) {
    // A two-sided 2 x 2 lamp at y = 1 and a point 0.01 below its plane, 0.05 beside its edge:
    // the ceiling beside the lamp of the Cornell box in Ray Tracing: The Next Week. Sampled by
    // area, the estimate L cos(theta) cos(theta_l) A / d^2 of the irradiance is unbounded near the
    // edge; sampled by solid angle it is L cos(theta) Omega, bounded. Both agree with Lambert's
    // formula; the standard error differs by an order of magnitude.
    Scene scene;
    const float L = 2.0f;
    const Vec3 corner(-1, 1, -1), eu(2, 0, 0), ev(0, 0, 2);
    scene.add_quad(Quad(corner, eu, ev), add_emitter(scene, Color(L), true));
    scene.commit();
    ASSERT_TRUE(scene.area_lights()[0].rectangle);
    const Vec3 p(1.05f, 0.99f, 0.3f), n(0, 1, 0);
    const glm::dvec3 c(corner), u(eu), v(ev);
    const double expected = test::lambert_polygon_irradiance({c, c + u, c + u + v, c + v},
                                                             glm::dvec3(p), glm::dvec3(n), L);
    const auto [mean, se] = irradiance_by_light_sampling(scene, p, n, 100000, 6);
    EXPECT_NEAR(mean, expected, test::z_quantile(kSignificance) * se) << "expected " << expected;

    // The same estimate with points uniform by area (p_A = 1 / A, converted to solid angle).
    Rng rng(6);
    std::vector<double> by_area;
    for (int i = 0; i < 100000; ++i) {
        const Vec3 q = corner + rng.uniform() * eu + rng.uniform() * ev;
        const Vec3 d = q - p;
        const float d2 = glm::dot(d, d);
        const Vec3 wi = d / std::sqrt(d2);
        const float pdf = area_to_solid_angle_pdf(1.0f / 4.0f, d2, wi.y);
        by_area.push_back(pdf > 0.0f ? L * std::max(0.0f, wi.y) / pdf : 0.0);
    }
    const auto [mean_area, se_area] = test::mean_and_error(by_area);
    EXPECT_NEAR(mean_area, expected, test::z_quantile(kSignificance) * se_area);
    EXPECT_GT(se_area, 10.0 * se) << "by area " << se_area << ", by solid angle " << se;
    RecordProperty("standard_error_ratio", std::to_string(se_area / se));

    // The directions match the density MIS uses, from beside the lamp and from above it.
    for (const Vec3& from : {p, Vec3(0.2f, 1.5f, -0.4f)}) {
        const auto r = check_light_directions(scene, from, 7);
        EXPECT_TRUE(r.passed) << r.report;
        EXPECT_NEAR(r.pdf_integral, 1.0, 5e-3) << r.report;
    }
}

namespace {
std::shared_ptr<const EnvironmentMap> test_map(float rotate) {
    return test::structured_environment_map(rotate, 3, 50.0f, 1.5f);
}
}  // namespace

TEST(Lights, EveryLightOfPositivePowerCanBeChosen) {
    // Beside a light 1e8 times more powerful, listed before it (point lights come first), a lamp
    // keeps a positive choice probability (sampling/discrete.h), for the emission sampler and the
    // light sampler alike; so does a quad beside one 1e8 times brighter; and the choices add up
    // to 1 exactly.
    for (const bool point_first : {true, false}) {
        Scene scene;
        Material faint, bright;
        faint.name = "faint";
        faint.emission = Color(1.0f);
        bright.name = "bright";
        bright.emission = Color(1e8f);
        const uint32_t f = scene.add_material(faint), b = scene.add_material(bright);
        scene.add_quad(Quad(Vec3(-0.5f, 2, -0.5f), Vec3(1, 0, 0), Vec3(0, 0, 1)), f);  // down
        if (point_first)
            scene.add_point_light({Vec3(0, -5, 0), Color(1e8f / (4.0f * kPi) * kPi)});
        else
            scene.add_quad(Quad(Vec3(3, 2, -0.5f), Vec3(0, 0, 1), Vec3(1, 0, 0)), b);  // up
        scene.commit();
        const LightSampler sampler(scene);
        double total = 0.0;
        for (const AreaLight& light : scene.area_lights()) {
            const auto pdf = sampler.emission_pdf(light.prim, light.normal, light.normal);
            EXPECT_GT(pdf.area, 0.0f) << light.material;
            total += pdf.area * light.area;
            // The light sample's density for a point of it, seen from 1 m in front.
            const Vec3 q = light.center;
            EXPECT_GT(sampler.pdf(q + light.normal, light.prim, q, light.normal), 0.0f)
                << light.material;
        }
        for (uint32_t i = 0; i < scene.point_lights().size(); ++i)
            total += sampler.point_emission_pdf(i, Vec3(0, 0, 1)).area;
        EXPECT_EQ(total, 1.0);  // the choices add up to 1 exactly (multiples of 2^-24)
    }
}

TEST(Lights, ASunOfABillionTimesTheRestLeavesEveryTexelADensity) {
    // Every texel of positive radiance keeps a positive density however bright a sun beside it
    // (sampling/discrete.h), and the texels' probabilities, read back from the density, add up
    // to 1: the sun in the top row (so that every other row comes after it in the row table),
    // and in a middle row.
    for (const int sun_row : {0, 4}) {
        const int w = 16, h = 8;
        std::vector<Color> texels(w * h, Color(1.0f));
        texels[sun_row * w + 5] = Color(1e9f);
        const EnvironmentMap map(w, h, texels, 0.0f, 1.0f);
        double integral = 0.0;  // the density is constant over each texel's patch
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const double theta = kPi * (j + 0.5) / h, phi = 2.0 * kPi * (i + 0.5) / w;
                const Vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta),
                             std::sin(theta) * std::sin(phi));
                const double p = map.pdf(d);
                EXPECT_GT(p, 0.0) << "texel " << i << ", " << j;
                const double solid_angle =
                    2.0 * kPi / w * (std::cos(kPi * j / h) - std::cos(kPi * (j + 1) / h));
                // p = P(texel) W H / (2 pi^2 sin(theta)) at the direction's theta: P(texel) back
                // from the density at the texel's centre.
                integral += p * solid_angle * std::sin(theta) /
                            ((std::cos(kPi * j / h) - std::cos(kPi * (j + 1) / h)) * h / kPi);
            }
        EXPECT_NEAR(integral, 1.0, 1e-5) << "sun in row " << sun_row;
    }
}

TEST(Lights, EnvironmentMapDirectionsMatchTheirDensity) {
    Scene scene;
    scene.environment_map = test_map(30.0f);
    scene.commit();
    const auto r = check_light_directions(scene, Vec3(0), 5);
    EXPECT_TRUE(r.passed) << r.report;
    // The density integrates to 1 over the sphere (numerically, over the test's cells).
    EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3);
}

TEST(Lights, EnvironmentMapDensityIntegratesToOne) {
    // Monte Carlo over uniform directions: E[pdf(w) / (1 / 4 pi)] = 1.
    const auto map = test_map(-70.0f);
    Rng rng(11);
    double sum = 0.0, sum2 = 0.0;
    const int n = 400000;
    for (int k = 0; k < n; ++k) {
        const double x =
            map->pdf(sample_uniform_sphere({rng.uniform(), rng.uniform()})) * 4.0 * kPi;
        sum += x;
        sum2 += x * x;
    }
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / (n - 1));
    EXPECT_NEAR(mean, 1.0, test::z_quantile(kSignificance) * se);
    // And every sample's density is the density of its direction.
    for (int k = 0; k < 1000; ++k) {
        const auto s = map->sample({rng.uniform(), rng.uniform()});
        ASSERT_TRUE(s);
        EXPECT_NEAR(s->pdf, map->pdf(s->dir), 1e-4f * s->pdf);
        EXPECT_EQ(s->radiance, map->radiance(s->dir));
    }
}

// One bright texel is a small sun: the irradiance it gives a surface is its radiance times the
// integral of cos(theta) over its patch, (2 pi / W) (sin^2 theta_1 - sin^2 theta_0) / 2 for a
// surface facing the zenith, exactly (the radiance is constant over the patch).
TEST(Lights, OneBrightTexelIsASmallSun) {
    const int w = 16, h = 8, row = 2, column = 5;
    std::vector<Color> texels(w * h, Color(0.0f));
    texels[row * w + column] = Color(100.0f);
    Scene scene;
    scene.environment_map = std::make_shared<const EnvironmentMap>(w, h, texels, 0.0f, 1.0f);
    scene.commit();
    const double t0 = kPi * row / h, t1 = kPi * (row + 1) / h;
    const double expected =
        100.0 * (2.0 * kPi / w) * 0.5 * (std::pow(std::sin(t1), 2) - std::pow(std::sin(t0), 2));
    const auto [mean, se] = irradiance_by_light_sampling(scene, Vec3(0), Vec3(0, 1, 0), 200000, 3);
    EXPECT_NEAR(mean, expected, test::z_quantile(kSignificance) * se + 1e-6 * expected);
    // It lights from its own direction: phi of column 5.5 / 16 of the way round, from +x to +z.
    const auto s = scene.environment_map->sample({0.5f, 0.5f});
    ASSERT_TRUE(s);
    const double phi = std::atan2(s->dir.z, s->dir.x);
    EXPECT_NEAR(phi, 2.0 * kPi * 5.5 / 16.0, 2.0 * kPi / 16.0);
}

TEST(Lights, EnvironmentMapsRefuseBadTexelsAndDarkness) {
    EXPECT_THROW(EnvironmentMap(2, 1, {Color(NAN), Color(1.0f)}, 0.0f, 1.0f),
                 std::invalid_argument);
    EXPECT_THROW(EnvironmentMap(2, 1, {Color(-1.0f), Color(1.0f)}, 0.0f, 1.0f),
                 std::invalid_argument);
    EXPECT_THROW(EnvironmentMap(2, 1, {Color(0.0f), Color(0.0f)}, 0.0f, 1.0f),
                 std::invalid_argument);
}

TEST(Lights, SpotsAndSunsCarryTheirPowerAndMatchTheirDensities) {
    // A spot's light subpaths leave uniformly within its cone: I falloff / (p_choice p_dir)
    // averages to its power, I times the integral of its falloff over the sphere, 2 pi ((1 -
    // cos_inner) + (cos_inner - cos_outer) / 2); none leaves beyond the cone. A directional
    // light's start on a disk of radius R facing it (p per m^2 across the beam): E / (p_choice
    // p_disk) averages to E pi R^2, and every ray that meets the scene's bounding sphere starts
    // outside it. The light sample gives I falloff / d^2 and E, with the choice probability.
    Scene scene;
    scene.add_quad(Quad(Vec3(-2, 0, -2), Vec3(0, 0, 4), Vec3(4, 0, 0)),
                   test::add_diffuse(scene, Color(0.5f)));
    const float cos_outer = std::cos(25.0f * kPi / 180.0f);
    const SpotCone cone{glm::normalize(Vec3(0.2f, -1, 0)), cos_outer,
                        cos_outer + 0.4f * (1.0f - cos_outer)};
    scene.add_point_light({Vec3(0, 2, 0), Color(5.0f), cone});
    const Vec3 sun = glm::normalize(Vec3(1, -2, 0.5f));
    scene.add_directional_light({sun, Color(0.8f)});
    scene.commit();
    const LightSampler sampler(scene);
    ASSERT_TRUE(sampler.has_delta_lights());
    const double spot_power = 5.0 * 2.0 * kPi * ((1.0 - cone.cos_inner) +
                                                  0.5 * (double(cone.cos_inner) - cone.cos_outer));
    const double r = sampler.beam_radius();
    const Bounds3 bounds = scene.bounds();
    const Vec3 center = 0.5f * (bounds.min + bounds.max);
    EXPECT_NEAR(r, 0.5 * glm::length(bounds.extent()), 1e-5);
    const double sun_power = 0.8 * kPi * r * r;
    Rng rng(23);
    std::vector<double> power;
    int spots = 0, suns = 0;
    for (int i = 0; i < 200000; ++i) {
        const auto e = sampler.sample_emission(rng.uniform(), {rng.uniform(), rng.uniform()},
                                               {rng.uniform(), rng.uniform()});
        if (!e) {  // only the spot's zero-falloff rim can refuse
            power.push_back(0.0);
            continue;
        }
        ASSERT_TRUE(e->is_delta());
        power.push_back(luminance(e->radiance) / (e->pdf_area * e->pdf_dir));
        if (e->directional) {
            ++suns;
            EXPECT_EQ(e->ray.dir, sun);
            const LightSampler::EmissionPdf pdf = sampler.directional_emission_pdf(0);
            EXPECT_FLOAT_EQ(pdf.area, e->pdf_area);
            EXPECT_FLOAT_EQ(pdf.dir, e->pdf_dir);
            // The start lies on the disk's plane, outside the bounding sphere, and within R of
            // the line through the centre.
            const Vec3 off = e->point - center;
            EXPECT_NEAR(glm::dot(off, sun), -1.001 * r, 1e-4 * r);
            EXPECT_LE(glm::length(off - glm::dot(off, sun) * sun), r * (1.0f + 1e-5f));
        } else {
            ++spots;
            EXPECT_GT(glm::dot(e->ray.dir, cone.axis), cone.cos_outer - 1e-6f);
            const LightSampler::EmissionPdf pdf = sampler.point_emission_pdf(0, e->ray.dir);
            EXPECT_FLOAT_EQ(pdf.area, e->pdf_area);
            EXPECT_FLOAT_EQ(pdf.dir, e->pdf_dir);
        }
    }
    EXPECT_GT(spots, 1000);
    EXPECT_GT(suns, 1000);
    const test::MeanAndError m = test::mean_and_error(power);
    const double expected = spot_power + sun_power;
    EXPECT_NEAR(m.mean, expected,
                test::z_quantile(kSignificance) * m.standard_error + 1e-5 * expected)
        << "standard error " << m.standard_error;
    // Beyond the cone, no density; the choices add up to 1.
    EXPECT_EQ(sampler.point_emission_pdf(0, Vec3(0, 1, 0)).dir, 0.0f);
    EXPECT_NEAR(sampler.point_emission_pdf(0, cone.axis).area +
                    sampler.directional_emission_pdf(0).area,
                1.0, 1e-6);

    // The light sample, from a point of the floor inside the spot's full cone: I / d^2 or E.
    const Vec3 p(0.3f, 0, 0);
    const SurfacePoint at{p, Vec3(0.0f), Vec3(0, 1, 0)};
    int seen_spot = 0, seen_sun = 0;
    for (int i = 0; i < 64; ++i) {
        const auto s = sampler.sample(at, (i + 0.5f) / 64.0f, {0.5f, 0.5f});
        ASSERT_TRUE(s);
        ASSERT_TRUE(s->is_delta);
        if (s->directional) {
            ++seen_sun;
            EXPECT_EQ(s->wi, -sun);
            EXPECT_EQ(s->radiance, Color(0.8f));
            EXPECT_FLOAT_EQ(s->pdf, sampler.directional_emission_pdf(0).area);
        } else {
            ++seen_spot;
            const Vec3 d = Vec3(0, 2, 0) - p;
            EXPECT_NEAR(s->radiance.x, 5.0f * cone.falloff(-glm::normalize(d)) / glm::dot(d, d),
                        1e-6f);
            EXPECT_GT(cone.falloff(-glm::normalize(d)), 0.99f);  // inside the full cone
        }
    }
    EXPECT_GT(seen_spot, 0);
    EXPECT_GT(seen_sun, 0);
    // Outside the cone the spot sends nothing: no sample.
    const SurfacePoint outside{Vec3(-1.9f, 0, 1.9f), Vec3(0.0f), Vec3(0, 1, 0)};
    for (int i = 0; i < 64; ++i) {
        if (const auto s = sampler.sample(outside, (i + 0.5f) / 64.0f, {0.5f, 0.5f})) {
            EXPECT_TRUE(s->directional);
        }
    }
}
