// bench_bvh's scenes and rays (bench_bvh.cpp): triangles only, so that both libraries see exactly
// the same geometry, and the four sets of rays traced through them.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace lessons::bench {

// A mesh of triangles, a camera looking at it and a light casting its shadows.
struct TriangleMesh {
    std::string name;
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
    Camera camera;
    Vec3 light;  // a point light for the shadow rays
};

// The Cornell box of the scene file at `path`, its quads as two triangles each.
TriangleMesh cornell_box_mesh(const std::string& path);
// A cube subdivided n x n per face, pushed onto the unit sphere and displaced along its normal
// by a sum of sines: 12 n^2 triangles, none degenerate, with bumps that shadow each other.
TriangleMesh displaced_sphere(int n);

// The mesh as a scene, before commit() builds its BVH.
Scene uncommitted_scene(const TriangleMesh& mesh);
// The mesh as a scene, its BVH built.
Scene suite_scene(const TriangleMesh& mesh);

// A set of rays, by name: primary, shadow, diffuse or random.
struct RaySet {
    std::string name;
    std::vector<Ray> rays;
};

// `count` rays of each set through the mesh's scene: primary rays from its camera, shadow rays
// to its light and cosine-distributed diffuse rays from the primary hits, and uniformly random
// rays from inside its bounds.
std::vector<RaySet> make_ray_sets(const Scene& scene, const TriangleMesh& mesh, size_t count);

}  // namespace lessons::bench
