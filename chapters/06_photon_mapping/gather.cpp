// Lesson 6, section 6: photon mapping at the first diffuse vertex (pm and ppm; see
// photon_mapping.h). The camera path goes through mirrors and glass to the first vertex x whose
// BSDF is not a delta (first_diffuse.h). There the light splits in two, each found once:
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
#include "06_photon_mapping/first_diffuse.h"
#include "06_photon_mapping/photon_mapping.h"

namespace lessons {

Color photon_mapping(const Bidir& b, const PhotonPass& pass, const Ray& camera_ray, Rng& rng,
                     const PhotonOptions& options, std::span<Color> layers) {
    const int longest = longest_path(options.paths.max_depth);
    const FirstDiffuse walk = first_diffuse_vertex(b, camera_ray, rng, options.paths);
    Color direct = walk.emitted, photons(0.0f);
    if (walk.x) {
        const Vertex& x = *walk.x;
        // x: direct light by a light sample, f L cos / p_light ...
        if (walk.segments + 1 <= longest)
            direct += x.beta * light_sample_term(b.scene, b.lights, x.si, *x.bsdf, rng, false,
                                                 MisHeuristic::Power);
        // ... and the photons of light that bounced before: (1/N) sum K f beta_p.
        const uint32_t most = static_cast<uint32_t>(std::min(longest - walk.segments, 1 << 30));
        photons = x.beta * reflected_radiance(pass.grid, x.si, *x.bsdf, x.si.wo, options.kernel,
                                              pass.paths.count, 2, most)
                               .L;
    }
    if (!layers.empty()) {
        layers[0] += direct;
        layers[1] += photons;
    }
    return direct + photons;
}

}  // namespace lessons
