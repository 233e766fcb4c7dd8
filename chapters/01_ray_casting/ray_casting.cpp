// Lesson 1: ray casting (see ray_casting.h for the model's equation).
#include "01_ray_casting/ray_casting.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "geometry/spawn.h"

namespace lessons {

namespace {

// A light as ray casting sees it from the shaded point: the direction to it, the irradiance it
// gives a surface facing it there, and the shadow ray that must reach it unobstructed.
struct Incident {
    Vec3 wi;                         // unit, towards the light
    Color intensity;                 // I towards the shaded point, W/sr (a directional light: E)
    float distance_squared;          // d^2 (a directional light: 1), so that E = I / d^2
    Ray shadow;                      // towards the light, ending at it
    std::optional<PrimRef> emitter;  // the primitive the shadow ray ends on, if any
};

// A point source of intensity I (towards the shaded point p) at `position`, whose shadow rays end
// at `target` (on an emitter's surface, or the point itself, normal zero).
std::optional<Incident> from_point(const SurfaceInteraction& si, const Vec3& position,
                                   const Color& intensity, const SurfacePoint& target,
                                   std::optional<PrimRef> emitter) {
    const Vec3 d = position - si.p;
    const float distance_squared = glm::dot(d, d);
    if (is_black(intensity) || !(distance_squared > 0.0f)) return std::nullopt;
    const bool on_surface = glm::dot(target.n, target.n) > 0.0f;
    const Ray shadow = on_surface ? spawn_ray_between(si.surface_point(), target)
                                  : spawn_ray_to(si.surface_point(), target.p);
    return Incident{d / std::sqrt(distance_squared), intensity, distance_squared, shadow, emitter};
}

// Area light -> point source. A flat emitter of radiance L_e and area A sends intensity
// I(theta) = L_e A cos(theta) in direction theta from its normal (Lambert's cosine law); a
// sphere sends L_e pi r^2 in every direction. Exact far from the light; near it the finite size
// matters (soft shadows, lesson 3).
std::optional<Incident> as_point_source(const AreaLight& light, const Scene& scene,
                                        const SurfaceInteraction& si) {
    if (light.prim.kind() == ShapeKind::Sphere) {
        const Sphere& sphere = scene.spheres()[light.prim.index()];
        const Vec3 out = glm::normalize(si.p - light.center);
        return from_point(si, light.center, light.radiance * (kPi * sphere.radius * sphere.radius),
                          sphere.point_at(out), light.prim);  // the target faces p
    }
    const float cos_light = glm::dot(light.normal, glm::normalize(si.p - light.center));
    const float facing = light.two_sided ? std::fabs(cos_light) : std::fmax(cos_light, 0.0f);
    return from_point(si, light.center, light.radiance * (light.area * facing),
                      {light.center, light.center_error, light.normal}, light.prim);
}

// A light of the scene as lesson 1 sees it from the shading point si; none for the environment,
// which lights surfaces only through the ambient term, and none for the emitter si lies on,
// which does not light itself.
std::optional<Incident> incident(const Scene& scene, LightRef light, const SurfaceInteraction& si) {
    switch (light.kind) {
        case LightKind::Point: {
            const PointLight& l = scene.point_lights()[light.index];
            // A spot sends its intensity only within its cone.
            return from_point(si, l.position,
                              l.intensity_towards(glm::normalize(si.p - l.position)),
                              {l.position, Vec3(0.0f), Vec3(0.0f)}, std::nullopt);
        }
        case LightKind::Directional: {  // the same E everywhere, from one direction
            const DirectionalLight& l = scene.directional_lights()[light.index];
            return Incident{-l.direction, l.irradiance, 1.0f,
                            spawn_ray(si.surface_point(), -l.direction), std::nullopt};
        }
        case LightKind::Area: {
            const AreaLight& l = scene.area_lights()[light.index];
            if (l.prim == si.prim) return std::nullopt;
            return as_point_source(l, scene, si);
        }
        case LightKind::Environment: return std::nullopt;
    }
    return std::nullopt;
}

// Adds f * E cos(theta_i) from one light, if the shadow ray reaches it.
Color shade_from(const Scene& scene, const SurfaceInteraction& si, const LocalMaterial& m,
                 const Vec3& n, const Incident& light) {
    const Vec3& wi = light.wi;
    const float cos_i = glm::dot(n, wi);
    if (cos_i <= 0.0f) return Color(0.0f);  // the light is behind the surface
    // ... also behind the actual (geometric) surface: an interpolated shading normal can lean
    // towards a light the true surface faces away from, which would leak light through it.
    const Vec3 n_geo = glm::dot(si.n_geo, n) < 0.0f ? -si.n_geo : si.n_geo;
    if (glm::dot(n_geo, wi) <= 0.0f) return Color(0.0f);
    if (scene.occluded(light.shadow, light.emitter)) return Color(0.0f);
    // Irradiance from a point source: E = I cos(theta_i) / d^2 (inverse-square law).
    const Color irradiance = light.intensity * (cos_i / light.distance_squared);
    // f(wo, wi) = k_d / pi + k_s N(e) (n . h)^e: Lambert and the normalised Blinn-Phong lobe.
    return blinn_phong_brdf(m.k_d, m.k_s, m.exponent, n, si.wo, wi) * irradiance;
}

std::string rgb(const Color& c) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%g, %g, %g)", c.x, c.y, c.z);
    return buf;
}

}  // namespace

LocalMaterial local_material(const Material& m, const Vec2& uv) {
    LocalMaterial l;
    switch (m.type) {
        case MaterialType::Diffuse: l.k_d = m.albedo.eval(uv); break;
        case MaterialType::Glossy:
            l.k_d = m.albedo.eval(uv);
            l.k_s = m.specular;
            l.exponent = blinn_phong_exponent(m.roughness);
            break;
        case MaterialType::Conductor:  // a metal: all highlight, no diffuse base
            l.k_s = m.specular;
            l.exponent = blinn_phong_exponent(m.roughness);
            break;
        case MaterialType::Mirror: l.k_d = m.reflectance; break;
        case MaterialType::Glass: l.k_d = Color(1.0f); break;
    }
    return l;
}

std::vector<std::string> local_material_notes(const Scene& scene) {
    std::vector<std::string> notes;
    for (const Material& m : scene.materials()) {
        switch (m.type) {
            case MaterialType::Diffuse: break;  // Lambert, as it is
            case MaterialType::Glossy:
            case MaterialType::Conductor: notes.push_back(glossy_as_highlight_note(m)); break;
            case MaterialType::Mirror:
                notes.push_back("material '" + m.name +
                                "' (mirror): shaded as diffuse with albedo = its reflectance " +
                                rgb(m.reflectance) + "; no reflection");
                break;
            case MaterialType::Glass:
                notes.push_back("material '" + m.name +
                                "' (glass): shaded as white diffuse (albedo 1: a clear dielectric "
                                "absorbs nothing); no refraction, no reflection");
                break;
        }
    }
    return notes;
}

std::string glossy_as_highlight_note(const Material& m) {
    return "material '" + m.name + "' (" + material_type_name(m.type) + ", roughness " +
           std::to_string(m.roughness) + "): Blinn-Phong highlight, exponent " +
           std::to_string(blinn_phong_exponent(m.roughness)) +
           "; no glossy reflection of other surfaces";
}

std::string area_lights_as_points_note(const Scene& scene) {
    return std::to_string(scene.area_lights().size()) +
           " emissive primitive(s): each treated as a point source at its centre with intensity "
           "L_e A cos(theta) (spheres L_e pi r^2) for shadow rays; hard shadows, no soft penumbra";
}

std::string ambient_note(const Color& ambient) {
    return "indirect light ignored; a constant ambient radiance L_a = " + rgb(ambient) +
           " stands in for it (--ambient): it lights every diffuse point alike, in shadow or "
           "not, from no direction";
}

Color direct_local(const Scene& scene, const SurfaceInteraction& si, const LocalMaterial& m,
                   const Vec3& n) {
    Color L(0.0f);
    for (const LightRef& light : scene.lights())
        if (const std::optional<Incident> in = incident(scene, light, si))
            L += shade_from(scene, si, m, n, *in);
    return L;
}

Color ray_cast(const Scene& scene, const Ray& ray, const RayCastingOptions& options) {
    const std::optional<Hit> hit = scene.intersect(ray);
    if (!hit) return scene.background_radiance(ray.dir);  // the ray escapes: it sees the sky
    const SurfaceInteraction si = scene.interaction(ray, *hit);
    const LocalMaterial m = local_material(scene.material(si.material), si.uv);
    // Shade the side the ray arrived on: both normals turned towards the viewer.
    const Vec3 n = si.front_face() ? si.n_shading : -si.n_shading;
    // L = L_e + k_d L_a + sum over lights of f E cos V (E = I / d^2 for a point source).
    return scene.emitted(si) + m.k_d * options.ambient + direct_local(scene, si, m, n);
}

std::string environment_map_note(const Scene& scene) {
    if (!scene.environment_map) return "";
    return "environment map: escaping rays see it, but it lights surfaces only through the "
           "ambient term, as its mean radiance (no direction, no shadows; lessons 3 to 5 sample "
           "it)";
}

RayCastingModel::RayCastingModel(const Scene& scene, const RayCastingOptions& options)
    : scene_(scene), options_(options) {
    if (!scene.area_lights().empty()) notes.push_back(area_lights_as_points_note(scene));
    for (const std::string& n : local_material_notes(scene)) notes.push_back(n);
    notes.push_back(ambient_note(options.ambient));
    if (scene.environment_map) notes.push_back(environment_map_note(scene));
    biased_because.push_back(
        "a local model: light arriving from other surfaces (indirect light, reflections, "
        "refraction) is missing, and the ambient term is a constant guess for it");
    const std::vector<LightRef> lights = scene.lights();  // the sky lights only the ambient term
    if (std::all_of(lights.begin(), lights.end(),
                    [](LightRef l) { return l.kind == LightKind::Environment; }))
        notes.push_back("the scene has no lights: only emission, ambient and background");
}

Color RayCastingModel::sample(const Ray& ray, Rng&, uint32_t, std::span<Color>,
                              std::vector<Splat>&) const {
    return ray_cast(scene_, ray, options_);
}

}  // namespace lessons
