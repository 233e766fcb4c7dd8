// bench_bvh's scenes and rays (see scenes.h).
#include "scenes.h"

#include <cmath>
#include <cstdint>

#include "geometry/spawn.h"
#include "io/scene_file.h"
#include "lights/lights.h"
#include "sampling/rng.h"
#include "sampling/sampling.h"

namespace lessons::bench {

TriangleMesh cornell_box_mesh(const std::string& path) {
    const Scene scene = load_scene(path);
    TriangleMesh mesh{"cornell_box", {}, {}, scene.camera, {}};
    for (const Quad& q : scene.quads()) {
        const auto base = static_cast<uint32_t>(mesh.positions.size());
        mesh.positions.push_back(q.corner);
        mesh.positions.push_back(q.corner + q.edge_u);
        mesh.positions.push_back(q.corner + q.edge_u + q.edge_v);
        mesh.positions.push_back(q.corner + q.edge_v);
        mesh.triangles.push_back({{base, base + 1, base + 2}, 0, false});
        mesh.triangles.push_back({{base, base + 2, base + 3}, 0, false});
    }
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), scene.positions().begin(), scene.positions().end());
    for (Triangle t : scene.triangles()) {
        for (uint32_t& v : t.v) v += base;
        t.material = 0;
        mesh.triangles.push_back(t);
    }
    // The shadow rays' target: just below the middle of the lamp (on it, a ray could end on
    // the lamp or stop just short of it, depending on rounding).
    mesh.light = scene.bounds().centroid();
    if (!scene.area_lights().empty()) {
        const AreaLight& lamp = scene.area_lights()[0];
        mesh.light = lamp.center +
                     1e-3f * glm::length(scene.bounds().max - scene.bounds().min) * lamp.normal;
    }
    return mesh;
}

TriangleMesh displaced_sphere(int n) {
    TriangleMesh mesh;
    mesh.name = "sphere_" + std::to_string(12 * n * n);
    auto radius = [](const Vec3& d) {
        return 1.0f + 0.12f * std::sin(9.0f * d.x) * std::sin(11.0f * d.y) * std::sin(10.0f * d.z) +
               0.04f * std::sin(37.0f * d.x + 23.0f * d.y) * std::sin(41.0f * d.z);
    };
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int face = 0; face < 6; ++face) {
        const Vec3 normal = axes[face / 2] * (face % 2 ? -1.0f : 1.0f);
        const Vec3 u = axes[(face / 2 + 1) % 3] * (face % 2 ? -1.0f : 1.0f);
        const Vec3 v = axes[(face / 2 + 2) % 3];
        const auto base = static_cast<uint32_t>(mesh.positions.size());
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const Vec3 d =
                    glm::normalize(normal + (2.0f * i / n - 1.0f) * u + (2.0f * j / n - 1.0f) * v);
                mesh.positions.push_back(radius(d) * d);
            }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const uint32_t a = base + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
                mesh.triangles.push_back({{a, b, d}, 0, false});
                mesh.triangles.push_back({{a, d, c}, 0, false});
            }
    }
    // Shared cube edges repeat their vertices; the mesh stays closed because the positions are
    // computed identically on both faces.
    mesh.camera = Camera(Vec3(0.3f, 0.8f, -3.2f), Vec3(0.0f), Vec3(0, 1, 0), 45.0f, 1.0f);
    mesh.light = Vec3(2.0f, 3.0f, -2.0f);
    return mesh;
}

Scene uncommitted_scene(const TriangleMesh& mesh) {
    Scene scene;
    Material white;
    scene.add_material(white);
    scene.add_mesh(mesh.positions, {}, {}, mesh.triangles);
    return scene;
}

Scene suite_scene(const TriangleMesh& mesh) {
    Scene scene = uncommitted_scene(mesh);
    scene.commit();
    return scene;
}

std::vector<RaySet> make_ray_sets(const Scene& scene, const TriangleMesh& mesh, size_t count) {
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
    RaySet primary{"primary", {}};
    primary.rays.reserve(count);
    for (int y = 0; y < side && primary.rays.size() < count; ++y)
        for (int x = 0; x < side && primary.rays.size() < count; ++x)
            primary.rays.push_back(mesh.camera.generate_ray(x + 0.5f, y + 0.5f, side, side));

    std::vector<SurfaceInteraction> hits;
    for (const Ray& r : primary.rays)
        if (const auto h = scene.intersect(r)) hits.push_back(scene.interaction(r, *h));

    RaySet shadow{"shadow", {}}, diffuse{"diffuse", {}}, random{"random", {}};
    Rng rng(2026, 11, 22);
    for (size_t i = 0; !hits.empty() && shadow.rays.size() < count; ++i) {
        const SurfaceInteraction& si = hits[i % hits.size()];
        const SurfacePoint from{si.p, si.p_error, si.front_face() ? si.n_geo : -si.n_geo};
        shadow.rays.push_back(spawn_ray_to(from, mesh.light));
        const Frame frame(from.n);
        diffuse.rays.push_back(spawn_ray(
            from, frame.to_world(sample_cosine_hemisphere(Vec2(rng.uniform(), rng.uniform())))));
    }
    const Bounds3 box = scene.bounds();
    for (size_t i = 0; i < count; ++i) {
        const Vec3 u(rng.uniform(), rng.uniform(), rng.uniform());
        const Vec3 origin = box.min + u * (box.max - box.min);
        random.rays.push_back(
            Ray{origin, sample_uniform_sphere(Vec2(rng.uniform(), rng.uniform()))});
    }
    return {primary, shadow, diffuse, random};
}

}  // namespace lessons::bench
