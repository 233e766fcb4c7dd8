// A pinhole camera: position, look-at point, up vector and vertical field of view.
#pragma once

#include "math.h"

namespace lessons {

class Camera {
public:
    Camera() = default;
    // fov_y_degrees: full vertical field of view. aspect: width / height of the image.
    Camera(const Vec3& position, const Vec3& look_at, const Vec3& up, float fov_y_degrees,
           float aspect);

    // The primary ray through film position (x, y) in pixels: (0, 0) is the top-left corner of
    // the image, (width, height) the bottom-right. Direction is unit length.
    Ray generate_ray(float x, float y, int width, int height) const;

    const Vec3& position() const { return position_; }
    const Vec3& forward() const { return forward_; }

private:
    Vec3 position_{0.0f};
    Vec3 forward_{0.0f, 0.0f, 1.0f};  // unit viewing direction
    Vec3 right_{1.0f, 0.0f, 0.0f};    // unit, image +x
    Vec3 up_{0.0f, 1.0f, 0.0f};       // unit, image -y (rows go down)
    float tan_half_fov_ = 1.0f;       // half-height of the image plane at distance 1
    float aspect_ = 1.0f;
};

}  // namespace lessons
