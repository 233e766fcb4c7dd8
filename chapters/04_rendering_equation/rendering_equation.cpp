// Lesson 4: path tracing the rendering equation (see rendering_equation.h).
#include "rendering_equation.h"

#include <algorithm>

#include "bsdf.h"
#include "sampling.h"

namespace lessons {

namespace {

// The density, per unit area at `to` (unit geometric normal n_to), of reaching it along a
// direction sampled at `from` with solid-angle density pdf_dir (lights.h's conversion). The
// weights below multiply two such densities, in double.
double area_density(float pdf_dir, const Vec3& from, const Vec3& to, const Vec3& n_to) {
    const Vec3 d = to - from;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) return 0.0;
    return solid_angle_to_area_pdf(pdf_dir, d2, glm::dot(n_to, d) / std::sqrt(d2));
}

// A camera-path vertex X, as the weights of the vertices after it need it.
struct PathVertex {
    Vec3 p{0.0f}, n{0.0f};  // position and unit geometric normal
    float pdf_next = 0.0f;  // solid-angle density of the direction sampled there, towards Y
    bool connects = false;  // the light path could have been connected to it
};

// A path's last two segments X -> Y -> q, q on a light, can come from three strategies; their
// densities per unit area of Y and of q (the path before X is common to all and cancels):
struct LastSegments {
    double bsdf;        // BSDF sampling at X, then at Y, whose ray hits the light
    double next_event;  // BSDF sampling at X, next-event estimation at Y
    double light_path;  // a light path q -> Y, connected to X
};
// pdf_bsdf and pdf_next_event: the solid-angle densities at Y of the direction Y -> q.
LastSegments last_segments(const LightSampler& lights, const PathVertex& x, const Vec3& y,
                           const Vec3& n_y, float pdf_bsdf, float pdf_next_event, PrimRef light,
                           const Vec3& q, const Vec3& n_q) {
    if (!x.connects) return {pdf_bsdf, pdf_next_event, 0.0};  // Y's two: X's density cancels
    const double x_to_y = area_density(x.pdf_next, x.p, y, n_y);
    const double y_to_q = area_density(1.0f, y, q, n_q);
    if (!(y_to_q > 0.0)) return {0.0, 0.0, 0.0};  // q = Y, or seen edge-on: no strategy
    // The light path: q by the light's density per area, then the direction q -> Y.
    const LightSampler::EmissionPdf e = lights.emission_pdf(light, n_q, glm::normalize(y - q));
    return {x_to_y * pdf_bsdf * y_to_q, x_to_y * pdf_next_event * y_to_q,
            e.area * area_density(e.dir, q, y, n_y)};
}

}  // namespace

std::optional<LightVertex> trace_light_path(const Scene& scene, const LightSampler& lights,
                                            Rng& rng) {
    const float u_choose = rng.uniform();
    const Vec2 u_point{rng.uniform(), rng.uniform()}, u_dir{rng.uniform(), rng.uniform()};
    const std::optional<EmissionSample> e = lights.sample_emission(u_choose, u_point, u_dir);
    if (!e) return std::nullopt;
    const std::optional<Hit> hit = scene.intersect(e->ray);
    if (!hit) return std::nullopt;
    LightVertex v;
    v.y = scene.interaction(e->ray, *hit);
    // A mirror or glass Y reflects into one direction only, which a connection never meets.
    if (Bsdf(scene.material(v.y.material), v.y).is_delta()) return std::nullopt;
    // L_e leaves q along the ray; times cos(theta_q) and divided by the densities of q and of
    // the direction, it is the light path's throughput, the light-side counterpart of beta.
    const float cos_q = glm::dot(e->normal, e->ray.dir);
    v.beta = e->radiance * (cos_q / (e->pdf_area * e->pdf_dir));
    v.emitter = e->emitter;
    v.q = e->point;
    v.n_q = e->normal;
    // The density next-event estimation at Y has of choosing q (for the weights).
    v.pdf_next_event = lights.pdf(v.y.p, v.emitter, v.q, v.n_q);
    return v;
}

Color connect_light_vertex(const Scene& scene, const LightSampler& lights,
                           const SurfaceInteraction& x, const Bsdf& bsdf_x, const LightVertex& lv) {
    const SurfaceInteraction& y = lv.y;
    const Vec3 d = y.p - x.p;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) return Color(0.0f);
    const Vec3 w = d / std::sqrt(d2);  // X -> Y
    const Color f_x = bsdf_x.eval(x.wo, w);
    if (is_black(f_x)) return Color(0.0f);
    // Y's BSDF as the camera path would see it, arriving from X.
    SurfaceInteraction y_from_x = y;
    y_from_x.wo = -w;
    y_from_x.front = glm::dot(y.n_geo, -w) > 0.0f;
    const Bsdf bsdf_y(scene.material(y.material), y_from_x);
    const Vec3& to_q = y.wo;
    const Color f_y = bsdf_y.eval(-w, to_q);
    const float cos_y_q = std::fabs(glm::dot(y.n_geo, to_q));  // against the geometric normal
    if (is_black(f_y) || !(cos_y_q > 0.0f)) return Color(0.0f);
    // Weighted against the two camera-path strategies for the same last two segments.
    const LastSegments p =
        last_segments(lights, {x.p, x.n_geo, bsdf_x.pdf(x.wo, w), true}, y.p, y.n_geo,
                      bsdf_y.pdf(-w, to_q), lv.pdf_next_event, lv.emitter, lv.q, lv.n_q);
    const float weight = power_heuristic(p.light_path, p.bsdf, p.next_event);
    if (!(weight > 0.0f)) return Color(0.0f);
    // Y's own surface cannot block the segment (X and q are on the same side of it, else f_Y
    // would be 0), and must not be asked: the segment ends just off it, and a triangle test near
    // t = 1 found it blocked often enough to darken a wall by 4%
    // (RenderingEquation.LightPathsSeeInterpolatedNormalsAsCameraPathsDo). As next-event
    // estimation's shadow rays ignore the light they end on.
    if (scene.occluded(spawn_ray_between(x.surface_point(), y.surface_point()), y.prim))
        return Color(0.0f);
    // f_X cos_X G(X, Y) f_Y, times the light path's throughput. G(X, Y) = cos_X cos_Y / d^2 has
    // its cos_X in f_X's cosine (shading normal). At Y, the camera path's integrand has f_Y times
    // cos against the shading normal towards q, while the light path's density gave the
    // geometric one: their ratio, 1 on flat surfaces, makes the two integrands the same.
    return weight * f_x * bsdf_x.abs_cos(w) * (std::fabs(glm::dot(y.n_geo, w)) / d2) * f_y *
           (bsdf_y.abs_cos(to_q) / cos_y_q) * lv.beta;
}

Color path_trace(const Scene& scene, const LightSampler& lights, const Ray& camera_ray, Rng& rng,
                 const PathOptions& options, std::span<Color> bounces) {
    Color L(0.0f);
    // Adds light that has bounced `k` times: to the total, and to its layer.
    auto add = [&](int k, const Color& contribution) {
        L += contribution;
        if (!bounces.empty()) bounces[std::min<size_t>(k, bounces.size() - 1)] += contribution;
    };
    // Light paths: one per camera path, its five numbers drawn first (so that the camera path's
    // numbers do not depend on whether it is traced), traced when a vertex first connects.
    const bool light_paths = options.light_paths && options.next_event;
    Rng light_rng = rng;
    if (light_paths)
        for (int i = 0; i < 5; ++i) rng.uniform();
    bool light_path_traced = false;
    std::optional<LightVertex> light_path;  // none if it found no surface to join
    // The longest path any strategy may make: the depth limit, or the safety cut.
    const int longest = options.max_depth > 0 ? options.max_depth : kLongestPath;

    Color beta(1.0f);  // path throughput: product of f cos / p along the path so far
    Ray ray = camera_ray;
    bool specular = true;          // the last direction came from a delta BSDF (or the camera)
    PathVertex last, before_last;  // the vertex the ray left (Y below), and the one before (X)
    for (int bounce = 0;; ++bounce) {
        const int segments = bounce + 1;  // this ray is the path's segment number `segments`
        const std::optional<Hit> hit = scene.intersect(ray);

        // E: emission found by this ray. Weighted against light sampling when NEE could have
        // found the same light from the previous vertex (its BSDF was not a delta), and against
        // the light path when the vertex before that could have been connected to it.
        const bool weigh = options.next_event && !specular;
        if (!hit) {
            const float w = weigh ? power_heuristic(last.pdf_next, lights.environment_pdf()) : 1.0f;
            if (!is_black(scene.background)) add(bounce, w * beta * scene.background);
            break;
        }
        const SurfaceInteraction si = scene.interaction(ray, *hit);
        const Color Le = scene.emitted(si);
        if (!is_black(Le)) {
            float w = 1.0f;
            if (weigh) {
                const LastSegments p =
                    last_segments(lights, before_last, last.p, last.n, last.pdf_next,
                                  lights.pdf(last.p, si), si.prim, si.p, si.n_geo);
                w = power_heuristic(p.bsdf, p.next_event, p.light_path);
            }
            add(bounce, w * beta * Le);
        }
        if (segments >= longest) break;

        const Bsdf bsdf(scene.material(si.material), si);
        const SurfacePoint at = si.surface_point();

        // Next-event estimation: a light sample at this vertex, f L cos / p_light, as in lesson
        // 3, MIS-weighted against the BSDF (and the light path); it is light that bounces once
        // more.
        const bool nee_allowed = segments + 1 <= longest;
        if (options.next_event && !bsdf.is_delta() && nee_allowed) {
            const float u_choose = rng.uniform();
            const Vec2 u_light{rng.uniform(), rng.uniform()};
            const std::optional<LightSample> ls = lights.sample(at, u_choose, u_light);
            const Color f = ls ? bsdf.eval(si.wo, ls->wi) : Color(0.0f);
            if (!is_black(f) && !scene.occluded(ls->shadow_ray, ls->emitter)) {
                float w = 1.0f;  // a point light: no other strategy finds it
                if (!ls->is_delta && ls->emitter) {
                    const LastSegments p =
                        last_segments(lights, last, si.p, si.n_geo, bsdf.pdf(si.wo, ls->wi),
                                      ls->pdf, *ls->emitter, ls->point, ls->normal);
                    w = power_heuristic(p.next_event, p.bsdf, p.light_path);
                } else if (!ls->is_delta) {  // the environment
                    w = power_heuristic(ls->pdf, bsdf.pdf(si.wo, ls->wi));
                }
                add(bounce + 1, w * beta * f * ls->radiance * bsdf.abs_cos(ls->wi) / ls->pdf);
            }
        }

        // Light-path connection (--light-paths): this vertex X to the light path's first vertex
        // Y; light that bounces twice more.
        const bool connects = light_paths && !bsdf.is_delta() && segments + 2 <= longest;
        if (connects) {
            if (!light_path_traced) {
                light_path = trace_light_path(scene, lights, light_rng);
                light_path_traced = true;
            }
            if (light_path)
                add(bounce + 2, beta * connect_light_vertex(scene, lights, si, bsdf, *light_path));
        }

        // Continue the path: wi from the BSDF, beta *= f cos / p.
        const std::optional<BsdfSample> s = bsdf.sample(si.wo, {rng.uniform(), rng.uniform()});
        if (!s) break;
        beta *= s->f * bsdf.abs_cos(s->wi) / s->pdf;
        if (is_black(beta) || !is_finite(beta)) break;
        specular = s->is_delta;
        before_last = last;
        last = {si.p, si.n_geo, s->pdf, connects};

        // Russian roulette: continue with probability q = min(1, max beta); survivors carry
        // beta / q, so the expected contribution is unchanged (q beta / q = beta).
        if (options.roulette_after >= 0 && bounce >= options.roulette_after) {
            const float q = std::min(1.0f, max_component(beta));
            if (rng.uniform() >= q) break;
            beta /= q;
        }
        ray = spawn_ray(at, s->wi);
    }
    return L;
}

Model make_path_tracing_model(const Scene& scene, const LightSampler& lights,
                              const PathOptions& options) {
    Model model;
    model.radiance = [&scene, &lights, options](const Ray& ray, Rng& rng) {
        return path_trace(scene, lights, ray, rng, options);
    };
    if (options.bounce_layers > 0) {
        for (int k = 0; k < options.bounce_layers; ++k)
            model.layer_names.push_back("bounce" + std::to_string(k));
        model.layer_names.push_back("bounce" + std::to_string(options.bounce_layers) + "plus");
        model.layered = [&scene, &lights, options](const Ray& ray, Rng& rng,
                                                   std::span<Color> layers) {
            return path_trace(scene, lights, ray, rng, options, layers);
        };
    }
    const bool light_paths = options.light_paths && options.next_event;
    model.notes.push_back(
        light_paths ? "estimator: next-event estimation, BSDF sampling and a light path of one "
                      "segment joined to every vertex, combined by MIS (power heuristic)"
        : options.next_event ? "estimator: next-event estimation with BSDF sampling, combined by "
                               "MIS (power heuristic)"
                             : "estimator: plain path tracing, BSDF sampling only (no next-event "
                               "estimation)");
    if (options.light_paths && !options.next_event)
        model.notes.push_back(
            "no light paths: they are weighed against next-event estimation, "
            "which --plain turns off");
    if (light_paths && scene.area_lights().empty())
        model.notes.push_back(
            "no light paths start: only emissive surfaces start them, not point "
            "lights or the background");
    if (!options.next_event && lights.has_point_lights())
        model.notes.push_back(
            "the scene's point lights are invisible without next-event "
            "estimation: a sampled direction never hits a point");
    model.notes.push_back(options.max_depth > 0
                              ? "paths end after " + std::to_string(options.max_depth) +
                                    " segments (biased: later bounces are missing)"
                              : "no depth limit (a safety cut at " + std::to_string(kLongestPath) +
                                    " segments ends paths trapped by total internal reflection)");
    if (options.roulette_after >= 0)
        model.notes.push_back("Russian roulette after " + std::to_string(options.roulette_after) +
                              " bounces (unbiased)");
    if (lights.empty()) model.notes.push_back("the scene has no lights: only emission is visible");
    return model;
}

}  // namespace lessons
