// Reflection, refraction and the Fresnel equations against their closed forms.
#include <gtest/gtest.h>

#include "materials/optics.h"
#include "test_util.h"

using namespace lessons;

namespace {
// Transmittance computed independently of fresnel_dielectric, from the Fresnel amplitude
// transmission coefficients and the change of beam cross-section and index:
//   T = (n_t cos_t) / (n_i cos_i) * (t_s^2 + t_p^2) / 2.
double transmittance(double cos_i, double n_i, double n_t) {
    const double sin_t = n_i / n_t * std::sqrt(1.0 - cos_i * cos_i);
    if (sin_t >= 1.0) return 0.0;
    const double cos_t = std::sqrt(1.0 - sin_t * sin_t);
    const double t_s = 2.0 * n_i * cos_i / (n_i * cos_i + n_t * cos_t);
    const double t_p = 2.0 * n_i * cos_i / (n_t * cos_i + n_i * cos_t);
    return (n_t * cos_t) / (n_i * cos_i) * 0.5 * (t_s * t_s + t_p * t_p);
}
}  // namespace

TEST(Fresnel, ReflectedPlusTransmittedIsOneAtEveryAngleOnBothSides) {
    for (double ior : {1.33, 1.5, 2.4}) {
        for (bool entering : {true, false}) {
            const double n_i = entering ? 1.0 : ior, n_t = entering ? ior : 1.0;
            for (int k = 1; k <= 1000; ++k) {
                const double cos_i = k / 1000.0;
                const double R =
                    fresnel_dielectric(static_cast<float>(cos_i), static_cast<float>(n_t / n_i));
                ASSERT_NEAR(R + transmittance(cos_i, n_i, n_t), 1.0, 2e-5)
                    << "ior " << ior << " entering " << entering << " cos " << cos_i;
            }
        }
    }
}

TEST(Fresnel, NormalIncidenceAndTotalInternalReflection) {
    for (float ior : {1.33f, 1.5f, 2.4f}) {
        const float r0 = ((1.0f - ior) / (1.0f + ior)) * ((1.0f - ior) / (1.0f + ior));
        EXPECT_NEAR(fresnel_dielectric(1.0f, ior), r0, 1e-6f);
        EXPECT_NEAR(fresnel_dielectric(1.0f, 1.0f / ior), r0, 1e-6f);  // same from inside
        // From inside, beyond the critical angle sin(theta_c) = 1 / ior, everything reflects.
        const float cos_critical = std::sqrt(1.0f - 1.0f / (ior * ior));
        for (float c = 0.0f; c < cos_critical * 0.999f; c += 0.001f)
            ASSERT_EQ(fresnel_dielectric(c, 1.0f / ior), 1.0f) << "cos " << c;
        EXPECT_LT(fresnel_dielectric(cos_critical * 1.001f, 1.0f / ior), 1.0f);
        EXPECT_FALSE(refract(Vec3(std::sqrt(1 - 0.01f), 0, 0.1f), Vec3(0, 0, 1), 1.0f / ior));
        // Grazing incidence from outside reflects everything too.
        EXPECT_NEAR(fresnel_dielectric(0.0f, ior), 1.0f, 1e-6f);
    }
    // Schlick's approximation: exact at normal incidence and at grazing, 1 under TIR, and for
    // glass (ior 1.5) entering from air never more than 0.036 from the exact value (the largest
    // difference is near cos = 0.09).
    EXPECT_NEAR(fresnel_schlick(1.0f, 1.5f), 0.04f, 1e-6f);
    EXPECT_NEAR(fresnel_schlick(0.0f, 1.5f), 1.0f, 1e-6f);
    float worst = 0.0f;
    for (int k = 0; k <= 1000; ++k)
        worst = std::max(worst, std::fabs(fresnel_schlick(k / 1000.0f, 1.5f) -
                                          fresnel_dielectric(k / 1000.0f, 1.5f)));
    EXPECT_LT(worst, 0.036f);
    EXPECT_GT(worst, 0.03f);
    EXPECT_EQ(fresnel_schlick(0.1f, 1.0f / 1.5f), 1.0f);
}

TEST(Refraction, SnellsLawAndReflectionGeometry) {
    Rng rng(4);
    for (int i = 0; i < 10000; ++i) {
        Vec3 wi = test::random_unit_vector(rng);
        const Vec3 n(0, 0, 1);
        if (wi.z < 0) wi.z = -wi.z;
        const Vec3 r = reflect(wi, n);
        EXPECT_NEAR(r.z, wi.z, 1e-6f);
        EXPECT_NEAR(r.x, -wi.x, 1e-6f);
        for (float eta : {1.5f, 1.0f / 1.5f}) {
            const std::optional<Vec3> t = refract(wi, n, eta);
            const float sin_i = std::sqrt(std::max(0.0f, 1 - wi.z * wi.z));
            if (!t) {
                EXPECT_GE(sin_i / eta, 0.999f);
                continue;
            }
            EXPECT_NEAR(glm::length(*t), 1.0f, 1e-5f);
            EXPECT_LE(t->z, 0.0f);  // on the far side
            const float sin_t = std::sqrt(std::max(0.0f, 1 - t->z * t->z));
            EXPECT_NEAR(sin_i, eta * sin_t, 2e-4f);  // n_i sin_i = n_t sin_t
            // In the plane of incidence: the tangential parts point opposite ways.
            EXPECT_LE(wi.x * t->x + wi.y * t->y, 1e-6f);
        }
    }
}
