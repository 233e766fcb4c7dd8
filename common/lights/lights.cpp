// Choosing a light by power, sampling the chosen light for a shading point (an area light's point
// and density are in area_light.cpp), and light leaving a light for light paths (see lights.h).
#include "lights/lights.h"

#include <algorithm>
#include <cmath>

#include "sampling/discrete.h"
#include "sampling/sampling.h"

namespace lessons {

namespace {

// Emitted power, W (luminance), which sets how often a light is chosen.
float power_of(const AreaLight& light) {
    // A Lambertian emitter of radiance L and area A sends pi L A from each emitting side.
    const float sides = light.two_sided ? 2.0f : 1.0f;
    return kPi * luminance(light.radiance) * light.area * sides;
}

// The same for a point light: an isotropic point source of intensity I sends 4 pi I; a spot,
// less.
float power_of(const PointLight& l) {
    return luminance(l.intensity) * (l.cone ? l.cone->solid_angle() : 4.0f * kPi);
}

// The same for a directional light: irradiance E across the disk of area pi R^2 that the
// scene's bounding sphere (radius R) shows it, the power that reaches the scene.
float power_of(const DirectionalLight& l, float r) {
    const float e = luminance(l.irradiance);
    return e * kPi * r * r;
}

// The weight of the environment, for a bounding sphere of radius r. A uniform environment of
// radiance L sends, from every direction, the radiance L through the disk of area pi R^2 that
// the scene's bounding sphere (radius R) shows that direction: pi R^2 L per steradian, over
// 4 pi steradians, power 4 pi^2 R^2 L. Only the ratios of the powers matter (they set how
// often each light is chosen, never the image's mean): the weight used is a quarter of that
// power, pi^2 R^2 L, so the sky is chosen less often than its power alone would say.
float environment_weight(const Scene& scene, float r) {
    const Color sky = scene.environment_map ? scene.environment_map->mean() : scene.background;
    return kPi * kPi * r * r * luminance(sky);
}

}  // namespace

LightSampler::LightSampler(const Scene& scene)
    : scene_(scene), rectangles_(solid_angle_rectangles(scene)) {
    light_of_point_.assign(scene.point_lights().size(), SIZE_MAX);
    light_of_directional_.assign(scene.directional_lights().size(), SIZE_MAX);
    // The scene's bounding sphere, which a directional light's beam must cover.
    const Bounds3 bounds = scene.bounds();
    if (!bounds.empty()) {
        beam_center_ = 0.5f * (bounds.min + bounds.max);
        beam_radius_ = std::max(0.5f * glm::length(bounds.extent()), 1e-3f);
    }
    std::vector<double> power;
    // Each light's power, and where the sampler finds it again; a point, directional or area
    // light that sends nothing (or no finite power) is never chosen.
    for (const LightRef& light : scene.lights()) {
        float p = 0.0f;
        switch (light.kind) {
            case LightKind::Point: {
                p = power_of(scene.point_lights()[light.index]);
                if (!(p > 0.0f) || !std::isfinite(p)) continue;
                light_of_point_[light.index] = lights_.size();
                has_delta_lights_ = true;
                break;
            }
            case LightKind::Directional: {
                p = power_of(scene.directional_lights()[light.index], beam_radius_);
                if (!(p > 0.0f) || !std::isfinite(p)) continue;
                light_of_directional_[light.index] = lights_.size();
                has_delta_lights_ = true;
                break;
            }
            case LightKind::Area: {
                const AreaLight& area_light = scene.area_lights()[light.index];
                p = power_of(area_light);
                if (!(p > 0.0f) || !std::isfinite(p)) continue;
                light_of_primitive_[area_light.prim.bits] = lights_.size();
                break;
            }
            case LightKind::Environment: {
                p = environment_weight(scene, beam_radius_);
                environment_ = lights_.size();
                break;
            }
        }
        lights_.push_back(light);
        power.push_back(p);
    }
    // By power, yet every light at least 2^-24 (sampling/discrete.h): a lamp 1e8 times dimmer
    // than another is still chosen now and then, so no estimator weighs its light against a
    // choice that cannot happen.
    cdf_ = choice_cdf(power);
}

size_t LightSampler::choose_light(float u_choose) const {
    return choose_entry(cdf_, u_choose);
}

float LightSampler::choice_probability(size_t light) const {
    return entry_probability(cdf_, light);
}

float LightSampler::environment_pdf(const Vec3& dir) const {
    if (!environment_) return 0.0f;
    const float p =
        scene_.environment_map ? scene_.environment_map->pdf(dir) : uniform_sphere_pdf();
    return choice_probability(*environment_) * p;
}

std::optional<LightSample> LightSampler::sample(const SurfacePoint& at, float u_choose,
                                                const Vec2& u) const {
    if (lights_.empty()) return std::nullopt;
    const size_t light = choose_light(u_choose);
    const float choose = choice_probability(light);
    if (!(choose > 0.0f)) return std::nullopt;
    const LightRef& e = lights_[light];
    std::optional<LightSample> s;
    switch (e.kind) {
        case LightKind::Point: {
            const PointLight& l = scene_.point_lights()[e.index];
            const Vec3 d = l.position - at.p;
            const float d2 = glm::dot(d, d);
            if (!(d2 > 0.0f)) return std::nullopt;
            // Irradiance from a point source facing it: E = I / d^2 (a spot's I towards `at`).
            const Vec3 wi = d / std::sqrt(d2);
            const Color intensity = l.intensity_towards(-wi);
            if (is_black(intensity)) return std::nullopt;  // outside a spot's cone
            s = LightSample{intensity / d2, wi,   std::sqrt(d2),
                            1.0f,           true, spawn_ray_to(at, l.position),
                            std::nullopt};
            s->light_index = e.index;
            break;
        }
        case LightKind::Directional: {
            const DirectionalLight& l = scene_.directional_lights()[e.index];
            const Vec3 wi = -l.direction;
            s = LightSample{l.irradiance,      wi,          kInfinity, 1.0f, true,
                            spawn_ray(at, wi), std::nullopt};
            s->light_index = e.index;
            s->directional = true;
            break;
        }
        case LightKind::Area: return sample_area(e.index, at, u, choose);  // the common case
        case LightKind::Environment: {
            // A map: by its importance (environment.h); a uniform sky: uniform on the sphere.
            if (scene_.environment_map) {
                const std::optional<EnvironmentMap::Sample> m = scene_.environment_map->sample(u);
                if (!m) return std::nullopt;
                s = LightSample{m->radiance,           m->dir,      kInfinity, m->pdf, false,
                                spawn_ray(at, m->dir), std::nullopt};
                break;
            }
            const Vec3 wi = sample_uniform_sphere(u);
            s = LightSample{scene_.background, wi,          kInfinity, uniform_sphere_pdf(), false,
                            spawn_ray(at, wi), std::nullopt};
            break;
        }
    }
    if (!s) return std::nullopt;
    s->pdf *= choose;
    return s;
}

std::optional<EmissionSample> LightSampler::sample_emission(float u_choose, const Vec2& u_point,
                                                            const Vec2& u_dir) const {
    if (lights_.empty()) return std::nullopt;
    const size_t light = choose_light(u_choose);
    const float choose = choice_probability(light);
    if (!(choose > 0.0f)) return std::nullopt;
    const LightRef& e = lights_[light];
    switch (e.kind) {
        case LightKind::Point: {
            const PointLight& l = scene_.point_lights()[e.index];
            // Isotropic: uniform on the sphere; a spot: uniform in its cone.
            Vec3 w;
            float pdf_dir;
            if (l.cone) {
                const float one_minus_cos = 1.0f - l.cone->cos_outer;
                w = glm::normalize(
                    Frame(l.cone->axis).to_world(sample_uniform_cone(u_dir, one_minus_cos)));
                pdf_dir = uniform_cone_pdf(one_minus_cos);
            } else {
                w = sample_uniform_sphere(u_dir);
                pdf_dir = uniform_sphere_pdf();
            }
            const Color intensity = l.intensity_towards(w);
            if (is_black(intensity)) return std::nullopt;
            EmissionSample s{Ray{l.position, w, kInfinity},
                             l.position,
                             Vec3(0.0f),
                             intensity,
                             choose,
                             pdf_dir,
                             std::nullopt};
            s.light_index = e.index;
            return s;
        }
        case LightKind::Directional: {
            const DirectionalLight& l = scene_.directional_lights()[e.index];
            // A point uniform on the disk of radius R facing the light, just outside the
            // bounding sphere on the light's side (beam_origin).
            const Vec2 disk = sample_concentric_disk(u_point);
            const Frame frame(l.direction);
            const Vec3 origin =
                beam_origin(l.direction, beam_center_ + frame.to_world(Vec3(disk.x, disk.y, 0.0f)) *
                                                            beam_radius_);
            EmissionSample s{Ray{origin, l.direction, kInfinity},
                             origin,
                             l.direction,
                             l.irradiance,
                             choose,
                             1.0f / (kPi * beam_radius_ * beam_radius_),
                             std::nullopt};
            s.directional = true;
            s.light_index = e.index;
            return s;
        }
        case LightKind::Area: return sample_area_emission(e.index, choose, u_point, u_dir);
        case LightKind::Environment: return std::nullopt;  // starts no light path (lights.h)
    }
    return std::nullopt;
}

LightSampler::EmissionPdf LightSampler::point_emission_pdf(uint32_t index, const Vec3& w) const {
    if (index >= light_of_point_.size() || light_of_point_[index] == SIZE_MAX) return {};
    const PointLight& l = scene_.point_lights()[index];
    float dir = uniform_sphere_pdf();
    if (l.cone)
        dir = glm::dot(l.cone->axis, w) > l.cone->cos_outer
                  ? uniform_cone_pdf(1.0f - l.cone->cos_outer)
                  : 0.0f;
    return {choice_probability(light_of_point_[index]), dir};
}

LightSampler::EmissionPdf LightSampler::directional_emission_pdf(uint32_t index) const {
    if (index >= light_of_directional_.size() || light_of_directional_[index] == SIZE_MAX)
        return {};
    return {choice_probability(light_of_directional_[index]),
            1.0f / (kPi * beam_radius_ * beam_radius_)};
}

LightSampler::EmissionPdf LightSampler::emission_pdf(PrimRef light, const Vec3& n_q,
                                                     const Vec3& w) const {
    const auto it = light_of_primitive_.find(light.bits);
    if (it == light_of_primitive_.end()) return {};
    const AreaLight& area_light = scene_.area_lights()[lights_[it->second].index];
    const float cos_q = glm::dot(n_q, w);
    const float dir = area_light.two_sided ? 0.5f * cosine_hemisphere_pdf(std::fabs(cos_q))
                                           : cosine_hemisphere_pdf(std::max(cos_q, 0.0f));
    return {choice_probability(it->second) / area_light.area, dir};
}

float LightSampler::pdf(const Vec3& p, const SurfaceInteraction& light_hit) const {
    return pdf(p, light_hit.prim, light_hit.p, light_hit.n_geo);
}

float LightSampler::pdf(const Vec3& p, PrimRef light, const Vec3& q, const Vec3& n_q) const {
    const auto it = light_of_primitive_.find(light.bits);
    if (it == light_of_primitive_.end()) return 0.0f;
    return choice_probability(it->second) * area_pdf(lights_[it->second].index, p, q, n_q);
}

}  // namespace lessons
