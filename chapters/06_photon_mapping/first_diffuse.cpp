// Lesson 6, section 6: the camera path to its first non-delta vertex (see first_diffuse.h).
#include "06_photon_mapping/first_diffuse.h"

namespace lessons {

Vertex camera_side_vertex(const SurfaceInteraction& si, const Bsdf& bsdf, const Color& beta) {
    Vertex v;
    v.type = VertexType::Surface;
    v.si = si;
    v.p = si.p;
    v.n = si.n_geo;
    v.bsdf = bsdf;
    v.beta = beta;
    return v;
}

FirstDiffuse first_diffuse_vertex(const Bidir& b, const Ray& camera_ray, Rng& rng,
                                  const BidirOptions& paths) {
    const Scene& scene = b.scene;
    const int longest = longest_path(paths.max_depth);
    FirstDiffuse walk;
    Color beta(1.0f);
    Ray ray = camera_ray;
    for (int segments = 1; segments <= longest; ++segments) {
        const std::optional<Hit> hit = scene.intersect(ray);
        if (!hit) {  // the sky, seen directly or in mirrors and glass
            walk.emitted += beta * scene.background_radiance(ray.dir);
            break;
        }
        const SurfaceInteraction si = scene.interaction(ray, *hit);
        walk.emitted += beta * scene.emitted(si);  // a lamp, seen directly or in mirrors and glass
        const Bsdf bsdf(scene.material(si.material), si);
        if (!bsdf.is_delta()) {
            walk.x = camera_side_vertex(si, bsdf, beta);
            walk.segments = segments;
            break;
        }
        // A mirror or glass: on along its direction, beta *= f cos / p (lesson 4's step).
        const std::optional<BsdfSample> s = bsdf.sample(si.wo, rng.uniform2());
        if (!s) break;
        beta *= s->f * bsdf.abs_cos(s->wi) / s->pdf;
        if (is_black(beta) || !is_finite(beta)) break;
        if (paths.roulette_after >= 0 && segments > paths.roulette_after) {
            const float q = russian_roulette_survival(beta);
            if (rng.uniform() >= q) break;
            beta /= q;
        }
        ray = spawn_ray(si.surface_point(), s->wi);
    }
    return walk;
}

}  // namespace lessons
