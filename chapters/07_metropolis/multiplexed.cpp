// Lesson 7, section 2: the path of a state, by one of lesson 5's strategies (multiplexed.h).
#include "07_metropolis/multiplexed.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "05_bidirectional/connect.h"

namespace lessons {

int path_length(float u, int longest, double* probability) {
    // The cumulative probability of lengths 1 .. k is (1 - 1 / (k + 1)) / norm: the length is the
    // first k whose 1 / (k + 1) falls below 1 - u norm.
    const double norm = 1.0 - 1.0 / (static_cast<double>(longest) + 1.0);
    const double v = static_cast<double>(u) * norm;
    const double k_real = std::floor(1.0 / (1.0 - v));
    const int k = static_cast<int>(std::clamp(k_real, 1.0, static_cast<double>(longest)));
    if (probability) *probability = 1.0 / (static_cast<double>(k) * (k + 1.0)) / norm;
    return k;
}

PathContribution multiplexed_path(const Bidir& b, PrimarySamples& x, int longest) {
    thread_local std::vector<Vertex> camera, light;
    x.start_path();
    // The film position, uniform over the whole image.
    const Vec2 u_film = x.stream(kCameraStream).uniform2();
    const Vec2 raster(u_film.x * static_cast<float>(b.width),
                      u_film.y * static_cast<float>(b.height));
    // The length, then the strategy: one of the path's segments + 1.
    double q = 1.0;
    const int segments = path_length(x.stream(kConnectionStream).uniform(), longest, &q);
    const int strategies = segments + 1;
    const int s = std::min(
        static_cast<int>(x.stream(kConnectionStream).uniform() * static_cast<float>(strategies)),
        strategies - 1);
    const int t = strategies - s;

    PathContribution out;
    const glm::ivec2 at = pixel_at(b, raster);
    out.pixel =
        static_cast<uint32_t>(at.y) * static_cast<uint32_t>(b.width) + static_cast<uint32_t>(at.x);
    // Subpaths of exactly t and s vertices, without Russian roulette: a chain keeps its length.
    const Ray ray = b.camera.generate_ray(raster.x, raster.y, b.width, b.height);
    camera_subpath(b, ray, x.stream(kCameraStream), t, -1, camera);
    if (static_cast<int>(camera.size()) < t) return out;
    light.clear();
    if (s >= 2 || (s == 1 && t == 1)) {
        light_subpath(b, x.stream(kLightStream), s, -1, light);
        if (static_cast<int>(light.size()) < s) return out;
    }
    const StrategySample c =
        connect(b, light, s, camera, t, x.stream(kConnectionStream), true, nullptr);
    if (is_black(c.L)) return out;
    if (t == 1) {
        if (!c.pixel) return out;
        out.pixel = *c.pixel;
    }
    out.value = c.L * static_cast<float>(static_cast<double>(c.weight) * strategies / q);
    return out;
}

}  // namespace lessons
