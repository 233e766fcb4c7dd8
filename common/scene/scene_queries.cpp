// The scene's ray queries: the nearest hit along a ray and whether a segment is blocked (through
// the BVH, each leaf's shapes tested four at once where they can be), one primitive's test
// (meets), the description of a hit (interaction) and the light it emits (emitted). Building the
// scene is in scene.cpp.
#include <bit>
#include <cmath>

#include "geometry/simd.h"
#include "scene/scene.h"

namespace lessons {

namespace {
// Rays traced by this thread: intersect() and occluded() count one each.
thread_local uint64_t t_rays_traced = 0;
}  // namespace

uint64_t rays_traced_by_this_thread() {
    return t_rays_traced;
}

[[gnu::always_inline]] inline bool Scene::intersect_primitive(uint32_t k, const Ray& ray,
                                                              const WatertightRay& wr, float t_max,
                                                              ShapeHit& hit) const {
    const PrimRef prim = prims_[k];
    switch (prim.kind()) {
        case ShapeKind::Sphere: {
            Ray r = ray;
            r.t_max = t_max;
            return naive.textbook_quadratic ? intersect_sphere_naive(spheres_[prim.index()], r, hit)
                                            : intersect_sphere(spheres_[prim.index()], r, hit);
        }
        case ShapeKind::Quad: break;  // always four at once, by QuadBlock
        case ShapeKind::Triangle: {
            const TriangleBlock& block = triangle_blocks_[k / 4];
            const int lane = static_cast<int>(k % 4);
            const Vec3 p0 = block.vertex(lane, 0), p1 = block.vertex(lane, 1),
                       p2 = block.vertex(lane, 2);
            if (naive.moller_trumbore) {
                Ray r = ray;
                r.t_max = t_max;
                return intersect_triangle_moller_trumbore(r, p0, p1, p2, hit);
            }
            return intersect_triangle(wr, p0, p1, p2, t_max, hit);
        }
    }
    return false;
}

Scene::RayTests Scene::ray_tests(const Ray& ray) const {
    const bool triangle_blocks = !triangle_blocks_.empty() && !naive.moller_trumbore;
    return {triangles_.empty() ? WatertightRay() : WatertightRay(ray), triangle_blocks,
            !quad_blocks_.empty(), !spheres_.empty() || (!triangles_.empty() && !triangle_blocks)};
}

template <class OnHit>
bool Scene::intersect_leaf(const RayTests& tests, uint32_t first, uint32_t end, const Ray& ray,
                           float& t_max, OnHit&& on_hit) const {
    const WatertightRay& wr = tests.wr;
    bool hit_any = false;
    ShapeHit h;
    // Leaves start at multiples of four and hold at most four: one block of each kind.
    static_assert(Bvh::kLeafAlignment == 4 && Bvh::kMaxLeafSize <= 4);
    const unsigned lanes = (1u << (end - first)) - 1u;
    if (tests.triangle_blocks) {
        // The leaf's triangles, four at once; a lane with an edge function of exactly zero is
        // decided by the scalar test, which re-evaluates it in double.
        const TriangleBlock& block = triangle_blocks_[first / 4];
        TriangleHits4 th;
        unsigned recheck;
        for (unsigned m = block.intersect(wr, t_max, th, recheck) & lanes; m != 0; m &= m - 1) {
            const int lane = std::countr_zero(m);
            // Beyond a hit found in this leaf meanwhile? (By distance: the scalar test compares
            // t_scaled with t_max det, which can differ in the last bit on near-ties.)
            if (!(th.t[lane] < t_max)) continue;
            h = {th.t[lane], th.u[lane], th.v[lane], th.det[lane] > 0.0f};
            hit_any = true;
            if (on_hit(first + lane, h)) return true;
        }
        for (unsigned m = recheck & lanes; m != 0; m &= m - 1) {
            const int lane = std::countr_zero(m);
            if (!intersect_triangle(wr, block.vertex(lane, 0), block.vertex(lane, 1),
                                    block.vertex(lane, 2), t_max, h))
                continue;
            hit_any = true;
            if (on_hit(first + lane, h)) return true;
        }
    }
    if (tests.quad_blocks) {
        // The leaf's quads, four at once, with exactly intersect_quad's arithmetic.
        QuadTerms<Float4> q;
        for (unsigned m = quad_blocks_[first / 4].intersect(ray, t_max, q) & lanes; m != 0;
             m &= m - 1) {
            const int lane = std::countr_zero(m);
            if (!(q.t[lane] < t_max)) continue;  // beyond a hit found in this leaf meanwhile
            h = {q.t[lane], q.a[lane], q.b[lane], q.denom[lane] < 0.0f};
            hit_any = true;
            if (on_hit(first + lane, h)) return true;
        }
    }
    // One by one: spheres, and triangles under --naive moller-trumbore.
    if (!tests.single_tests) return hit_any;
    for (uint32_t k = first; k < end; ++k) {
        const ShapeKind kind = prims_[k].kind();
        if (kind == ShapeKind::Quad || (tests.triangle_blocks && kind == ShapeKind::Triangle))
            continue;
        if (!intersect_primitive(k, ray, wr, t_max, h)) continue;
        hit_any = true;
        if (on_hit(k, h)) return true;
    }
    return hit_any;
}

std::optional<Hit> Scene::intersect(const Ray& ray) const {
    ++t_rays_traced;
    const RayTests tests = ray_tests(ray);
    ShapeHit best;
    uint32_t best_k = 0;  // its position in the primitive order: prims_ is read once, at the end
    const bool found = bvh_.closest_hit(ray, [&](uint32_t first, uint32_t end, float& t_max) {
        return intersect_leaf(tests, first, end, ray, t_max, [&](uint32_t k, const ShapeHit& h) {
            t_max = h.t;  // nearer hits only from now on
            best = h;
            best_k = k;
            return false;
        });
    });
    if (!found) return std::nullopt;
    return Hit{best, prims_[best_k]};
}

bool Scene::meets(PrimRef prim, const Ray& ray) const {
    ShapeHit hit;
    switch (prim.kind()) {
        case ShapeKind::Sphere: return intersect_sphere(spheres_[prim.index()], ray, hit);
        case ShapeKind::Quad: return intersect_quad(quads_[prim.index()], ray, hit);
        case ShapeKind::Triangle: {
            const Triangle& tri = triangles_[prim.index()];
            return intersect_triangle(WatertightRay(ray), positions_[tri.v[0]],
                                      positions_[tri.v[1]], positions_[tri.v[2]], ray.t_max, hit);
        }
    }
    return false;
}

bool Scene::occluded(const Ray& ray, std::optional<PrimRef> target) const {
    ++t_rays_traced;
    const RayTests tests = ray_tests(ray);
    return bvh_.any_hit(ray, [&](uint32_t first, uint32_t end) {
        bool blocked = false;
        float t_max = ray.t_max;
        intersect_leaf(tests, first, end, ray, t_max, [&](uint32_t k, const ShapeHit&) {
            blocked = !(target && prims_[k] == *target);
            return blocked;  // stop at the first blocker
        });
        return blocked;
    });
}

SurfaceInteraction Scene::interaction(const Ray& ray, const Hit& hit) const {
    SurfaceGeometry g;
    switch (hit.prim.kind()) {
        case ShapeKind::Sphere:
            g = sphere_surface(spheres_[hit.prim.index()], ray, hit.shape);
            break;
        case ShapeKind::Quad: g = quad_surface(quads_[hit.prim.index()], hit.shape); break;
        case ShapeKind::Triangle: {
            const Triangle& t = triangles_[hit.prim.index()];
            const float b1 = hit.shape.u, b2 = hit.shape.v, b0 = 1.0f - b1 - b2;
            const Vec3 &p0 = positions_[t.v[0]], &p1 = positions_[t.v[1]], &p2 = positions_[t.v[2]];
            // Barycentric interpolation: the point's error is bounded by the vertices', not by
            // the length of the ray.
            g.p = b0 * p0 + b1 * p1 + b2 * p2;
            g.p_error =
                gamma_bound(7) * (glm::abs(b0 * p0) + glm::abs(b1 * p1) + glm::abs(b2 * p2));
            g.n_geo = glm::normalize(glm::cross(p1 - p0, p2 - p0));
            g.n_shading = g.n_geo;
            if (t.smooth) {
                const Vec3 n =
                    b0 * normals_[t.v[0]] + b1 * normals_[t.v[1]] + b2 * normals_[t.v[2]];
                const float len = glm::length(n);
                if (len > 0.0f && std::isfinite(len)) {
                    g.n_shading = n / len;
                    // Keep the shading normal on the geometric normal's side.
                    if (glm::dot(g.n_shading, g.n_geo) < 0.0f) g.n_shading = -g.n_shading;
                }
            }
            g.uv = uvs_.empty() ? Vec2(b1, b2)
                                : b0 * uvs_[t.v[0]] + b1 * uvs_[t.v[1]] + b2 * uvs_[t.v[2]];
            break;
        }
    }
    SurfaceInteraction si;
    si.p = g.p;
    si.p_error = g.p_error;
    if (naive.fixed_epsilon > 0.0f) {
        // The textbook way: the hit at o + t d, moved off by a fixed distance (about epsilon).
        si.p = ray.at(hit.shape.t);
        si.p_error = Vec3(naive.fixed_epsilon / 1.5f);
    }
    si.n_geo = g.n_geo;
    si.n_shading = g.n_shading;
    si.uv = g.uv;
    si.wo = -glm::normalize(ray.dir);
    si.t = hit.shape.t;
    si.material = material_of(hit.prim);
    si.prim = hit.prim;
    si.front = hit.shape.front;
    // The textbook way: the side from the sign of a dot product, which a grazing ray can flip.
    if (naive.side_by_dot) si.front = glm::dot(ray.dir, g.n_geo) < 0.0f;
    si.shading_fallback = !naive.raw_shading_normals;
    return si;
}

Color Scene::emitted(const SurfaceInteraction& si) const {
    const Material& m = materials_[si.material];
    if (!m.is_emissive()) return Color(0.0f);
    if (!m.two_sided && !si.front_face()) return Color(0.0f);
    return m.emission;
}

}  // namespace lessons
