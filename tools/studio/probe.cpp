// The probe: what is at a clicked pixel, with units (Studio::probe_json). The pixel's radiance L
// with its standard error and each layer's share of it; the surface the pixel's centre ray hits
// and its material; the direct irradiance E there, estimated with the lessons' light sampler;
// and the BRDF value f towards a chosen light.
#include <algorithm>
#include <cmath>

#include "io/report.h"
#include "lights/lights.h"
#include "materials/bsdf.h"
#include "sampling/rng.h"
#include "studio_internal.h"

namespace lessons::studio {

namespace {

// The direct irradiance at a surface point, E = integral of L_i cos(theta_i) over the hemisphere
// about `n` (the viewer's side): `samples` samples of the lessons' light sampler (a light by
// power, a point on it, a shadow ray), their mean and its standard error, W/m^2.
struct Irradiance {
    Color mean, standard_error;
};
Irradiance direct_irradiance(const Scene& scene, const SurfaceInteraction& si, const Vec3& n,
                             int samples, uint64_t pixel) {
    const LightSampler sampler(scene);
    Rng rng(12345, pixel, 0);
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int k = 0; k < samples; ++k) {
        const float u = rng.uniform();
        const Vec2 uv{rng.uniform(), rng.uniform()};
        Color e(0.0f);
        if (const std::optional<LightSample> ls = sampler.sample(si.surface_point(), u, uv)) {
            const float cos_i = glm::dot(ls->wi, n);
            if (cos_i > 0.0f && ls->pdf > 0.0f && !scene.occluded(ls->shadow_ray, ls->emitter))
                e = ls->radiance * (cos_i / ls->pdf);
        }
        const glm::dvec3 d(e);
        sum += d;
        sum2 += d * d;
    }
    const glm::dvec3 mean = sum / double(samples);
    const glm::dvec3 var = samples > 1
                               ? (sum2 / double(samples) - mean * mean) / double(samples - 1)
                               : glm::dvec3(0.0);
    return {Color(mean), Color(glm::sqrt(glm::max(var, glm::dvec3(0.0))))};
}

// A light, for the page's choice of a direction for f: a point or spot light's position, an
// area light's centre, a directional light's direction (the environment has neither: not
// offered).
struct LightPoint {
    std::string what;
    Vec3 position;
    std::optional<Vec3> towards;  // a directional light: the unit direction towards it
    // The unit direction from p towards the light.
    Vec3 direction_from(const Vec3& p) const {
        return towards ? *towards : glm::normalize(position - p);
    }
};
std::vector<LightPoint> light_points(const Scene& scene) {
    std::vector<LightPoint> points;
    for (const LightRef& light : scene.lights()) {
        switch (light.kind) {
            case LightKind::Point: {
                const PointLight& l = scene.point_lights()[light.index];
                points.push_back({l.cone ? "spot light" : "point light", l.position, {}});
                break;
            }
            case LightKind::Directional:
                points.push_back({"directional light", Vec3(0.0f),
                                  -scene.directional_lights()[light.index].direction});
                break;
            case LightKind::Area: {
                const AreaLight& l = scene.area_lights()[light.index];
                const std::string& name = scene.material(l.material).name;
                points.push_back({"area light (" + name + ")", l.center, {}});
                break;
            }
            case LightKind::Environment: break;
        }
    }
    return points;
}

// The pixel's radiance L (the mean of its samples) and the standard error of that mean.
std::string radiance_json(int x, int y, const Snapshot& snap) {
    const Color L = snap.result.image.at(x, y), var = snap.result.variance.at(x, y);
    std::string s = "{\"x\": " + std::to_string(x) + ", \"y\": " + std::to_string(y);
    s += ", \"spp\": " + std::to_string(snap.spp);
    s += ", \"L\": " + json_color(L);
    s += ", \"L_standard_error\": " +
         json_color({std::sqrt(var.x), std::sqrt(var.y), std::sqrt(var.z)});
    return s + ", \"L_units\": \"W/(sr m^2)\"";
}

std::string lights_json(const std::vector<LightPoint>& lights) {
    std::string s = ", \"lights\": [";
    for (size_t k = 0; k < lights.size(); ++k)
        s += std::string(k ? ", " : "") + json_quote(lights[k].what);
    return s + "]";
}

// The layers' shares of this pixel (lesson 4's bounces, lesson 5's strategies).
std::string layers_json(const RenderResult& r, int x, int y,
                        const std::vector<std::string>& layer_names) {
    const float total = luminance(r.image.at(x, y));
    std::string s = ", \"layers\": [";
    for (size_t k = 0; k < r.layers.size(); ++k) {
        const Color v = r.layers[k].at(x, y);
        s += std::string(k ? ", " : "") + "{\"name\": " + json_quote(layer_names[k]) +
             ", \"value\": " + json_color(v) +
             ", \"share\": " + json_number(total > 0 ? luminance(v) / total : 0.0) + "}";
    }
    return s + "]";
}

std::string hit_json(const Hit& hit, const SurfaceInteraction& si, const Material& m) {
    static const char* kinds[] = {"sphere", "quad", "triangle"};
    return ", \"hit\": {\"shape\": \"" + std::string(kinds[static_cast<int>(hit.prim.kind())]) +
           " " + std::to_string(hit.prim.index()) + "\", \"material\": " + json_quote(m.name) +
           ", \"type\": \"" + material_type_name(m.type) +
           "\", \"distance\": " + json_number(si.t) + ", \"position\": " + json_color(si.p) +
           ", \"front\": " + (si.front ? "true" : "false") + "}";
}

std::string irradiance_json(const Irradiance& E, int samples) {
    std::string s = ", \"E\": " + json_color(E.mean);
    s += ", \"E_standard_error\": " + json_color(E.standard_error);
    return s + ", \"E_samples\": " + std::to_string(samples) + ", \"E_units\": \"W/m^2\"";
}

// f(wo, wi) towards the light's position (a point or spot light), centre (an area light) or
// direction (a directional light); a delta BSDF has no finite value.
std::string bsdf_json(const LightPoint& light, const SurfaceInteraction& si, const Bsdf& bsdf,
                      const Material& m, const Vec3& n) {
    const Vec3 wi = light.direction_from(si.p);
    std::string s = ", \"f_light\": " + json_quote(light.what) +
                    ", \"cos_theta_i\": " + json_number(glm::dot(wi, n));
    if (bsdf.is_delta())
        s += ", \"f\": null, \"f_note\": \"a delta BSDF (" +
             std::string(material_type_name(m.type)) +
             "): f is a Dirac distribution, nonzero only along the mirror or refracted "
             "direction, with no finite value\"";
    else
        s += ", \"f\": " + json_color(bsdf.eval(si.wo, wi));
    return s + ", \"f_units\": \"1/sr\"";
}

}  // namespace

std::string Studio::probe_json(int pane_index, int x, int y, int light, int samples) const {
    const auto [p, snap] = rendered(pane_index);
    const Scene& scene = p->inputs.scene;
    if (x < 0 || y < 0 || x >= scene.width || y >= scene.height)
        throw RequestError("x, y: outside the " + std::to_string(scene.width) + "x" +
                           std::to_string(scene.height) + " image");
    samples = std::clamp(samples, 1, 1 << 16);
    const std::vector<LightPoint> lights = light_points(scene);
    std::string s = radiance_json(x, y, *snap) + lights_json(lights) +
                    layers_json(snap->result, x, y, p->inputs.model->layer_names);

    const Ray ray = scene.camera.generate_ray(x + 0.5f, y + 0.5f, scene.width, scene.height);
    const std::optional<Hit> hit = scene.intersect(ray);
    if (!hit)
        return s + ", \"hit\": null, \"background\": " +
               json_color(scene.background_radiance(ray.dir)) + "}";
    const SurfaceInteraction si = scene.interaction(ray, *hit);
    const Material& m = scene.material(si.material);
    s += hit_json(*hit, si, m);

    // E = integral of L_i cos(theta_i) over the hemisphere on the viewer's side, estimated from
    // the lesson's own light sampler (direct light only), with its standard error.
    const Bsdf bsdf(m, si);
    Vec3 n = bsdf.normal();
    if (glm::dot(n, si.wo) < 0.0f) n = -n;
    s += irradiance_json(
        direct_irradiance(scene, si, n, samples, static_cast<uint64_t>(y) * scene.width + x),
        samples);
    if (light >= 0 && light < static_cast<int>(lights.size()))
        s += bsdf_json(lights[light], si, bsdf, m, n);
    return s + "}";
}

}  // namespace lessons::studio
