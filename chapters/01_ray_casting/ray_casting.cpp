// Lesson 1: ray casting (see ray_casting.h for the model's equation).
#include "ray_casting.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "geometry/spawn.h"

namespace lessons {

namespace {

// A light as ray casting sees it: a point that sends intensity I towards the shaded point,
// and the point a shadow ray must reach unobstructed.
struct PointSource {
    Vec3 position;
    Color intensity;                 // W/sr towards the shaded point
    SurfacePoint shadow_target;      // normal zero for a point light, which lies on no surface
    std::optional<PrimRef> emitter;  // the primitive the target lies on, if any
};

// Area light -> point source. A flat emitter of radiance L_e and area A sends intensity
// I(theta) = L_e A cos(theta) in direction theta from its normal (Lambert's cosine law); a
// sphere sends L_e pi r^2 in every direction. Exact far from the light; near it the finite size
// matters (soft shadows, lesson 3).
PointSource as_point_source(const AreaLight& light, const Scene& scene, const Vec3& p) {
    PointSource s;
    s.position = light.center;
    s.emitter = light.prim;
    if (light.prim.kind() == ShapeKind::Sphere) {
        const float r = scene.spheres()[light.prim.index()].radius;
        const Vec3 out = glm::normalize(p - light.center);
        s.intensity = light.radiance * (kPi * r * r);
        s.shadow_target = scene.spheres()[light.prim.index()].point_at(out);  // facing p
        return s;
    }
    const float cos_light = glm::dot(light.normal, glm::normalize(p - light.center));
    const float facing = light.two_sided ? std::fabs(cos_light) : std::fmax(cos_light, 0.0f);
    s.intensity = light.radiance * (light.area * facing);
    s.shadow_target = {light.center, light.center_error, light.normal};
    return s;
}

// A light of the scene as lesson 1 sees it from the shading point si, a point source; none for the
// environment, which lights surfaces only through the ambient term, and none for the emitter si
// lies on, which does not light itself.
std::optional<PointSource> point_source(const Scene& scene, LightRef light,
                                        const SurfaceInteraction& si) {
    switch (light.kind) {
        case LightKind::Point: {
            const PointLight& l = scene.point_lights()[light.index];
            return PointSource{
                l.position, l.intensity, {l.position, Vec3(0.0f), Vec3(0.0f)}, std::nullopt};
        }
        case LightKind::Area: {
            const AreaLight& l = scene.area_lights()[light.index];
            if (l.prim == si.prim) return std::nullopt;
            return as_point_source(l, scene, si.p);
        }
        case LightKind::Environment: return std::nullopt;
    }
    return std::nullopt;
}

// Adds f * I cos(theta_i) / d^2 from one point source, if the shadow ray reaches it.
Color shade_from(const Scene& scene, const SurfaceInteraction& si, const LocalMaterial& m,
                 const Vec3& n, const PointSource& light) {
    if (is_black(light.intensity)) return Color(0.0f);
    Vec3 wi = light.position - si.p;
    const float distance_squared = glm::dot(wi, wi);
    if (!(distance_squared > 0.0f)) return Color(0.0f);
    wi /= std::sqrt(distance_squared);
    const float cos_i = glm::dot(n, wi);
    if (cos_i <= 0.0f) return Color(0.0f);  // the light is behind the surface
    // ... also behind the actual (geometric) surface: an interpolated shading normal can lean
    // towards a light the true surface faces away from, which would leak light through it.
    const Vec3 n_geo = glm::dot(si.n_geo, n) < 0.0f ? -si.n_geo : si.n_geo;
    if (glm::dot(n_geo, wi) <= 0.0f) return Color(0.0f);
    const bool on_surface = glm::dot(light.shadow_target.n, light.shadow_target.n) > 0.0f;
    const Ray shadow = on_surface ? spawn_ray_between(si.surface_point(), light.shadow_target)
                                  : spawn_ray_to(si.surface_point(), light.shadow_target.p);
    if (scene.occluded(shadow, light.emitter)) return Color(0.0f);
    // Irradiance from a point source: E = I cos(theta_i) / d^2 (inverse-square law).
    const Color irradiance = light.intensity * (cos_i / distance_squared);
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
        if (const std::optional<PointSource> source = point_source(scene, light, si))
            L += shade_from(scene, si, m, n, *source);
    return L;
}

Color ray_cast(const Scene& scene, const Ray& ray, const RayCastingOptions& options) {
    const std::optional<Hit> hit = scene.intersect(ray);
    if (!hit) return scene.background_radiance(ray.dir);  // the ray escapes: it sees the sky
    const SurfaceInteraction si = scene.interaction(ray, *hit);
    const LocalMaterial m = local_material(scene.material(si.material), si.uv);
    // Shade the side the ray arrived on: both normals turned towards the viewer.
    const Vec3 n = si.front_face() ? si.n_shading : -si.n_shading;
    // L = L_e + k_d L_a + sum over lights of f I cos / d^2 V.
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

Color RayCastingModel::sample(const Ray& ray, Rng&, std::span<Color>, std::vector<Splat>&) const {
    return ray_cast(scene_, ray, options_);
}

}  // namespace lessons
