// Lesson 2: Whitted-style recursive ray tracing (see whitted.h for the model's equations).
#include "02_whitted/whitted.h"

#include <cstdio>

#include "geometry/spawn.h"
#include "materials/optics.h"

namespace lessons {

namespace {

// Follows one specular branch: the ray from the surface along `dir`, carrying `weight`
// (R, F or (1 - F) / eta^2). A branch past the depth limit, or too faint to matter, stops
// and contributes nothing.
Color trace_branch(const Scene& scene, const SurfaceInteraction& si, const Vec3& dir,
                   const Color& weight, const WhittedOptions& options, int depth,
                   const Color& attenuation) {
    const Color branch_attenuation = attenuation * weight;
    if (depth + 1 > options.max_bounces) return Color(0.0f);
    if (max_component(branch_attenuation) < options.min_attenuation) return Color(0.0f);
    return weight * whitted(scene, spawn_ray(si.surface_point(), dir), options, depth + 1,
                            branch_attenuation);
}

}  // namespace

Color whitted(const Scene& scene, const Ray& ray, const WhittedOptions& options, int depth,
              const Color& attenuation) {
    const std::optional<Hit> hit = scene.intersect(ray);
    if (!hit) return scene.background_radiance(ray.dir);
    const SurfaceInteraction si = scene.interaction(ray, *hit);
    const Material& material = scene.material(si.material);
    // The shading normal on the side the ray arrived from (decided by the intersection test).
    const Vec3 n = si.front_face() ? si.n_shading : -si.n_shading;
    Color L = scene.emitted(si);

    switch (material.type) {
        case MaterialType::Mirror: {
            // L = R * L(p, reflect(wo))
            L += trace_branch(scene, si, reflect(si.wo, n), material.reflectance, options, depth,
                              attenuation);
            break;
        }
        case MaterialType::Glass: {
            // Entering through the front (n_geo's side) goes from outside (index 1) to inside.
            const float eta = si.front_face() ? material.ior : 1.0f / material.ior;
            const float cos_i = glm::dot(si.wo, n);
            const float F =
                options.schlick ? fresnel_schlick(cos_i, eta) : fresnel_dielectric(cos_i, eta);
            // F * L(p, reflect(wo)): the reflected part (all of it past the critical angle).
            L += trace_branch(scene, si, reflect(si.wo, n), Color(F), options, depth, attenuation);
            // (1 - F) / eta^2 * L(p, refract(wo)): radiance divided by n^2 is what an interface
            // conserves, so crossing into a denser medium compresses the beam's solid angle.
            if (F < 1.0f)
                if (const std::optional<Vec3> wt = refract(si.wo, n, eta))
                    L += trace_branch(scene, si, *wt,
                                      material.transmittance * ((1.0f - F) / (eta * eta)), options,
                                      depth, attenuation);
            break;
        }
        case MaterialType::Diffuse:
        case MaterialType::Glossy:
        case MaterialType::Conductor: {
            // Lesson 1's model, and the recursion stops here.
            const LocalMaterial m = local_material(material, si.uv);
            L += m.k_d * options.ambient + direct_local(scene, si, m, n);
            break;
        }
    }
    return L;
}

WhittedModel::WhittedModel(const Scene& scene, const WhittedOptions& options)
    : scene_(scene), options_(options) {
    char limits[160];
    std::snprintf(limits, sizeof limits,
                  "specular recursion stops after %d bounces or below attenuation %g; stopped "
                  "rays contribute nothing",
                  options.max_bounces, options.min_attenuation);
    notes.push_back(limits);
    if (!scene.area_lights().empty())
        notes.push_back(area_lights_as_points_note(scene) +
                        "; seen directly and in mirrors as surfaces");
    for (const Material& m : scene.materials())
        if (facts_of(m.type).lobe) notes.push_back(glossy_as_highlight_note(m));
    bool has_glass = false, has_specular = false;
    for (const Material& m : scene.materials()) {
        has_glass |= m.type == MaterialType::Glass;
        has_specular |= facts_of(m.type).delta;
    }
    if (has_glass)
        notes.push_back(std::string("glass: ") +
                        (options.schlick ? "Schlick's approximation" : "exact Fresnel") +
                        "; shadow rays are blocked by glass like by any surface (no "
                        "caustics)");
    if (!has_specular)
        notes.push_back("no mirror or glass in this scene: the image equals lesson 1's");
    notes.push_back(ambient_note(options.ambient));
    if (scene.environment_map) notes.push_back(environment_map_note(scene));
    if (has_specular && !scene.point_lights().empty())
        notes.push_back(
            "point lights are never seen in mirrors or glass (a reflected ray never hits a "
            "point): the lamp's reflection and its highlights through glass are missing");
    if (has_specular && !scene.directional_lights().empty())
        notes.push_back(
            "directional lights are never seen in mirrors or glass (a reflected ray never has "
            "their one exact direction): the sun's reflection is missing");
    biased_because.push_back(
        "diffuse surfaces see lights only through shadow rays: light from other surfaces "
        "(colour bleeding) and light focused by mirrors and glass (caustics) are missing");
}

Color WhittedModel::sample(const Ray& ray, Rng&, uint32_t, std::span<Color>,
                           std::vector<Splat>&) const {
    return whitted(scene_, ray, options_);
}

}  // namespace lessons
