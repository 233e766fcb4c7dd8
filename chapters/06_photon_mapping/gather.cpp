// Lesson 6, section 6: photon mapping at the first diffuse vertex (pm and ppm; see
// photon_mapping.h). The camera path follows mirrors and glass (their one direction each, as
// lesson 4 samples them), adding the emission it meets, to the first vertex x whose BSDF is not
// a delta. There the light splits in two, each found once:
//   direct light   (one bounce, at x): lesson 3's light sample, unweighted (no BSDF sample is
//                  taken at x to share it with);
//   the rest       (light that has bounced at least once before x: caustics, colour bleeding):
//                  the photons of vertices y_i, i >= 2, within r of x (density.h).
// A photon at y_1 is light straight from a lamp, which the light sample finds with far less
// noise, so it is left out; a photon at y_i makes a path of i + (the camera's segments) segments,
// kept within --max-depth.
#include <algorithm>

#include "03_reflection_equation/reflection_equation.h"
#include "04_rendering_equation/rendering_equation.h"
#include "06_photon_mapping/density.h"
#include "06_photon_mapping/photon_mapping.h"

namespace lessons {

Color photon_mapping(const Bidir& b, const PhotonPass& pass, const Ray& camera_ray, Rng& rng,
                     const PhotonOptions& options, std::span<Color> layers) {
    const Scene& scene = b.scene;
    const int longest = longest_path(options.paths.max_depth);
    Color beta(1.0f), direct(0.0f), photons(0.0f);
    Ray ray = camera_ray;
    for (int segments = 1; segments <= longest; ++segments) {
        const std::optional<Hit> hit = scene.intersect(ray);
        if (!hit) {  // the sky, seen directly or in mirrors and glass
            direct += beta * scene.background_radiance(ray.dir);
            break;
        }
        const SurfaceInteraction si = scene.interaction(ray, *hit);
        direct += beta * scene.emitted(si);  // a lamp, seen directly or in mirrors and glass
        const Bsdf bsdf(scene.material(si.material), si);
        if (!bsdf.is_delta()) {
            // x: direct light by a light sample, f L cos / p_light ...
            if (segments + 1 <= longest)
                direct += beta * light_sample_term(scene, b.lights, si, bsdf, rng, false,
                                                   MisHeuristic::Power);
            // ... and the photons of light that bounced before: (1/N) sum K f beta_p.
            const uint32_t most = static_cast<uint32_t>(std::min(longest - segments, 1 << 30));
            photons = beta * reflected_radiance(pass.grid, si, bsdf, si.wo, options.kernel,
                                                pass.paths.count, 2, most)
                                 .L;
            break;
        }
        // A mirror or glass: on along its direction, beta *= f cos / p (lesson 4's step).
        const std::optional<BsdfSample> s = bsdf.sample(si.wo, rng.uniform2());
        if (!s) break;
        beta *= s->f * bsdf.abs_cos(s->wi) / s->pdf;
        if (is_black(beta) || !is_finite(beta)) break;
        if (options.paths.roulette_after >= 0 && segments > options.paths.roulette_after) {
            const float q = russian_roulette_survival(beta);
            if (rng.uniform() >= q) break;
            beta /= q;
        }
        ray = spawn_ray(si.surface_point(), s->wi);
    }
    if (!layers.empty()) {
        layers[0] += direct;
        layers[1] += photons;
    }
    return direct + photons;
}

}  // namespace lessons
