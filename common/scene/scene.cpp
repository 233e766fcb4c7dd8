// Building a scene: its shapes and materials, then commit(): the BVH over every primitive, the
// area lights, the primitives in the BVH's order; and what it holds (lights(), contents(),
// geometry_bytes()). Its ray queries are in scene_queries.cpp.
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "accel/parallel.h"
#include "geometry/simd.h"

namespace lessons {

namespace {
// A box rounded outwards by one float step on every side (Scene::build_bvh).
Bounds3 rounded_outwards(const Bounds3& b) {
    const Float4 lo = -next_floats_up(-Float4{b.min.x, b.min.y, b.min.z, 0.0f});
    const Float4 hi = next_floats_up(Float4{b.max.x, b.max.y, b.max.z, 0.0f});
    return {Vec3(lo[0], lo[1], lo[2]), Vec3(hi[0], hi[1], hi[2])};
}
}  // namespace

void Scene::replace_material(uint32_t i, const Material& m) {
    if (m.emission != materials_.at(i).emission || m.two_sided != materials_[i].two_sided)
        throw std::logic_error("Scene::replace_material: the emission cannot change");
    materials_[i] = m;
}

uint32_t Scene::add_material(const Material& m) {
    materials_.push_back(m);
    return static_cast<uint32_t>(materials_.size() - 1);
}

void Scene::add_sphere(const Sphere& s, uint32_t material) {
    spheres_.push_back(s);
    sphere_materials_.push_back(material);
}

void Scene::add_quad(const Quad& q, uint32_t material) {
    quads_.push_back(q);
    quad_materials_.push_back(material);
}

void Scene::add_mesh(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                     const std::vector<Vec2>& uvs, const std::vector<Triangle>& triangles) {
    const uint32_t base = static_cast<uint32_t>(positions_.size());
    // Vertex attributes are stored only once some mesh has them; meshes without are padded.
    if (!normals.empty() || !normals_.empty()) {
        normals_.resize(base, Vec3(0.0f));
        if (normals.empty())
            normals_.resize(base + positions.size(), Vec3(0.0f));
        else
            normals_.insert(normals_.end(), normals.begin(), normals.end());
    }
    if (!uvs.empty() || !uvs_.empty()) {
        uvs_.resize(base, Vec2(0.0f));
        if (uvs.empty())
            uvs_.resize(base + positions.size(), Vec2(0.0f));
        else
            uvs_.insert(uvs_.end(), uvs.begin(), uvs.end());
    }
    positions_.insert(positions_.end(), positions.begin(), positions.end());
    // Room for exactly the first mesh's triangles (growing one at a time would leave up to half
    // the array unused: 10.8 bytes per triangle of the 10M mesh), geometrically for later ones.
    const size_t needed = triangles_.size() + triangles.size();
    if (needed > triangles_.capacity())
        triangles_.reserve(std::max(needed, 2 * triangles_.capacity()));
    for (Triangle t : triangles) {
        for (uint32_t& v : t.v) v += base;
        t.smooth = t.smooth && !normals.empty();
        triangles_.push_back(t);
    }
}

uint32_t Scene::material_of(PrimRef prim) const {
    switch (prim.kind()) {
        case ShapeKind::Sphere: return sphere_materials_[prim.index()];
        case ShapeKind::Quad: return quad_materials_[prim.index()];
        case ShapeKind::Triangle: return triangles_[prim.index()].material;
    }
    return 0;
}

Bounds3 Scene::primitive_bounds(PrimRef prim) const {
    switch (prim.kind()) {
        case ShapeKind::Sphere: return spheres_[prim.index()].bounds();
        case ShapeKind::Quad: return quads_[prim.index()].bounds();
        case ShapeKind::Triangle: {
            const Triangle& t = triangles_[prim.index()];
            Bounds3 b;
            for (uint32_t v : t.v) b.expand(positions_[v]);
            return b;
        }
    }
    return {};
}

void Scene::commit(int threads) {
    build_bvh(threads);
    collect_area_lights();
    store_in_bvh_order(threads);
}

void Scene::build_bvh(int threads) {
    prims_.clear();
    prims_.reserve(spheres_.size() + quads_.size() + triangles_.size());
    for (uint32_t i = 0; i < spheres_.size(); ++i) prims_.emplace_back(ShapeKind::Sphere, i);
    for (uint32_t i = 0; i < quads_.size(); ++i) prims_.emplace_back(ShapeKind::Quad, i);
    for (uint32_t i = 0; i < triangles_.size(); ++i) prims_.emplace_back(ShapeKind::Triangle, i);
    std::vector<Bounds3> boxes(prims_.size());
    parallel_parts(prims_.size(), threads, kMinBuildPart, [&](size_t begin, size_t end, int) {
        // Rounded outwards by one float step, so a hit computed in higher precision (spheres
        // are intersected in double) can never lie outside its box.
        for (size_t k = begin; k < end; ++k)
            boxes[k] = rounded_outwards(primitive_bounds(prims_[k]));
    });
    bvh_ = Bvh(boxes, threads);
}

AreaLight Scene::area_light_of(PrimRef p, uint32_t m) const {
    AreaLight light{
        p,          m,         materials_[m].emission, materials_[m].two_sided, 0.0f, Vec3(0.0f),
        Vec3(0.0f), Vec3(0.0f)};
    switch (p.kind()) {
        case ShapeKind::Sphere: {
            const Sphere& s = spheres_[p.index()];
            light.area = s.area();
            light.center = s.center;
            break;
        }
        case ShapeKind::Quad: {
            const Quad& q = quads_[p.index()];
            light.area = q.area();
            light.center = q.center();
            light.center_error =
                gamma_bound(4) * (glm::abs(q.corner) + glm::abs(q.edge_u) + glm::abs(q.edge_v));
            light.normal = q.normal;
            // Orthogonal to float precision (edges as given, or turned by a rotation).
            light.rectangle = std::fabs(glm::dot(q.edge_u, q.edge_v)) <=
                              1e-5f * glm::length(q.edge_u) * glm::length(q.edge_v);
            break;
        }
        case ShapeKind::Triangle: {
            const Triangle& t = triangles_[p.index()];
            const Vec3 &a = positions_[t.v[0]], &b = positions_[t.v[1]], &c = positions_[t.v[2]];
            const Vec3 n = glm::cross(b - a, c - a);
            light.area = 0.5f * glm::length(n);
            light.center = (a + b + c) / 3.0f;
            light.center_error = gamma_bound(4) * (glm::abs(a) + glm::abs(b) + glm::abs(c));
            light.normal = light.area > 0.0f ? glm::normalize(n) : Vec3(0.0f);
            break;
        }
    }
    return light;
}

void Scene::collect_area_lights() {
    area_lights_.clear();
    if (std::none_of(materials_.begin(), materials_.end(),
                     [](const Material& m) { return m.is_emissive(); }))
        return;  // no pass over the primitives in a scene without emission
    for (PrimRef p : prims_) {
        const uint32_t m = material_of(p);
        if (!materials_[m].is_emissive()) continue;
        const AreaLight light = area_light_of(p, m);
        if (light.area > 0.0f) area_lights_.push_back(light);
    }
}

// Store the primitives in the BVH's order, so that a leaf's primitives lie side by side, and the
// triangles' vertices with them, four to a block: a leaf's triangles are then tested four at once
// from one 144-byte block, instead of following indices to three vertices each
// (docs/performance.md).
void Scene::store_in_bvh_order(int threads) {
    const std::vector<uint32_t> order = bvh_.take_primitive_order();  // kept in prims_ below
    std::vector<PrimRef> ordered(order.size());
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const size_t blocks = (order.size() + 3) / 4;
    QuadBlock unused_quads;
    for (int axis = 0; axis < 3; ++axis)
        unused_quads.corner[axis] = unused_quads.normal[axis] = unused_quads.dual_u[axis] =
            unused_quads.dual_v[axis] = Float4{} + nan;
    TriangleBlock unused_triangles;
    for (auto& vertex : unused_triangles.p)
        for (Float4& axis : vertex) axis = Float4{} + nan;
    // Sized but not written (large_pages.h): the threads below write every block.
    quad_blocks_.clear();
    quad_blocks_.resize(quads_.empty() ? 0 : blocks);
    triangle_blocks_.clear();
    triangle_blocks_.resize(triangles_.empty() ? 0 : blocks);
    // Block by block, so that no two threads write one block.
    parallel_parts(blocks, threads, kMinBuildPart / 4, [&](size_t begin, size_t end, int) {
        for (size_t b = begin; b < end; ++b) {
            if (!quads_.empty()) quad_blocks_[b] = unused_quads;
            if (!triangles_.empty()) triangle_blocks_[b] = unused_triangles;
        }
        for (size_t k = 4 * begin; k < std::min(4 * end, order.size()); ++k) {
            if (order[k] == Bvh::kPadding) continue;  // gaps: never visited
            const PrimRef p = ordered[k] = prims_[order[k]];
            const int lane = static_cast<int>(k % 4);
            if (p.kind() == ShapeKind::Quad) {
                quad_blocks_[k / 4].set(lane, quads_[p.index()]);
            } else if (p.kind() == ShapeKind::Triangle) {
                const Triangle& t = triangles_[p.index()];
                triangle_blocks_[k / 4].set(lane, positions_[t.v[0]], positions_[t.v[1]],
                                            positions_[t.v[2]]);
            }
        }
    });
    prims_ = std::move(ordered);
}

size_t Scene::geometry_bytes() const {
    auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
    return bytes(spheres_) + bytes(sphere_materials_) + bytes(quads_) + bytes(quad_materials_) +
           bytes(positions_) + bytes(normals_) + bytes(uvs_) + bytes(triangles_) + bytes(prims_) +
           bytes(triangle_blocks_) + bytes(quad_blocks_) + bvh_.memory_bytes();
}

std::vector<LightRef> Scene::lights() const {
    std::vector<LightRef> lights;
    lights.reserve(point_lights_.size() + directional_lights_.size() + area_lights_.size() + 1);
    for (uint32_t i = 0; i < point_lights_.size(); ++i) lights.push_back({LightKind::Point, i});
    for (uint32_t i = 0; i < directional_lights_.size(); ++i)
        lights.push_back({LightKind::Directional, i});
    for (uint32_t i = 0; i < area_lights_.size(); ++i) lights.push_back({LightKind::Area, i});
    if (has_environment()) lights.push_back({LightKind::Environment, 0});
    return lights;
}

uint32_t Scene::add_medium(const Medium& m) {
    media_.push_back(m);
    return static_cast<uint32_t>(media_.size() - 1);
}

Scene::PrimitiveCounts Scene::primitive_counts() const {
    return {static_cast<uint32_t>(spheres_.size()), static_cast<uint32_t>(quads_.size()),
            static_cast<uint32_t>(triangles_.size())};
}

void Scene::set_interior(const PrimitiveCounts& before, uint32_t medium) {
    const PrimitiveCounts now = primitive_counts();
    if (now.spheres > before.spheres)
        interiors_.push_back({ShapeKind::Sphere, before.spheres, now.spheres, medium});
    if (now.quads > before.quads)
        interiors_.push_back({ShapeKind::Quad, before.quads, now.quads, medium});
    if (now.triangles > before.triangles)
        interiors_.push_back({ShapeKind::Triangle, before.triangles, now.triangles, medium});
}

std::optional<uint32_t> Scene::interior_of(PrimRef prim) const {
    for (const Interior& i : interiors_)
        if (i.kind == prim.kind() && prim.index() >= i.first && prim.index() < i.end)
            return i.medium;
    return std::nullopt;
}

std::vector<int> Scene::shapes_inside_each_medium() const {
    std::vector<int> shapes(media_.size(), 0);
    for (const Interior& i : interiors_) ++shapes[i.medium];
    return shapes;
}

std::string Scene::media_summary() const {
    const std::vector<int> shapes_inside = shapes_inside_each_medium();
    auto colour = [](const Color& c) {
        std::ostringstream s;
        s << "[" << c.x << ", " << c.y << ", " << c.z << "]";
        return s.str();
    };
    std::string out;
    for (uint32_t k = 0; k < media_.size(); ++k) {
        const Medium& m = media_[k];
        const bool outside = outside_medium_ == k;
        if (m.is_vacuum() || (!outside && shapes_inside[k] == 0)) continue;
        std::ostringstream s;
        s << m.name << " (";
        if (outside) s << "fills space";
        if (outside && shapes_inside[k] > 0) s << " and ";
        // Each shape with an interior added one range (a shape adds primitives of one kind).
        if (shapes_inside[k] > 0) s << "inside " << shapes_inside[k] << " shape(s)";
        s << ": sigma_a " << colour(m.sigma_a) << ", sigma_s " << colour(m.sigma_s)
          << " per unit length, g " << m.g << ")";
        if (!out.empty()) out += "; ";
        out += s.str();
    }
    return out;
}

SceneContents Scene::contents() const {
    SceneContents c;
    for (const LightRef& light : lights()) {
        switch (light.kind) {
            case LightKind::Point: {
                c.point_lights = true;
                const PointLight& l = point_lights_[light.index];
                const Vec3 d = l.position - camera.position();
                // In the image, and (a spot) sending some light towards the camera.
                if (glm::dot(d, d) > 0.0f && !is_black(l.intensity_towards(-glm::normalize(d))))
                    c.point_light_in_view |=
                        camera.raster_position(glm::normalize(d), width, height).has_value();
                break;
            }
            case LightKind::Directional: c.directional_lights = true; break;
            case LightKind::Area: c.area_lights = true; break;
            case LightKind::Environment: c.environment = true; break;
        }
    }
    auto delta = [&](uint32_t m) { return facts_of(materials_[m].type).delta; };
    for (uint32_t m : sphere_materials_) c.delta_materials |= delta(m);
    for (uint32_t m : quad_materials_) c.delta_materials |= delta(m);
    for (const Triangle& t : triangles_) c.delta_materials |= delta(t.material);
    const std::vector<int> shapes_inside = shapes_inside_each_medium();
    for (uint32_t k = 0; k < media_.size(); ++k)
        c.media |= !media_[k].is_vacuum() && (outside_medium_ == k || shapes_inside[k] > 0);
    return c;
}

}  // namespace lessons
