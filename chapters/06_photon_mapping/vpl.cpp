// Lesson 6, section 8: instant radiosity (see vpl.h).
#include "06_photon_mapping/vpl.h"

#include <cmath>

#include "03_reflection_equation/reflection_equation.h"
#include "05_bidirectional/connect.h"
#include "06_photon_mapping/first_diffuse.h"

namespace lessons {

std::vector<VirtualLight> virtual_lights(const LightPaths& paths) {
    std::vector<VirtualLight> lights;
    lights.reserve(paths.photons.size());
    for (const Photon& p : paths.photons)
        lights.push_back({&paths.vertex_of(p), static_cast<int>(p.vertex)});
    return lights;
}

float default_vpl_clamp(const Scene& scene) {
    const Bounds3 box = scene.bounds();
    if (box.empty()) return 0.0f;
    const float diagonal = glm::length(box.extent());
    if (!(diagonal > 0.0f) || !std::isfinite(diagonal)) return 0.0f;
    return 100.0f / (diagonal * diagonal);
}

namespace {

// G(y, x) = |cos_y| |cos_x| / d^2 with the geometric normals.
float geometry_term(const Vertex& y, const Vertex& x) {
    const Vec3 d = x.p - y.p;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) return kInfinity;
    const Vec3 w = d / std::sqrt(d2);
    return std::fabs(glm::dot(y.n, w)) * std::fabs(glm::dot(x.n, w)) / d2;
}

// The compensation's step from x: a BSDF sample traced at most 1 / sqrt(C); the next vertex y
// (non-delta) with x's throughput times f cos / p times the share of G(x, y) the cap removed,
// 1 - C / G; none where the sample finds nothing the cap touched.
std::optional<Vertex> compensation_step(const Bidir& b, const Vertex& x, float clamp, Rng& rng) {
    const std::optional<BsdfSample> s = x.bsdf->sample(x.si.wo, rng.uniform2());
    if (!s || s->is_delta || !(s->pdf > 0.0f)) return std::nullopt;
    Ray ray = spawn_ray(x.si.surface_point(), s->wi);
    ray.t_max = 1.0f / std::sqrt(clamp);  // G <= 1 / d^2 <= C beyond it
    const std::optional<Hit> hit = b.scene.intersect(ray);
    if (!hit) return std::nullopt;
    const SurfaceInteraction si = b.scene.interaction(ray, *hit);
    const Bsdf bsdf(b.scene.material(si.material), si);
    if (bsdf.is_delta()) return std::nullopt;  // the virtual lights miss its light too (vpl.h)
    Vertex y = camera_side_vertex(si, bsdf, Color(0.0f));
    const float G = geometry_term(y, x);
    if (!(G > clamp)) return std::nullopt;
    y.beta = x.beta * s->f * (x.bsdf->abs_cos(s->wi) / s->pdf) * (1.0f - clamp / G);
    if (is_black(y.beta) || !is_finite(y.beta)) return std::nullopt;
    return y;
}

}  // namespace

float capped_share(const Vertex& y, const Vertex& x, float clamp) {
    if (!(clamp > 0.0f)) return 1.0f;
    const float G = geometry_term(y, x);
    return G > clamp ? clamp / G : 1.0f;
}

Color virtual_light_at(const Bidir& b, std::span<const VirtualLight> lights, int count,
                       const Vertex& x, int segments, int longest, float clamp) {
    // y_i joined to x makes a path of i + 1 + segments segments.
    const int most = longest - 1 - segments;
    Color sum(0.0f);
    for (const VirtualLight& light : lights) {
        if (light.index > most) continue;
        const Color L = join(b, *light.y, x);
        if (!is_black(L) && is_finite(L)) sum += L * capped_share(*light.y, x, clamp);
    }
    return count > 0 ? sum / static_cast<float>(count) : Color(0.0f);
}

Color instant_radiosity(const Bidir& b, std::span<const VirtualLight> lights, int count,
                        const Ray& ray, Rng& rng, const VplSettings& settings,
                        std::span<Color> layers) {
    const int longest = longest_path(settings.paths.max_depth);
    const FirstDiffuse walk = first_diffuse_vertex(b, ray, rng, settings.paths);
    Color direct = walk.emitted, connected(0.0f), compensated(0.0f);
    std::optional<Vertex> x = walk.x;
    for (int segments = walk.segments; x; ++segments) {
        const bool first = segments == walk.segments;
        Color& light_sampled = first ? direct : compensated;
        Color& from_vpls = first ? connected : compensated;
        if (segments + 1 <= longest)
            light_sampled += x->beta * light_sample_term(b.scene, b.lights, x->si, *x->bsdf, rng,
                                                         false, MisHeuristic::Power);
        from_vpls += virtual_light_at(b, lights, count, *x, segments, longest, settings.clamp);
        // The light the cap removed, through the next vertex: two segments more at least.
        if (!settings.compensate || !(settings.clamp > 0.0f) || segments + 2 > longest) break;
        x = compensation_step(b, *x, settings.clamp, rng);
        if (x && settings.paths.roulette_after >= 0 && segments > settings.paths.roulette_after) {
            const float q = russian_roulette_survival(x->beta);
            if (rng.uniform() >= q) break;
            x->beta /= q;
        }
    }
    if (!layers.empty()) {
        layers[0] += direct;
        layers[1] += connected;
        layers[2] += compensated;
    }
    return direct + connected + compensated;
}

}  // namespace lessons
