// The scene: shapes, materials, lights, camera and the BVH over all shapes.
//
// Shapes are kept in one array per kind (spheres, quads, triangles), so a scene of spheres pays
// only for spheres; a primitive is named by a PrimRef (kind and index). Lessons ask two
// questions of a scene: the nearest hit along a ray (intersect) and whether anything lies on a
// segment (occluded). The full description of a hit (interaction) is computed once, for the
// nearest hit only. The lights it holds are plain data, in light_types.h; building a scene is in
// scene.cpp, its queries in scene_queries.cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "accel/bvh.h"
#include "geometry/interaction.h"
#include "geometry/math.h"
#include "geometry/shapes.h"
#include "geometry/spawn.h"
#include "materials/material.h"
#include "media/medium.h"
#include "scene/camera.h"
#include "scene/environment.h"
#include "scene/light_types.h"

namespace lessons {

// One triangle of a mesh: three indices into the scene's vertex arrays.
// 16 bytes: the flag shares the material's word (a scene cannot hold 2^31 materials).
struct Triangle {
    uint32_t v[3];
    uint32_t material : 31;
    uint32_t smooth : 1;  // interpolate the vertex normals for shading
};
static_assert(sizeof(Triangle) == 16);

// The naive methods that the robust ones replace, kept so their failures can be shown
// (docs/robustness.md; the --naive flag). All off by default.
struct NaiveMethods {
    float fixed_epsilon = 0.0f;          // > 0: spawned rays start this far off the surface, at the
                                         // point o + t d, instead of beyond its rounding error
    bool textbook_quadratic = false;     // spheres by b^2 - 4ac in single precision
    bool moller_trumbore = false;        // triangles by Moller-Trumbore, not watertight
    bool side_by_dot = false;            // the side a ray hits from dot(d, n), not the hit test
    bool raw_shading_normals = false;    // no fallback when the viewer is below the shading normal
    bool light_abs_cosine = false;       // next-event estimation with |cos| at one-sided lights
    bool no_adjoint_correction = false;  // lesson 5's light subpaths with the camera side's BSDF
                                         // (no adjoint shading-normal correction)
    bool any() const {
        return fixed_epsilon > 0.0f || textbook_quadratic || moller_trumbore || side_by_dot ||
               raw_shading_normals || light_abs_cosine || no_adjoint_correction;
    }
};

// What a scene holds, as far as a lesson's model cares (for its notes and its bias).
struct SceneContents {
    bool point_lights = false;  // point and spot lights
    bool directional_lights = false;
    bool area_lights = false;
    bool environment = false;          // a background of nonzero radiance
    bool delta_materials = false;      // a mirror or glass on some shape
    bool point_light_in_view = false;  // a point light the camera sees (unless something hides it)
    bool media = false;  // a medium that is not a vacuum fills space or a shape's interior
};

// Rays traced by the calling thread since it started: the render loop reads the difference.
uint64_t rays_traced_by_this_thread();

class Scene {
public:
    // ---- building ----
    uint32_t add_material(const Material& m);
    void add_sphere(const Sphere& s, uint32_t material);
    void add_quad(const Quad& q, uint32_t material);
    // Appends vertices and triangles. normals: empty, or one unit normal per position.
    // uvs: empty, or one per position. Triangles index the given positions from 0.
    void add_mesh(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                  const std::vector<Vec2>& uvs, const std::vector<Triangle>& triangles);
    void add_point_light(const PointLight& l) { point_lights_.push_back(l); }
    void add_directional_light(const DirectionalLight& l) { directional_lights_.push_back(l); }
    // Media: the one that fills all space outside the shapes' interiors (the camera's), and the
    // one inside each closed shape that has one (docs/scene-format.md, "Media").
    uint32_t add_medium(const Medium& m);
    void set_outside_medium(uint32_t medium) { outside_medium_ = medium; }
    // How many primitives of each kind the scene holds: before adding a shape, to say afterwards
    // that the primitives it added enclose a medium (set_interior).
    struct PrimitiveCounts {
        uint32_t spheres = 0, quads = 0, triangles = 0;
    };
    PrimitiveCounts primitive_counts() const;
    void set_interior(const PrimitiveCounts& before, uint32_t medium);
    // Replaces material i's reflectance parameters. Its emission must stay as it was: the area
    // lights were collected from it (--albedo changes only reflectances).
    void replace_material(uint32_t i, const Material& m);
    // Builds the BVH and the list of area lights. Call once, after adding every shape.
    // threads: how many may build the BVH (0: every hardware thread); the result is the same.
    void commit(int threads = 0);

    // ---- queries ----
    std::optional<Hit> intersect(const Ray& ray) const;
    // Whether anything blocks the segment. `target`: the primitive the segment ends on (an area
    // light), which cannot block it: offsets alone cannot guarantee that when the segment is
    // much longer than the light's coordinates are large.
    bool occluded(const Ray& ray, std::optional<PrimRef> target = std::nullopt) const;
    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const;
    // Whether the ray meets primitive `prim` anywhere in (0, ray.t_max), on either side, whatever
    // lies in front of it: one shape test, no BVH (lesson 5 asks whether a pixel's corners all
    // meet a lamp). Always the robust tests (--naive does not apply); not counted as a ray.
    bool meets(PrimRef prim, const Ray& ray) const;
    // Emitted radiance L_e(p, wo) leaving the hit point towards wo.
    Color emitted(const SurfaceInteraction& si) const;

    // ---- contents ----
    const std::vector<Material>& materials() const { return materials_; }
    const Material& material(uint32_t i) const { return materials_[i]; }
    const std::vector<PointLight>& point_lights() const { return point_lights_; }
    const std::vector<DirectionalLight>& directional_lights() const { return directional_lights_; }
    const std::vector<AreaLight>& area_lights() const { return area_lights_; }
    // Every light, in one order: the point lights, the directional lights, the area lights (found
    // by commit()), then the environment if there is one (has_environment()). The light sampler's
    // choice and lesson 1's sum over lights follow this order.
    std::vector<LightRef> lights() const;
    const std::vector<Sphere>& spheres() const { return spheres_; }
    const std::vector<Quad>& quads() const { return quads_; }
    const std::vector<Triangle>& triangles() const { return triangles_; }
    const std::vector<Vec3>& positions() const { return positions_; }
    const std::vector<Vec3>& normals() const { return normals_; }  // empty, or one per position
    const std::vector<Vec2>& uvs() const { return uvs_; }          // empty, or one per position
    const Bvh& bvh() const { return bvh_; }
    size_t primitive_count() const { return spheres_.size() + quads_.size() + triangles_.size(); }
    // The primitive at position k of the BVH's order (bvh.h), or a sphere 0 in the gaps before
    // aligned leaves, which no query visits. Positions run from 0 to primitive_slots() - 1.
    PrimRef primitive_at(size_t k) const { return prims_[k]; }
    size_t primitive_slots() const { return prims_.size(); }
    uint32_t material_of(PrimRef prim) const;
    Bounds3 primitive_bounds(PrimRef prim) const;
    Bounds3 bounds() const { return bvh_.bounds(); }
    // Bytes held for intersection: shapes, vertices, triangles and the BVH (not materials).
    size_t geometry_bytes() const;
    // The kinds of lights, whether any shape has a delta material (mirror, glass), and whether
    // the scene has media.
    SceneContents contents() const;
    const std::vector<Medium>& media() const { return media_; }
    std::optional<uint32_t> outside_medium() const { return outside_medium_; }
    // The medium inside the closed shape that primitive `prim` belongs to, if it has one.
    std::optional<uint32_t> interior_of(PrimRef prim) const;
    // The media in use, each named with where it is and its coefficients, for notes (empty
    // without media).
    std::string media_summary() const;

    // ---- what is seen and how ----
    Camera camera;
    int width = 0, height = 0;
    Color background{0.0f};  // radiance of every ray that escapes the scene (without a map)
    // Or, when set, the radiance an escaping ray sees depends on its direction.
    std::shared_ptr<const EnvironmentMap> environment_map;
    // What a ray escaping along unit direction `dir` sees.
    Color background_radiance(const Vec3& dir) const {
        return environment_map ? environment_map->radiance(dir) : background;
    }
    bool has_environment() const { return environment_map || !is_black(background); }
    NaiveMethods naive;  // for demonstrations only
    std::string source;  // the file it came from, for messages and reports
    // Every file it was made of, each once, in the order loading read them: the scene file,
    // meshes and their MTL files, textures, the environment map, glTF files and the buffers and
    // images they name. What the farm's scene hash and the studio's reference cache key cover.
    std::vector<std::string> input_files;
    // What loading approximated or ignored (a glTF file's materials, its camera): every lesson
    // adds these to its notes.
    std::vector<std::string> notes;

private:
    // The three steps of commit(): the BVH over every primitive's box; the area lights (one per
    // emissive primitive of nonzero area); the primitives and their SIMD blocks in BVH order.
    void build_bvh(int threads);
    void collect_area_lights();
    void store_in_bvh_order(int threads);
    // Build steps give each thread at least this many primitives (accel/parallel.h).
    static constexpr size_t kMinBuildPart = 16384;
    AreaLight area_light_of(PrimRef p, uint32_t material) const;
    // How many shapes hold each medium as their interior.
    std::vector<int> shapes_inside_each_medium() const;

    // Tests the primitive at position k of the BVH's order.
    bool intersect_primitive(uint32_t k, const Ray& ray, const WatertightRay& wr, float t_max,
                             ShapeHit& hit) const;

    // What every leaf of one ray's query needs, prepared once per ray: the ray's shear frame for
    // the watertight triangle test (three divisions: only scenes with triangles pay for it), and
    // which kinds of tests the leaves need.
    struct RayTests {
        WatertightRay wr;
        bool triangle_blocks;  // triangles four at once (not under --naive moller-trumbore)
        bool quad_blocks;      // quads four at once
        bool single_tests;     // spheres, or triangles under --naive moller-trumbore
    };
    RayTests ray_tests(const Ray& ray) const;

    // Tests the primitives of one BVH leaf, positions [first, end), within (0, t_max); calls
    // on_hit(k, hit) for each hit found, and stops when it returns true. A closest-hit query's
    // on_hit lowers t_max to the hit's distance.
    template <class OnHit>
    bool intersect_leaf(const RayTests& tests, uint32_t first, uint32_t end, const Ray& ray,
                        float& t_max, OnHit&& on_hit) const;

    std::vector<Material> materials_;
    std::vector<Sphere> spheres_;
    std::vector<uint32_t> sphere_materials_;
    std::vector<Quad> quads_;
    std::vector<uint32_t> quad_materials_;
    std::vector<Vec3> positions_;
    std::vector<Vec3> normals_;  // empty, or one per position
    std::vector<Vec2> uvs_;      // empty, or one per position
    std::vector<Triangle> triangles_;
    std::vector<PrimRef> prims_;                      // in the BVH's primitive order
    LargePageVector<TriangleBlock> triangle_blocks_;  // vertices of positions 4b..4b+3; empty
                                                      // without triangles; other lanes NaN
    LargePageVector<QuadBlock> quad_blocks_;          // the same for quads

    std::vector<PointLight> point_lights_;
    std::vector<DirectionalLight> directional_lights_;

    // The media, and which primitives enclose which (a range of one kind per shape: a scene
    // without interiors pays nothing per primitive).
    struct Interior {
        ShapeKind kind;
        uint32_t first, end;  // indices into the kind's array
        uint32_t medium;
    };
    std::vector<Medium> media_;
    std::optional<uint32_t> outside_medium_;
    std::vector<Interior> interiors_;
    std::vector<AreaLight> area_lights_;
    Bvh bvh_;
};

}  // namespace lessons
