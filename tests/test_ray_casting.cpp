// Lesson 1 against closed forms: a Lambertian sphere under a point light, an area light seen as
// a point source, and the Blinn-Phong highlight.
#include <gtest/gtest.h>

#include <glm/vec3.hpp>

#include "01_ray_casting/ray_casting.h"
#include "driver/app.h"
#include "io/scene_file.h"
#include "test_util.h"

using namespace lessons;

TEST(RayCasting, LambertianSphereUnderPointLightMatchesClosedFormPerPixel) {
    // L = rho / pi * I * cos(theta_i) / d^2 on the lit side, 0 on the other (docs/accuracy.md).
    Scene scene;
    const Color rho(0.2f, 0.5f, 0.8f);
    scene.add_sphere({Vec3(0), 1.0f}, test::add_diffuse(scene, rho));
    const Vec3 light_pos(3, 4, -5);
    const Color intensity(10, 20, 30);
    scene.add_point_light({light_pos, intensity});
    scene.width = 64;
    scene.height = 48;
    scene.camera = Camera(Vec3(0, 0, -6), Vec3(0), Vec3(0, 1, 0), 30.0f, 64.0f / 48.0f);
    scene.commit();

    RenderSettings settings;
    settings.jitter = false;  // one sample at each pixel center: a closed form per pixel
    settings.progress = false;
    const RenderResult r = render_scene(scene, RayCastingModel(scene, {}), 1, settings);

    int lit = 0, checked = 0;
    for (int y = 0; y < scene.height; ++y)
        for (int x = 0; x < scene.width; ++x) {
            const Ray ray = scene.camera.generate_ray(x + 0.5f, y + 0.5f, 64, 48);
            // Closed form in double: |o + t d| = 1.
            const glm::dvec3 o(ray.origin), d(ray.dir);
            const double b = glm::dot(o, d), c = glm::dot(o, o) - 1.0;
            const double disc = b * b - c;
            Color expected(0.0f);
            if (std::fabs(disc) < 1e-4) continue;  // within 1e-4 of the silhouette: skip
            if (disc > 0.0) {
                const glm::dvec3 p = o + (-b - std::sqrt(disc)) * d;
                const glm::dvec3 to_light = glm::dvec3(light_pos) - p;
                const double dist2 = glm::dot(to_light, to_light);
                const double cos_i = glm::dot(glm::normalize(p), to_light) / std::sqrt(dist2);
                if (cos_i > 0.0)
                    expected = Color(glm::dvec3(rho) / 3.14159265358979323846 *
                                     glm::dvec3(intensity) * cos_i / dist2);
            }
            const Color got = r.image.at(x, y);
            for (int ch = 0; ch < 3; ++ch)
                ASSERT_NEAR(got[ch], expected[ch], 1e-4f * expected[ch] + 1e-6f)
                    << "pixel " << x << "," << y << " channel " << ch;
            ++checked;
            lit += expected.x > 0.0f;
        }
    EXPECT_GT(lit, 300);
    EXPECT_GT(checked, 3000);
}

TEST(RayCasting, QuadLightIsAPointSourceOfIntensityLACosTheta) {
    // A quad light of radiance L_e and area A, h above a floor point straight below its center:
    // I = L_e A, E = I / h^2, reflected radiance rho / pi * E.
    Scene scene;
    const Color rho(0.5f);
    const uint32_t floor = test::add_diffuse(scene, rho);
    Material lamp;
    lamp.name = "lamp";
    lamp.emission = Color(4.0f, 2.0f, 1.0f);
    const uint32_t lamp_id = scene.add_material(lamp);
    scene.add_quad(Quad(Vec3(-5, 0, -5), Vec3(0, 0, 10), Vec3(10, 0, 0)), floor);  // facing up
    scene.add_quad(Quad(Vec3(-0.5f, 2, -0.25f), Vec3(1, 0, 0), Vec3(0, 0, 0.5f)), lamp_id);  // down
    scene.commit();
    ASSERT_EQ(scene.area_lights().size(), 1u);
    ASSERT_EQ(scene.area_lights()[0].normal, Vec3(0, -1, 0));
    const Ray down{Vec3(0.0f, 1.0f, 0.0f), Vec3(0, -1, 0)};
    const Color L = ray_cast(scene, down, {});
    const Color expected = rho * kInvPi * lamp.emission * (0.5f / 4.0f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(L[c], expected[c], 1e-5f * expected[c]);
    // A camera ray that sees the lamp's emitting side sees its radiance (plus nothing else:
    // the lamp does not light itself).
    const Color seen = ray_cast(scene, Ray{Vec3(0, 1, 0), Vec3(0, 1, 0)}, {});
    EXPECT_EQ(seen, lamp.emission);
    // Its back side emits nothing (one-sided).
    const Color back = ray_cast(scene, Ray{Vec3(0, 3, 0), Vec3(0, -1, 0)}, {});
    EXPECT_EQ(back, Color(0.0f));
}

TEST(RayCasting, BlinnPhongHighlightAtTheMirrorConfiguration) {
    // When h = n, f = k_d / pi + k_s N(e), N(e) = (e + 2)(e + 4) / (8 pi (2^(-e/2) + e)).
    Scene scene;
    Material glossy;
    glossy.name = "glossy";
    glossy.type = MaterialType::Glossy;
    glossy.albedo.value = Color(0.25f);
    glossy.specular = Color(0.5f);
    glossy.roughness = 0.2f;
    scene.add_quad(Quad(Vec3(-5, 0, -5), Vec3(0, 0, 10), Vec3(10, 0, 0)),
                   scene.add_material(glossy));
    scene.add_point_light({Vec3(0, 2, 0), Color(8.0f)});
    scene.commit();
    const float e = blinn_phong_exponent(0.2f);
    EXPECT_FLOAT_EQ(e, 48.0f);
    const Color L = ray_cast(scene, Ray{Vec3(0, 1, 0), Vec3(0, -1, 0)}, {});
    const float f =
        0.25f * kInvPi + 0.5f * (e + 2.0f) * (e + 4.0f) / (8.0f * kPi * (std::exp2(-e / 2) + e));
    EXPECT_NEAR(L.x, f * 8.0f / 4.0f, 1e-5f);
}

TEST(RayCasting, AmbientTermAndBackground) {
    Scene scene;
    scene.add_sphere({Vec3(0), 1.0f}, test::add_diffuse(scene, Color(0.5f)));
    scene.background = Color(0.1f, 0.2f, 0.3f);
    scene.commit();
    RayCastingOptions options;
    options.ambient = Color(1.0f);
    EXPECT_EQ(ray_cast(scene, Ray{Vec3(0, 0, -5), Vec3(0, 0, 1)}, options), Color(0.5f));
    EXPECT_EQ(ray_cast(scene, Ray{Vec3(0, 0, -5), Vec3(0, 1, 0)}, options), scene.background);
}

TEST(RayCasting, SaysWhatItApproximates) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/whitted_1979.toml", {32, 24});
    const auto model = RayCastingModel(scene, {});
    std::string all;
    for (const std::string& n : model.notes) all += n + "\n";
    EXPECT_NE(all.find("'mirror' (mirror): shaded as diffuse"), std::string::npos) << all;
    EXPECT_NE(all.find("'glass' (glass): shaded as white diffuse"), std::string::npos) << all;
    EXPECT_NE(all.find("indirect light ignored"), std::string::npos) << all;
}
