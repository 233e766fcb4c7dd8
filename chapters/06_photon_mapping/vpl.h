// Lesson 6, section 8: instant radiosity (Keller 1997), the light subpaths' vertices *connected*
// to the camera's instead of merged with it. A pass traces N light subpaths (--vpls N, lesson 5's
// light_subpath, as the photons are traced: photons.h), and every vertex y_i, i >= 1, on a surface
// whose BSDF is not a delta becomes a virtual point light: its position, shading frame, the
// direction its light arrived from and its throughput beta are the light subpath's vertex itself.
// A camera path goes through mirrors and glass to its first non-delta vertex x (first_diffuse.h);
// there the light arriving at x is
//   direct   lesson 3's light sample at x (next-event estimation), and
//   vpl      (1/N) sum over the virtual lights y of beta(y) f(y) G(y, x) V f(x) beta(x),
//            lesson 5's join of y to x (connect.h), with one shadow ray each; f(y) is y's own
//            BSDF towards x (exact for glossy and metal surfaces, not a Lambertian rho/pi).
// Each term is unbiased: a light subpath's vertices carry, on average, the light that arrives at
// them, and the join integrates over where they lie.
//
// The clamp. G = |cos_y| |cos_x| / d^2 grows without bound as y nears x: in a corner, one virtual
// light a hair from x lights it a thousand times brighter than its neighbours (the blotches of
// instant radiosity). --vpl-clamp C caps G at C (per m^2, with the geometric normals), removing the
// light of connections shorter than about 1 / sqrt(C): a bias, darker corners and contact shadows.
// C = 0 caps nothing. The default is 100 / D^2, D the scene box's diagonal: the cap acts on
// connections shorter than a tenth of the scene (default_vpl_clamp).
//
// The compensation (Kollig and Keller 2004). What the cap removed at x is
//   integral over directions of f(x) L_r(y) |cos_x| max(1 - C / G(x, y), 0) dw,
// y the first surface in direction w and L_r(y) the light y reflects towards x. --vpl-compensate
// estimates it with one BSDF sample at x, traced at most 1 / sqrt(C) (no farther y can have G > C),
// where L_r(y) is estimated in turn as at x: the light sample, the capped virtual lights, and again
// the compensation. The sum is the uncapped integral: the render is unbiased again (but for what
// virtual lights miss, below), and the light the cap took from the near field comes back as
// ordinary path-tracing noise. (In a scene with a sky, the light sample at y also finds the sky,
// whose light after a bounce no virtual light carries: the compensation then adds some of it.)
//
// What virtual lights cannot do: light that reaches x off a mirror or through glass (a caustic
// seen directly, L S+ D E, or a lit wall's light off a mirror, L D S+ D E) is missing: a join is a
// straight segment from a virtual light to x, and a light sample a straight segment from a lamp,
// and neither can bounce off a mirror or pass through glass on the way. The sky starts no light
// subpaths (photons.h), so its light after a bounce is missing too.
#pragma once

#include <span>
#include <vector>

#include "05_bidirectional/bidirectional.h"
#include "06_photon_mapping/photons.h"

namespace lessons {

// A virtual point light: light subpath vertex y_index (index >= 1), kept in its pass's LightPaths.
struct VirtualLight {
    const Vertex* y = nullptr;
    int index = 0;
};

// The virtual lights of a pass's light subpaths (traced with their vertices kept): the vertices
// that leave photons (photons.h), in the same order.
std::vector<VirtualLight> virtual_lights(const LightPaths& paths);

// The cap on G when none is given: 100 / D^2, D the diagonal of the scene's box (0 for a scene
// without surfaces or with a box of no size: no cap).
float default_vpl_clamp(const Scene& scene);

// The share of a connection's light that the cap C keeps: min(1, C / G(y, x)), G with the
// geometric normals (1 where C = 0).
float capped_share(const Vertex& y, const Vertex& x, float clamp);

// The light of every virtual light at camera vertex x (a Surface vertex with its throughput),
// whose path would be at most longest segments when x is `segments` from the camera: (1/N) sum of
// the capped joins, N = `count` light subpaths.
Color virtual_light_at(const Bidir& b, std::span<const VirtualLight> lights, int count,
                       const Vertex& x, int segments, int longest, float clamp);

// What instant radiosity asks: path length and Russian roulette (lesson 5's options), the cap,
// and whether to compensate for it.
struct VplSettings {
    BidirOptions paths;
    float clamp = 0.0f;
    bool compensate = false;
};

// One sample of the pixel of `ray`: emission on the way, the light sample and the virtual lights
// at the first non-delta vertex, and the compensation if asked. layers (if not empty): [0]
// emission and direct light, [1] the virtual lights, [2] the compensation.
Color instant_radiosity(const Bidir& b, std::span<const VirtualLight> lights, int count,
                        const Ray& ray, Rng& rng, const VplSettings& settings,
                        std::span<Color> layers);

}  // namespace lessons
