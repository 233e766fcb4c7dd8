// Small helpers shared by the tests: render settings, a model made of a function (FunctionModel,
// render_film), random geometry and a scene built in code.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/vec3.hpp>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "io/image.h"
#include "render/render.h"
#include "sampling/rng.h"
#include "sampling/sampling.h"
#include "scene/environment.h"
#include "scene/scene.h"

namespace lessons::test {

// Render settings for a test: no progress on stderr, the given seed and threads (0: all).
inline RenderSettings quiet_settings(uint64_t seed, int threads = 0) {
    RenderSettings settings;
    settings.progress = false;
    settings.seed = seed;
    settings.threads = threads;
    return settings;
}

// The same with independent samples (PCG32 per sample): each pixel's film variance is then the
// error of its mean.
inline RenderSettings independent_settings(uint64_t seed, int threads = 0) {
    RenderSettings settings = quiet_settings(seed, threads);
    settings.sampler = RenderSettings::Sampler::Independent;
    return settings;
}

// A model made of a function of the primary ray and its random numbers, fn(ray, rng): a test's
// own radiance through the render loop (it neither splats nor renders in passes).
template <class Fn>
class FunctionModel final : public Model {
public:
    explicit FunctionModel(Fn fn) : fn_(std::move(fn)) {}
    Color sample(const Ray& ray, Rng& rng, uint32_t, std::span<Color>,
                 std::vector<Splat>&) const override {
        return fn_(ray, rng);
    }

private:
    Fn fn_;
};

// Renders samples [begin, end) of every pixel of `film` (the image only) with `model`.
inline RenderStats render_film(const Camera& camera, Film& film, const RenderSettings& settings,
                               const Model& model, int begin, int end) {
    return render(camera, std::span<Film>(&film, 1), settings, model, begin, end);
}

// Calls fn(x, y, ray) for the ray through the center of every pixel of a width x height image,
// row by row: the rays that a render without jitter traces first.
template <class Fn>
void for_each_pixel_center(const Camera& camera, int width, int height, Fn&& fn) {
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            fn(x, y, camera.generate_ray(x + 0.5f, y + 0.5f, width, height));
}

inline Vec3 random_unit_vector(Rng& rng) {
    return sample_uniform_sphere({rng.uniform(), rng.uniform()});
}

inline Vec3 random_in_box(Rng& rng, float lo, float hi) {
    return {lo + (hi - lo) * rng.uniform(), lo + (hi - lo) * rng.uniform(),
            lo + (hi - lo) * rng.uniform()};
}

// A closed triangle mesh of the unit sphere (latitude-longitude, shared vertices at the seams
// and poles) scaled by `radius` about `center`.
inline void add_tessellated_sphere(Scene& scene, const Vec3& center, float radius, int rings,
                                   int segments, uint32_t material,
                                   std::vector<Vec3>* out_vertices = nullptr) {
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
    positions.push_back(center + Vec3(0, radius, 0));  // north pole: 0
    for (int i = 1; i < rings; ++i) {
        const float theta = kPi * i / rings;
        for (int j = 0; j < segments; ++j) {
            const float phi = 2.0f * kPi * j / segments;
            positions.push_back(center + radius * Vec3(std::sin(theta) * std::cos(phi),
                                                       std::cos(theta),
                                                       std::sin(theta) * std::sin(phi)));
        }
    }
    const uint32_t south = static_cast<uint32_t>(positions.size());
    positions.push_back(center + Vec3(0, -radius, 0));
    auto ring_vertex = [&](int ring, int seg) {  // ring in 1..rings-1
        return static_cast<uint32_t>(1 + (ring - 1) * segments + (seg % segments));
    };
    for (int j = 0; j < segments; ++j) {
        triangles.push_back({{0, ring_vertex(1, j + 1), ring_vertex(1, j)}, material, false});
        triangles.push_back(
            {{south, ring_vertex(rings - 1, j), ring_vertex(rings - 1, j + 1)}, material, false});
    }
    for (int i = 1; i < rings - 1; ++i)
        for (int j = 0; j < segments; ++j) {
            triangles.push_back(
                {{ring_vertex(i, j), ring_vertex(i, j + 1), ring_vertex(i + 1, j + 1)},
                 material,
                 false});
            triangles.push_back(
                {{ring_vertex(i, j), ring_vertex(i + 1, j + 1), ring_vertex(i + 1, j)},
                 material,
                 false});
        }
    scene.add_mesh(positions, {}, {}, triangles);
    if (out_vertices) *out_vertices = positions;
}

// Lambert's formula for the irradiance from a uniform polygonal emitter of radiance L
// (Arvo 1995, eq. 3.3): E = (L / 2) |sum_k Theta_k (Gamma_k . n)|, with Theta_k the angle the
// k-th edge subtends at p and Gamma_k the unit normal of the plane through p and that edge.
inline double lambert_polygon_irradiance(const std::vector<glm::dvec3>& vertices,
                                         const glm::dvec3& p, const glm::dvec3& n, double L) {
    double sum = 0.0;
    for (size_t k = 0; k < vertices.size(); ++k) {
        const glm::dvec3 a = glm::normalize(vertices[k] - p);
        const glm::dvec3 b = glm::normalize(vertices[(k + 1) % vertices.size()] - p);
        sum += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) *
               glm::dot(glm::normalize(glm::cross(a, b)), n);
    }
    return 0.5 * L * std::fabs(sum);
}

// The furnace: inside a unit sphere whose wall emits Le on both sides and reflects with albedo
// rho, radiance is Le / (1 - rho) everywhere. An 8 x 8 camera looks from inside it.
inline Scene furnace(float rho, float Le) {
    Scene scene;
    Material m;
    m.name = "furnace";
    m.albedo.value = Color(rho);
    m.emission = Color(Le);
    m.two_sided = true;
    scene.add_sphere({Vec3(0), 1.0f}, scene.add_material(m));
    scene.width = scene.height = 8;
    scene.camera = Camera(Vec3(0, 0, -0.3f), Vec3(0, 0, 1), Vec3(0, 1, 0), 70.0f, 1.0f);
    scene.commit();
    return scene;
}

inline uint32_t add_diffuse(Scene& scene, const Color& albedo) {
    Material m;
    m.name = "diffuse";
    m.type = MaterialType::Diffuse;
    m.albedo.value = albedo;
    return scene.add_material(m);
}

// A small environment map with structure, for the map tests: a sky gradient over a dark ground
// (16 x 8 texels) and one bright texel at (5, bright_row).
inline std::shared_ptr<const EnvironmentMap> structured_environment_map(float rotate,
                                                                        int bright_row,
                                                                        float bright,
                                                                        float strength) {
    const int w = 16, h = 8;
    std::vector<Color> texels(w * h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            texels[j * w + i] = j < h / 2 ? Color(0.2f + 0.1f * j, 0.3f, 0.5f + 0.05f * i)
                                          : Color(0.05f, 0.04f, 0.03f);
    texels[bright_row * w + 5] = Color(bright);
    return std::make_shared<const EnvironmentMap>(w, h, texels, rotate, strength);
}

// Whether two images are the same size and the same bits.
inline bool same_bits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Color)) == 0;
}

}  // namespace lessons::test
