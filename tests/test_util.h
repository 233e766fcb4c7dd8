// Small helpers shared by the tests: random geometry and a scene built in code.
#pragma once

#include <cmath>

#include "rng.h"
#include "scene.h"

namespace lessons::test {

inline Vec3 random_unit_vector(Rng& rng) {
    const float z = 1.0f - 2.0f * rng.uniform();
    const float r = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
    const float phi = 2.0f * kPi * rng.uniform();
    return {r * std::cos(phi), r * std::sin(phi), z};
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

inline uint32_t add_diffuse(Scene& scene, const Color& albedo) {
    Material m;
    m.name = "diffuse";
    m.type = MaterialType::Diffuse;
    m.albedo.value = albedo;
    return scene.add_material(m);
}

}  // namespace lessons::test
