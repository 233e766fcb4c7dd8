// Lesson 3: the reflection equation by Monte Carlo (see reflection_equation.h).
#include "03_reflection_equation/reflection_equation.h"

#include "materials/bsdf.h"
#include "sampling/sampling.h"

namespace lessons {

namespace {

// What a ray leaving the surface sees: the emitted radiance L_e of the first surface it hits,
// or the environment's if it escapes. For MIS, also the density with which light sampling
// would have chosen the same direction.
struct Incident {
    Color radiance{0.0f};
    float light_pdf = 0.0f;
};

Incident emitted_along(const Scene& scene, const LightSampler& lights, const Vec3& p,
                       const Ray& ray) {
    const std::optional<Hit> hit = scene.intersect(ray);
    if (!hit) return {scene.background_radiance(ray.dir), lights.environment_pdf(ray.dir)};
    const SurfaceInteraction light_hit = scene.interaction(ray, *hit);
    const Color Le = scene.emitted(light_hit);
    if (is_black(Le)) return {};
    return {Le, lights.pdf(p, light_hit)};
}

float mis_weight(MisHeuristic h, float pdf_this, float pdf_other) {
    return h == MisHeuristic::Power ? power_heuristic(pdf_this, pdf_other)
                                    : balance_heuristic(pdf_this, pdf_other);
}

}  // namespace

const char* estimator_name(Estimator e) {
    for (const auto& [name, estimator] : kEstimatorNames)
        if (estimator == e) return name;
    return "?";
}

Color light_sample_term(const Scene& scene, const LightSampler& lights,
                        const SurfaceInteraction& si, const Bsdf& bsdf, Rng& rng, bool mis,
                        MisHeuristic heuristic) {
    const float u_choose = rng.uniform();
    const Vec2 u_light = rng.uniform2();
    const std::optional<LightSample> ls = lights.sample(si.surface_point(), u_choose, u_light);
    if (!ls) return Color(0.0f);
    const Color f = bsdf.eval(si.wo, ls->wi);
    if (is_black(f) || scene.occluded(ls->shadow_ray, ls->emitter)) return Color(0.0f);
    // A point light (delta) cannot be found by BSDF sampling: its sample keeps weight 1.
    const float w =
        (mis && !ls->is_delta) ? mis_weight(heuristic, ls->pdf, bsdf.pdf(si.wo, ls->wi)) : 1.0f;
    // f L cos(theta_i) / p_light: one light sample of the reflection equation.
    return w * f * ls->radiance * bsdf.abs_cos(ls->wi) / ls->pdf;
}

Color reflection_equation(const Scene& scene, const LightSampler& lights, const Ray& ray, Rng& rng,
                          const ReflectionOptions& options) {
    const std::optional<Hit> hit = scene.intersect(ray);
    if (!hit) return scene.background_radiance(ray.dir);
    const SurfaceInteraction si = scene.interaction(ray, *hit);
    const Bsdf bsdf(scene.material(si.material), si);
    const SurfacePoint at = si.surface_point();
    const Vec3& wo = si.wo;

    // L_o = L_e + ...
    Color L = scene.emitted(si);

    // f L_i cos / p for a direction wi drawn with density pdf (same for every hemisphere rule).
    auto brdf_sample_term = [&](const Vec3& wi, const Color& f, float pdf, bool weight_by_mis) {
        if (!(pdf > 0.0f) || is_black(f)) return Color(0.0f);
        const Incident in = emitted_along(scene, lights, si.p, spawn_ray(at, wi));
        if (is_black(in.radiance)) return Color(0.0f);
        const float w = weight_by_mis ? mis_weight(options.heuristic, pdf, in.light_pdf) : 1.0f;
        return w * f * in.radiance * bsdf.abs_cos(wi) / pdf;
    };

    // A mirror or smooth glass reflects from one direction only: the integral collapses to that
    // direction, which only the BSDF can give (no light sample can ever land on it).
    if (bsdf.is_delta()) {
        if (const auto s = bsdf.sample(wo, rng.uniform2()))
            L += brdf_sample_term(s->wi, s->f, s->pdf, false);
        return L;
    }

    switch (options.estimator) {
        case Estimator::Uniform:
        case Estimator::Cosine: {
            const Frame frame(bsdf.normal());
            const Vec2 u = rng.uniform2();
            const bool uniform = options.estimator == Estimator::Uniform;
            const Vec3 local = uniform ? sample_uniform_hemisphere(u) : sample_cosine_hemisphere(u);
            const float pdf = uniform ? uniform_hemisphere_pdf() : cosine_hemisphere_pdf(local.z);
            const Vec3 wi = frame.to_world(local);
            L += brdf_sample_term(wi, bsdf.eval(wo, wi), pdf, false);
            break;
        }
        case Estimator::Brdf: {
            if (const auto s = bsdf.sample(wo, rng.uniform2()))
                L += brdf_sample_term(s->wi, s->f, s->pdf, false);
            break;
        }
        case Estimator::Light:
        case Estimator::Mis: {
            const bool mis = options.estimator == Estimator::Mis;
            L += light_sample_term(scene, lights, si, bsdf, rng, mis, options.heuristic);
            // BSDF sample, weighted against the light sampler's density for the same direction.
            if (mis)
                if (const auto s = bsdf.sample(wo, rng.uniform2()))
                    L += brdf_sample_term(s->wi, s->f, s->pdf, true);
            break;
        }
    }
    return L;
}

ReflectionModel::ReflectionModel(const Scene& scene, const ReflectionOptions& options)
    : scene_(scene), lights_(scene), options_(options) {
    std::string estimator = std::string("estimator: ") + estimator_name(options.estimator);
    if (options.estimator == Estimator::Mis)
        estimator += options.heuristic == MisHeuristic::Power ? " (power heuristic)"
                                                              : " (balance heuristic)";
    notes.push_back(estimator);
    biased_because.push_back(
        "direct illumination only: L_i is what emitters send; light reflected by other surfaces "
        "(indirect light) is ignored");
    const bool sees_points =
        options.estimator == Estimator::Light || options.estimator == Estimator::Mis;
    if (lights_.has_delta_lights() && !sees_points)
        notes.push_back(
            std::string("the scene's point and directional lights are invisible to the ") +
            estimator_name(options.estimator) +
            " estimator: a sampled direction never hits a point, nor is it ever one exact "
            "direction (use light or mis)");
    bool delta = false;
    for (const Material& m : scene.materials()) delta |= facts_of(m.type).delta;
    if (delta)
        notes.push_back(
            "mirror and glass: one BSDF-sampled direction, whatever the estimator (a delta "
            "BSDF cannot be sampled any other way); they show only emitters");
    if (lights_.empty()) notes.push_back("the scene has no lights: only emission is visible");
}

Color ReflectionModel::sample(const Ray& ray, Rng& rng, uint32_t, std::span<Color>,
                              std::vector<Splat>&) const {
    return reflection_equation(scene_, lights_, ray, rng, options_);
}

}  // namespace lessons
