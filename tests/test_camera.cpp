// The pinhole camera: basis, field of view, image orientation.
#include <gtest/gtest.h>

#include "scene/camera.h"

using namespace lessons;

TEST(Camera, CenterRayLooksAtTheTargetAndEdgesSpanTheFieldOfView) {
    const Camera camera(Vec3(1, 2, 3), Vec3(1, 2, 13), Vec3(0, 1, 0), 60.0f, 2.0f);
    const Ray center = camera.generate_ray(100, 50, 200, 100);
    EXPECT_NEAR(glm::length(center.dir - Vec3(0, 0, 1)), 0.0f, 1e-6f);
    EXPECT_EQ(center.origin, Vec3(1, 2, 3));
    // The top edge of the image is fov/2 above the axis; the right edge atan(aspect tan(fov/2))
    // to the right, which is -x when looking along +z with +y up.
    const Ray top = camera.generate_ray(100, 0, 200, 100);
    EXPECT_NEAR(std::atan2(top.dir.y, top.dir.z), 30.0f * kPi / 180.0f, 1e-5f);
    const Ray right = camera.generate_ray(200, 50, 200, 100);
    EXPECT_LT(right.dir.x, 0.0f);
    EXPECT_NEAR(std::atan2(-right.dir.x, right.dir.z), std::atan(2.0f * std::tan(kPi / 6)), 1e-5f);
    // Directions are unit length everywhere.
    for (float x : {0.0f, 17.5f, 200.0f})
        for (float y : {0.0f, 63.0f, 100.0f})
            EXPECT_NEAR(glm::length(camera.generate_ray(x, y, 200, 100).dir), 1.0f, 1e-6f);
}

TEST(Camera, UpNeedNotBePerpendicular) {
    const Camera camera(Vec3(0), Vec3(0, -1, 1), Vec3(0, 1, 0), 40.0f, 1.0f);
    const Ray top = camera.generate_ray(50, 0, 100, 100);
    const Ray bottom = camera.generate_ray(50, 100, 100, 100);
    EXPECT_GT(top.dir.y, bottom.dir.y);  // image up is world up, as far as it can be
}

TEST(Camera, RasterPositionInvertsGenerateRayOnAWideImageToItsCorners) {
    // Light tracing (lesson 5) splats a light vertex where the camera ray towards it starts on
    // the film: raster_position must undo generate_ray everywhere on the film, also on an image
    // whose aspect is not 1 and in its corner pixels, and refuse what lies outside.
    const int w = 320, h = 90;
    const Camera camera(Vec3(0.3f, 1.2f, -4), Vec3(-0.2f, 0.5f, 1), Vec3(0, 1, 0), 50.0f,
                        static_cast<float>(w) / h);
    std::vector<Vec2> film = {{0.5f, 0.5f},         {w - 0.5f, 0.5f},      {0.5f, h - 0.5f},
                              {w - 0.5f, h - 0.5f}, {1e-3f, 1e-3f},        {w - 1e-3f, h - 1e-3f},
                              {160.0f, 45.0f},      {w * 0.77f, h * 0.13f}};
    for (int i = 1; i <= 200; ++i)
        film.push_back({(i * 0.618034f - std::floor(i * 0.618034f)) * w,
                        (i * 0.7548777f - std::floor(i * 0.7548777f)) * h});
    for (const Vec2& p : film) {
        const std::optional<Vec2> back =
            camera.raster_position(camera.generate_ray(p.x, p.y, w, h).dir, w, h);
        ASSERT_TRUE(back) << p.x << ", " << p.y;
        EXPECT_NEAR(back->x, p.x, 2e-3f * (1.0f + p.x * 1e-2f)) << p.x << ", " << p.y;
        EXPECT_NEAR(back->y, p.y, 2e-3f) << p.x << ", " << p.y;
        // The pixel it lands in is the pixel the ray was made for (away from pixel edges).
        if (std::fabs(p.x - std::round(p.x)) > 0.01f && std::fabs(p.y - std::round(p.y)) > 0.01f) {
            EXPECT_EQ(static_cast<int>(back->x), static_cast<int>(p.x));
            EXPECT_EQ(static_cast<int>(back->y), static_cast<int>(p.y));
        }
    }
    // Outside the film, and behind the camera: nothing.
    for (const Vec2& p :
         {Vec2(-0.5f, 45.0f), Vec2(w + 0.5f, 45.0f), Vec2(160.0f, -0.5f), Vec2(160.0f, h + 0.5f)})
        EXPECT_FALSE(camera.raster_position(camera.generate_ray(p.x, p.y, w, h).dir, w, h))
            << p.x << ", " << p.y;
    EXPECT_FALSE(camera.raster_position(-camera.forward(), w, h));
}

TEST(Camera, ImportanceIntegratesToOneOverTheFilm) {
    // W(omega) = 1 / (A cos^3 theta) over the directions the film sees (camera.h): one light
    // path per pass is spread over every pixel, so W integrates to 1 over them. Monte Carlo with
    // directions uniform on the hemisphere about the view axis, z-test against 1; and W is 0
    // behind the camera.
    for (const float aspect : {1.0f, 2.5f, 0.6f}) {
        const int w = static_cast<int>(100 * aspect), h = 100;
        const Camera camera(Vec3(1, 2, 3), Vec3(0, 1.5f, 0), Vec3(0, 1, 0), 70.0f,
                            static_cast<float>(w) / h);
        const Vec3 f = camera.forward();
        const Vec3 a =
            glm::normalize(glm::cross(f, std::fabs(f.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0)));
        const Vec3 b = glm::cross(f, a);
        double sum = 0.0, sum2 = 0.0;
        const int n = 400000;
        uint64_t state = 12345;
        auto uniform = [&] {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return static_cast<double>(state >> 11) * 0x1p-53;
        };
        for (int i = 0; i < n; ++i) {
            const double z = uniform(), phi = 2.0 * kPi * uniform();  // uniform on the hemisphere
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const Vec3 d = glm::normalize(static_cast<float>(z) * f +
                                          static_cast<float>(r * std::cos(phi)) * a +
                                          static_cast<float>(r * std::sin(phi)) * b);
            const double x =
                camera.raster_position(d, w, h) ? camera.importance(d) * 2.0 * kPi : 0.0;
            sum += x;
            sum2 += x * x;
        }
        const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / (n - 1));
        EXPECT_LT(std::fabs(mean - 1.0), 4.0 * se)
            << "aspect " << aspect << ": " << mean << " +- " << se;
        EXPECT_EQ(camera.importance(-f), 0.0f);
    }
}
