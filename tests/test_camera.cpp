// The pinhole camera: basis, field of view, image orientation.
#include <gtest/gtest.h>

#include "render/camera.h"

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
