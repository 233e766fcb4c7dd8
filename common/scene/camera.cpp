// Pinhole camera: an orthonormal basis from look-at and up, rays through the image plane at
// distance 1, whose half-height is tan(fov_y / 2).
#include "scene/camera.h"

#include <cmath>

namespace lessons {

Camera::Camera(const Vec3& position, const Vec3& look_at, const Vec3& up, float fov_y_degrees,
               float aspect)
    : position_(position), aspect_(aspect) {
    forward_ = glm::normalize(look_at - position);
    right_ = glm::normalize(glm::cross(forward_, up));
    up_ = glm::cross(right_, forward_);
    tan_half_fov_ = std::tan(0.5f * fov_y_degrees * kPi / 180.0f);
}

Ray Camera::generate_ray(float x, float y, int width, int height) const {
    const float ndc_x = 2.0f * x / static_cast<float>(width) - 1.0f;   // -1 left, +1 right
    const float ndc_y = 1.0f - 2.0f * y / static_cast<float>(height);  // +1 top, -1 bottom
    const Vec3 d =
        forward_ + (ndc_x * tan_half_fov_ * aspect_) * right_ + (ndc_y * tan_half_fov_) * up_;
    return Ray{position_, glm::normalize(d), kInfinity};
}

std::optional<Vec2> Camera::raster_position(const Vec3& dir, int width, int height) const {
    const float cos_theta = glm::dot(dir, forward_);
    if (!(cos_theta > 0.0f)) return std::nullopt;
    // The point where the ray meets the image plane at distance 1, in generate_ray's units.
    const Vec3 on_plane = dir / cos_theta;
    const float ndc_x = glm::dot(on_plane, right_) / (tan_half_fov_ * aspect_);
    const float ndc_y = glm::dot(on_plane, up_) / tan_half_fov_;
    const float x = 0.5f * (ndc_x + 1.0f) * static_cast<float>(width);
    const float y = 0.5f * (1.0f - ndc_y) * static_cast<float>(height);
    if (!(x >= 0.0f && x < static_cast<float>(width) && y >= 0.0f &&
          y < static_cast<float>(height)))
        return std::nullopt;
    return Vec2(x, y);
}

float Camera::importance(const Vec3& dir) const {
    const float cos_theta = glm::dot(dir, forward_);
    if (!(cos_theta > 0.0f)) return 0.0f;
    return 1.0f / (image_plane_area() * cos_theta * cos_theta * cos_theta);
}

}  // namespace lessons
