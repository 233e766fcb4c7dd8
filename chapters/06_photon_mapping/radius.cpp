// Lesson 6, section 5: the default photon radius (see radius.h).
#include "06_photon_mapping/radius.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace lessons {

float pixel_side_at_unit_distance(const Camera& camera, int width, int height) {
    return std::sqrt(camera.image_plane_area() /
                     (static_cast<float>(std::max(width, 1)) * std::max(height, 1)));
}

std::optional<float> median_hit_distance(const Scene& scene) {
    constexpr int kGrid = 16;
    std::vector<float> distances;
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            // Film positions at the centres of a kGrid x kGrid partition of the image.
            const float x = (i + 0.5f) * scene.width / kGrid, y = (j + 0.5f) * scene.height / kGrid;
            const Ray ray = scene.camera.generate_ray(x, y, scene.width, scene.height);
            if (const std::optional<Hit> hit = scene.intersect(ray))
                distances.push_back(hit->shape.t);  // the direction is unit: t is the distance
        }
    if (distances.empty()) return std::nullopt;
    const auto middle = distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2);
    std::nth_element(distances.begin(), middle, distances.end());
    return *middle;
}

float default_photon_radius(const Scene& scene, float pixels) {
    const Bounds3 box = scene.bounds();
    if (box.empty()) return 1.0f;  // no surface: no photon to gather, any radius will do
    const float diagonal = glm::length(box.extent());
    const float d =
        median_hit_distance(scene).value_or(glm::length(box.centroid() - scene.camera.position()));
    const float footprint = pixel_side_at_unit_distance(scene.camera, scene.width, scene.height);
    const float r = pixels * footprint * d;
    // (If the diagonal is 0 or not finite, neither limit can be met: keep r, or fall back to 1.)
    if (!(diagonal > 0.0f) || !std::isfinite(diagonal)) return r > 0.0f ? r : 1.0f;
    return std::clamp(r, 1e-4f * diagonal, 0.05f * diagonal);
}

}  // namespace lessons
