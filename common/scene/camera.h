// A pinhole camera: position, look-at point, up vector and vertical field of view.
#pragma once

#include <optional>

#include "geometry/math.h"

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

    // The way back, for light paths (lesson 5): where on the film, in pixels, the ray from the
    // camera in unit direction `dir` passes; none if it misses the image.
    std::optional<Vec2> raster_position(const Vec3& dir, int width, int height) const;
    // The camera's importance, as light tracing needs it. A pixel's value is the mean radiance
    // over the pixel's patch of the image plane at distance 1, of area A_pixel; a patch dA of
    // that plane, at angle theta from the view axis, subtends d(omega) = cos^3(theta) dA. So
    //   pixel value = integral over directions of W(omega) L(omega) d(omega),
    //   W(omega) = 1 / (A_pixel cos^3(theta)) inside the pixel, 0 outside.
    // One light path per pixel sample estimates every pixel at once: with N = width x height
    // paths per pass, each is weighted by W / N = 1 / (A_image cos^3(theta)), the value this
    // returns (0 behind the camera). It is also the density, per unit solid angle, with which
    // the camera's rays of one pass (one per pixel, uniform in it) choose a direction.
    float importance(const Vec3& dir) const;
    // The image plane's area at distance 1: (2 tan(fov_y / 2))^2 aspect.
    float image_plane_area() const { return 4.0f * tan_half_fov_ * tan_half_fov_ * aspect_; }

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
