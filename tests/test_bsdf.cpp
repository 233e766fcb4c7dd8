// BSDFs, in the order Mitsuba tests them: values against closed forms, sampling against the
// density (chi-square), energy conservation, reciprocity (docs/accuracy.md).
#include <gtest/gtest.h>

#include "geometry/interaction.h"
#include "materials/bsdf.h"
#include "materials/microfacet.h"
#include "materials/optics.h"
#include "sampling/rng.h"
#include "statistics.h"
#include "test_util.h"

using namespace lessons;

namespace {

const double kSignificance = test::sidak(0.01, 60);

Vec3 direction_at(float theta_degrees) {
    const float t = theta_degrees * kPi / 180.0f;
    return {std::sin(t), 0.0f, std::cos(t)};
}

Bsdf local(const BsdfLobe& lobe) {
    return Bsdf(lobe, Vec3(0, 0, 1), Vec3(0, 0, 1));
}

struct NamedLobe {
    std::string name;
    BsdfLobe lobe;
    int cos_cells, phi_cells;  // chi-square grid: finer for peaked lobes
};

std::vector<NamedLobe> non_delta_lobes() {
    return {
        {"lambertian", Lambertian{Color(0.5f, 0.7f, 0.9f)}, 20, 40},
        {"glossy e=20", GlossyBlinnPhong{Color(0.3f), Color(0.6f), blinn_phong_exponent(0.3f)}, 40,
         80},
        {"glossy e=198", GlossyBlinnPhong{Color(0.1f), Color(0.8f), blinn_phong_exponent(0.1f)}, 80,
         160},
        {"ggx 0.1", GgxConductor{Color(0.9f, 0.6f, 0.3f), 0.1f}, 80, 160},
        {"ggx 0.3", GgxConductor{Color(0.9f, 0.6f, 0.3f), 0.3f}, 40, 80},
        {"ggx 0.7", GgxConductor{Color(0.9f, 0.6f, 0.3f), 0.7f}, 20, 40},
    };
}

}  // namespace

TEST(Bsdf, EverySamplerMatchesItsDensity) {
    int tests = 0;
    for (const NamedLobe& l : non_delta_lobes()) {
        const Bsdf bsdf = local(l.lobe);
        for (float theta : {0.0f, 40.0f, 75.0f}) {
            const Vec3 wo = direction_at(theta);
            Rng rng(100 + tests++);
            int produced = 0;
            const int n = 1000000;
            const auto r = test::chi2_test_directions(
                [&](Vec3& w) {
                    const auto s = bsdf.sample(wo, {rng.uniform(), rng.uniform()});
                    if (!s) return false;
                    EXPECT_NEAR(s->pdf, bsdf.pdf(wo, s->wi), 1e-3f * s->pdf + 1e-6f);
                    w = s->wi;
                    ++produced;
                    return true;
                },
                [&](const Vec3& w) { return static_cast<double>(bsdf.pdf(wo, w)); }, n,
                kSignificance, l.cos_cells, l.phi_cells);
            EXPECT_TRUE(r.passed) << l.name << " at " << theta << " degrees: " << r.report;
            // The density integrates to the probability that sample() produces a direction.
            const double fraction = static_cast<double>(produced) / n;
            EXPECT_NEAR(r.pdf_integral, fraction,
                        2e-3 + 4 * std::sqrt(fraction * (1 - fraction) / n))
                << l.name << " at " << theta;
        }
    }
}

TEST(Bsdf, DirectionalAlbedoNeverExceedsOneAndLambertIsExact) {
    for (const NamedLobe& l : non_delta_lobes()) {
        const Bsdf bsdf = local(l.lobe);
        for (float theta : {0.0f, 30.0f, 60.0f, 85.0f}) {
            const Vec3 wo = direction_at(theta);
            Rng rng(7);
            std::vector<double> values;
            for (int i = 0; i < 200000; ++i) {
                const auto s = bsdf.sample(wo, {rng.uniform(), rng.uniform()});
                // f cos / pdf: one sample of the directional albedo (0 when none was produced).
                values.push_back(s ? luminance(s->f) * bsdf.abs_cos(s->wi) / s->pdf : 0.0);
            }
            const auto [mean, se] = test::mean_and_error(values);
            EXPECT_LE(mean, 1.0 + 3.0 * se) << l.name << " at " << theta;
            if (l.name == "lambertian") {
                EXPECT_NEAR(mean, luminance(Color(0.5f, 0.7f, 0.9f)), 1e-5);
            }
        }
    }
}

TEST(Bsdf, GgxAlbedoAtNormalIncidenceMatchesTheReferenceValues) {
    // Single scattering, F = 1: 0.988 (alpha 0.1), 0.916 (0.25), 0.688 (0.5), 0.307 (1.0).
    const std::pair<float, double> cases[] = {
        {0.1f, 0.988}, {0.25f, 0.916}, {0.5f, 0.688}, {1.0f, 0.307}};
    for (const auto& [alpha, expected] : cases) {
        const Bsdf bsdf = local(GgxConductor{Color(1.0f), alpha});
        Rng rng(8);
        std::vector<double> values;
        for (int i = 0; i < 400000; ++i) {
            const auto s = bsdf.sample(Vec3(0, 0, 1), {rng.uniform(), rng.uniform()});
            values.push_back(s ? s->f.x * bsdf.abs_cos(s->wi) / s->pdf : 0.0);
        }
        const auto [mean, se] = test::mean_and_error(values);
        // The reference values are rounded to 0.001.
        EXPECT_NEAR(mean, expected, 0.0005 + 3.0 * se) << "alpha " << alpha;
    }
}

TEST(Bsdf, MicrofacetDistributionsIntegrateToOne) {
    // Integral of D(m) (m.n) dm = 1, and of the visible-normal density D_wo(m) dm = 1 (Heitz 2014).
    for (float alpha : {0.1f, 0.3f, 0.7f, 1.0f}) {
        const double projected = test::adaptive_simpson(
            [&](double c) {
                return 2.0 * kPi * ggx_D(Vec3(std::sqrt(1 - c * c), 0, c), alpha) * c;
            },
            0.0, 1.0, 1e-9, 20);
        EXPECT_NEAR(projected, 1.0, 1e-4) << alpha;
        const Vec3 wo = direction_at(50.0f);
        const double visible = test::adaptive_simpson(
            [&](double c) {
                return test::adaptive_simpson(
                    [&](double phi) {
                        const double s = std::sqrt(std::max(0.0, 1 - c * c));
                        const Vec3 m(s * std::cos(phi), s * std::sin(phi), c);
                        return ggx_G1(wo, alpha) * std::max(0.0f, glm::dot(wo, m)) *
                               ggx_D(m, alpha) / wo.z;
                    },
                    0.0, 2.0 * kPi, 1e-8, 12);
            },
            0.0, 1.0, 1e-7, 14);
        EXPECT_NEAR(visible, 1.0, 2e-3) << alpha;
    }
}

TEST(Bsdf, ReciprocityHolds) {
    Rng rng(9);
    for (const NamedLobe& l : non_delta_lobes()) {
        const Bsdf bsdf = local(l.lobe);
        for (int i = 0; i < 10000; ++i) {
            Vec3 a = test::random_unit_vector(rng), b = test::random_unit_vector(rng);
            a.z = std::fabs(a.z);
            b.z = std::fabs(b.z);
            const Color ab = bsdf.eval(a, b), ba = bsdf.eval(b, a);
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(ab[c], ba[c], 1e-4f * ab[c] + 1e-7f) << l.name;
        }
    }
}

TEST(Bsdf, DeltaBsdfsScatterWhereAndAsMuchAsOpticsSays) {
    const Bsdf mirror = local(PerfectMirror{Color(0.8f, 0.5f, 0.2f)});
    const Vec3 wo = glm::normalize(Vec3(0.3f, -0.2f, 0.9f));
    const auto s = mirror.sample(wo, {0.3f, 0.7f});
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->is_delta);
    EXPECT_NEAR(glm::length(s->wi - reflect(wo, Vec3(0, 0, 1))), 0.0f, 1e-6f);
    EXPECT_NEAR(s->f.x * mirror.abs_cos(s->wi) / s->pdf, 0.8f, 1e-6f);
    EXPECT_EQ(mirror.eval(wo, s->wi), Color(0.0f));
    EXPECT_EQ(mirror.pdf(wo, s->wi), 0.0f);

    // Glass: reflected with probability F, weight 1; transmitted with 1 - F, weight 1 / eta^2.
    const Bsdf glass(SmoothDielectric{1.5f}, Vec3(0, 0, 1), Vec3(0, 0, 1));
    for (const Vec3& w : {direction_at(30.0f), -direction_at(30.0f), -direction_at(60.0f)}) {
        const bool entering = w.z > 0.0f;
        const float eta = entering ? 1.5f : 1.0f / 1.5f;
        const float F = fresnel_dielectric(std::fabs(w.z), eta);
        Rng rng(10);
        const int n = 200000;
        int reflected = 0;
        for (int i = 0; i < n; ++i) {
            const auto g = glass.sample(w, {rng.uniform(), rng.uniform()});
            ASSERT_TRUE(g);
            const float weight = g->f.x * glass.abs_cos(g->wi) / g->pdf;
            if (g->wi.z * w.z > 0.0f) {
                ++reflected;
                ASSERT_NEAR(weight, 1.0f, 1e-5f);
            } else {
                ASSERT_NEAR(weight, 1.0f / (eta * eta), 1e-5f);
            }
        }
        const double sd = std::sqrt(n * F * (1 - F));
        EXPECT_NEAR(reflected, n * F, 5 * sd + 1) << "F = " << F;
    }
}

TEST(Bsdf, SamplesAreFiniteAtTheEndsOfTheUnitSquare) {
    std::vector<NamedLobe> lobes = non_delta_lobes();
    lobes.push_back({"mirror", PerfectMirror{Color(1.0f)}, 0, 0});
    lobes.push_back({"glass", SmoothDielectric{1.5f}, 0, 0});
    const float ends[] = {0.0f, 0.5f, 0x1.fffffep-1f};
    for (const NamedLobe& l : lobes) {
        const Bsdf bsdf = local(l.lobe);
        for (float theta : {0.0f, 45.0f, 89.9f})
            for (float a : ends)
                for (float b : ends) {
                    const auto s = bsdf.sample(direction_at(theta), {a, b});
                    if (!s) continue;
                    EXPECT_TRUE(is_finite(s->wi) && is_finite(s->f) && std::isfinite(s->pdf))
                        << l.name;
                    EXPECT_GT(s->pdf, 0.0f) << l.name;
                }
    }
}

TEST(Bsdf, ShadingFromBehindAndNoLightThroughTheGeometricSurface) {
    // A shading normal tilted away from the geometric one: reflection still needs wo and wi on
    // the same side of the true surface.
    const Bsdf bsdf(Lambertian{Color(0.5f)}, glm::normalize(Vec3(0.3f, 0, 1)), Vec3(0, 0, 1));
    const Vec3 wo(0, 0, 1);
    const Vec3 below =
        glm::normalize(Vec3(1, 0, -0.1f));  // above the shading plane, below the surface
    EXPECT_EQ(bsdf.eval(wo, below), Color(0.0f));
    EXPECT_EQ(bsdf.pdf(wo, below), 0.0f);
}

TEST(MaterialTypes, FactsAgreeWithTheBsdfTheTypeMakes) {
    // What materials/material.h says of each type (facts_of) against the BSDF the type makes,
    // seen from 30 degrees on its front: a delta type makes a delta BSDF, a transmitting one
    // sends some samples below the surface, and a parameter the type is said to use changes
    // the samples (directions, values, densities) while one it is said not to use changes none.
    SurfaceInteraction si{};
    si.n_geo = si.n_shading = Vec3(0, 0, 1);
    si.wo = direction_at(30.0f);
    si.shading_fallback = false;
    auto samples = [&](const Material& m) {
        const Bsdf bsdf(m, si);
        std::vector<float> all;
        for (float ux : {0.05f, 0.3f, 0.6f, 0.95f})
            for (float uy : {0.1f, 0.5f, 0.8f})
                if (const auto s = bsdf.sample(si.wo, {ux, uy}))
                    all.insert(all.end(), {s->wi.x, s->wi.y, s->wi.z, s->f.x, s->f.y, s->pdf});
        return all;
    };
    for (const MaterialType type :
         {MaterialType::Diffuse, MaterialType::Glossy, MaterialType::Conductor,
          MaterialType::Mirror, MaterialType::Glass}) {
        const MaterialTypeFacts facts = facts_of(type);
        Material m;
        m.type = type;
        m.albedo.value = Color(0.3f, 0.2f, 0.1f);
        m.specular = Color(0.4f, 0.5f, 0.6f);
        m.roughness = 0.3f;
        m.reflectance = Color(0.5f, 0.6f, 0.7f);
        m.ior = 1.5f;
        m.transmittance = Color(0.6f, 0.7f, 0.8f);
        EXPECT_EQ(Bsdf(m, si).is_delta(), facts.delta) << facts.name;
        const std::vector<float> base = samples(m);
        ASSERT_FALSE(base.empty()) << facts.name;
        bool below = false;
        for (size_t k = 2; k < base.size(); k += 6) below |= base[k] < 0.0f;
        EXPECT_EQ(below, facts.transmits) << facts.name;
        auto changes = [&](auto change) {
            Material other = m;
            change(other);
            return samples(other) != base;
        };
        EXPECT_EQ(changes([](Material& o) { o.albedo.value = Color(0.6f); }), facts.albedo)
            << facts.name;
        EXPECT_EQ(changes([](Material& o) { o.specular = Color(0.2f); }), facts.lobe) << facts.name;
        EXPECT_EQ(changes([](Material& o) { o.roughness = 0.6f; }), facts.lobe) << facts.name;
        EXPECT_EQ(changes([](Material& o) { o.reflectance = Color(0.9f); }), facts.reflectance)
            << facts.name;
        EXPECT_EQ(changes([](Material& o) { o.ior = 1.3f; }), facts.dielectric) << facts.name;
        EXPECT_EQ(changes([](Material& o) { o.transmittance = Color(0.9f); }), facts.dielectric)
            << facts.name;
    }
}
