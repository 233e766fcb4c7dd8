// Lesson 4: path tracing the rendering equation (see rendering_equation.h).
#include "04_rendering_equation/rendering_equation.h"

#include <algorithm>

#include "03_reflection_equation/reflection_equation.h"
#include "sampling/sampling.h"

namespace lessons {

float russian_roulette_survival(const Color& beta) {
    return std::min(1.0f, max_component(beta));
}

void add_path_length_notes(Model& model, int max_depth, int roulette_after) {
    if (max_depth > 0)
        model.biased_because.push_back("paths end after " + std::to_string(max_depth) +
                                       " segments: later bounces are missing");
    else
        model.notes.push_back("no depth limit (a safety cut at " + std::to_string(kLongestPath) +
                              " segments ends paths trapped by total internal reflection)");
    if (roulette_after >= 0)
        model.notes.push_back("Russian roulette after " + std::to_string(roulette_after) +
                              " bounces (unbiased)");
}

Color path_trace(const Scene& scene, const LightSampler& lights, const Ray& camera_ray, Rng& rng,
                 const PathOptions& options, std::span<Color> bounces) {
    Color L(0.0f);
    // Adds light that has bounced `k` times: to the total, and to its layer.
    auto add = [&](int k, const Color& contribution) {
        L += contribution;
        if (!bounces.empty()) bounces[std::min<size_t>(k, bounces.size() - 1)] += contribution;
    };
    const int longest = longest_path(options.max_depth);

    Color beta(1.0f);  // path throughput: product of f cos / p along the path so far
    Ray ray = camera_ray;
    bool specular = true;       // the last direction came from a delta BSDF (or the camera)
    Vec3 previous{0.0f};        // the vertex the ray left
    float previous_pdf = 0.0f;  // the BSDF's solid-angle density of the ray's direction there
    for (int bounce = 0;; ++bounce) {
        const int segments = bounce + 1;  // this ray is the path's segment number `segments`
        const std::optional<Hit> hit = scene.intersect(ray);

        // E: emission found by this ray. When next-event estimation could have found the same
        // light from the previous vertex (its BSDF was not a delta), the two strategies share
        // it by the power heuristic of their densities for this direction.
        const bool weigh = options.next_event && !specular;
        if (!hit) {
            if (scene.has_environment()) {
                const float w =
                    weigh ? power_heuristic(previous_pdf, lights.environment_pdf(ray.dir)) : 1.0f;
                add(bounce, w * beta * scene.background_radiance(ray.dir));
            }
            break;
        }
        const SurfaceInteraction si = scene.interaction(ray, *hit);
        const Color Le = scene.emitted(si);
        if (!is_black(Le)) {
            const float w = weigh ? power_heuristic(previous_pdf, lights.pdf(previous, si)) : 1.0f;
            add(bounce, w * beta * Le);
        }
        if (segments >= longest) break;

        const Bsdf bsdf(scene.material(si.material), si);

        // Next-event estimation: lesson 3's light sample at this vertex (f L cos / p_light,
        // MIS-weighted against the BSDF), times beta: light that bounces once more.
        if (options.next_event && !bsdf.is_delta() && segments + 1 <= longest)
            add(bounce + 1,
                beta * light_sample_term(scene, lights, si, bsdf, rng, true, MisHeuristic::Power));

        // Continue the path: wi from the BSDF, beta *= f cos / p.
        const std::optional<BsdfSample> s = bsdf.sample(si.wo, rng.uniform2());
        if (!s) break;
        beta *= s->f * bsdf.abs_cos(s->wi) / s->pdf;
        if (is_black(beta) || !is_finite(beta)) break;
        specular = s->is_delta;
        previous = si.p;
        previous_pdf = s->pdf;

        // Russian roulette: continue with probability q, survivors carry beta / q.
        if (options.roulette_after >= 0 && bounce >= options.roulette_after) {
            const float q = russian_roulette_survival(beta);
            if (rng.uniform() >= q) break;
            beta /= q;
        }
        ray = spawn_ray(si.surface_point(), s->wi);
    }
    return L;
}

PathTracingModel::PathTracingModel(const Scene& scene, const PathOptions& options)
    : scene_(scene), lights_(scene), options_(options) {
    if (options.bounce_layers > 0) {
        for (int k = 0; k < options.bounce_layers; ++k)
            layer_names.push_back("bounce" + std::to_string(k));
        layer_names.push_back("bounce" + std::to_string(options.bounce_layers) + "plus");
    }
    notes.push_back(options.next_event
                        ? "estimator: next-event estimation with BSDF sampling, combined by "
                          "MIS (power heuristic)"
                        : "estimator: plain path tracing, BSDF sampling only (no next-event "
                          "estimation)");
    const SceneContents contents = scene.contents();
    if (!options.next_event && lights_.has_delta_lights())
        biased_because.push_back(
            "the scene's point and directional lights are invisible without next-event "
            "estimation: a sampled direction never hits a point, nor is it ever one exact "
            "direction");
    else if ((contents.point_lights || contents.directional_lights) && contents.delta_materials)
        biased_because.push_back(
            "point-light caustics are missing: light from a point (or directional) light by way "
            "of a mirror or glass is never found from the camera (a delta BSDF meets a delta "
            "light); lesson 5 renders it");
    if (contents.point_light_in_view)
        biased_because.push_back(
            "a point light in view is missing: no ray hits a point (lesson 5 joins the light to "
            "the camera: one bright pixel)");
    if (contents.area_lights && contents.delta_materials)
        notes.push_back(
            "caustics of lamps through mirrors and glass are found only by BSDF paths that "
            "happen to hit a lamp: unbiased but noisy (fireflies); lesson 5 traces them from the "
            "lamps");
    add_path_length_notes(*this, options.max_depth, options.roulette_after);
    if (lights_.empty()) notes.push_back("the scene has no lights: only emission is visible");
}

Color PathTracingModel::sample(const Ray& ray, Rng& rng, uint32_t, std::span<Color> layers,
                               std::vector<Splat>&) const {
    return path_trace(scene_, lights_, ray, rng, options_, layers);
}

}  // namespace lessons
