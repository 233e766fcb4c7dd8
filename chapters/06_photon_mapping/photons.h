// Lesson 6, section 3: tracing the photons. An iteration traces N light subpaths with lesson 5's
// light_subpath, and every vertex y_i (i >= 1) on a surface that does not scatter by a delta
// (mirror, glass) leaves a photon there: beta(y_i), the direction it came from, the surface's
// normal (photon_map.h). What each kind of light gives (LightSampler::sample_emission, as
// lesson 5's light_subpath calls it):
//   a point light of intensity I, chosen with probability P: y_0 its position, a direction
//     uniform on the sphere (1 / (4 pi) per sr), so every photon at y_1 carries
//     beta = I / P * 4 pi: its whole power 4 pi I, shared among the subpaths that chose it;
//   an area light of radiance L_e and area A, chosen with probability P: y_0 uniform on it
//     (P / A per m^2) and a direction cos-distributed about its emitting side (cos / pi per sr,
//     half of that per side for a two-sided light), so beta(y_1) = L_e cos / (P/A cos/pi) =
//     pi A L_e / P: again its power (times two for two sides), shared;
//   the environment (the sky, a map): lesson 5 starts no light subpath there (sample_emission
//     returns none, light_subpath an empty path). Photons from the sky are left out: its light
//     is found by next-event estimation and by camera paths that escape. A subpath that chose
//     the sky still counts among the N: the other lights' betas are divided by their own
//     choice probabilities, so (1/N) sum over photons stays an unbiased estimate of their light.
// y_0 itself leaves no photon: light that reaches the camera vertex straight from a light is
// direct light, which next-event estimation finds with far less noise than a density estimate.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "05_bidirectional/subpaths.h"
#include "06_photon_mapping/photon_map.h"

namespace lessons {

// One iteration's light subpaths, their photons, and the memory they hold.
struct LightPaths {
    // The subpaths in the parts they were traced in (one per thread: a contiguous range of
    // subpaths each, kept where it was made rather than copied into one array). A part's subpath
    // i is vertices[start[i] .. start[i + 1]) (y_0 first; empty when its light starts none).
    struct Part {
        size_t first = 0;  // the index of its first subpath
        std::vector<Vertex> vertices;
        std::vector<uint32_t> start;  // its subpaths + 1 offsets
    };
    std::vector<Part> parts;  // empty when the vertices were not kept
    // The photons, in subpath order and, within one, vertex order.
    std::vector<Photon> photons;
    int count = 0;      // N, the number of light subpaths traced (those that started none included)
    uint64_t rays = 0;  // rays traced to make them

    // Subpath j's vertices, y_0 first (empty when its light starts none, or when the vertices
    // were not kept).
    std::span<const Vertex> subpath(size_t j) const;
    // The vertex a photon lies on (the vertices must have been kept).
    const Vertex& vertex_of(const Photon& photon) const {
        return subpath(photon.path)[photon.vertex];
    }
    // Bytes of the subpaths and photons (the arrays' sizes: the same for any number of threads,
    // while their spare capacity is not).
    size_t bytes() const;
};

// The seed of the photons' random numbers: iteration k's subpath j draws from
// Rng(seed ^ kPhotonSeed, k, j) (sampling/rng.h), numbers of its own for each (seed, k, j)
// and apart from the camera's, which draw from Rng(seed, pixel, sample). They are independent
// (PCG32) whatever the --sampler: a randomised Kronecker sequence keyed per subpath would move
// each light subpath's numbers in lockstep with its pixel's camera numbers of the same
// dimension from pass to pass (the same alpha_d), which the joins of vcm pair up; measured on
// the Cornell box, that raised vcm's error by a fifth. ("photons" in ASCII.)
inline constexpr uint64_t kPhotonSeed = 0x70686f746f6e73ULL;

// The `count` light subpaths of iteration `iteration` and their photons, into `out` (whose
// arrays are reused: a render traces into the same memory every pass). Subpath j draws from
// Rng(seed ^ kPhotonSeed, iteration, j) and is light_subpath(b, rng, max_vertices,
// roulette_after) (y_0 counted among max_vertices; Russian roulette after roulette_after
// bounces, < 0 never). Traced on `threads` threads (0: every hardware thread), each a contiguous
// range of subpaths, the photons concatenated in order: as every subpath's random numbers depend
// on its index alone, the result is the same bits for any number of threads.
// With keep_vertices false, only the photons are kept (LightPaths::parts stays empty, and
// subpath and vertex_of may not be asked): photon mapping reads nothing else.
void trace_photons(const Bidir& b, uint64_t seed, int iteration, int count, int max_vertices,
                   int roulette_after, int threads, bool keep_vertices, LightPaths& out);
// The same into a new LightPaths.
LightPaths trace_photons(const Bidir& b, uint64_t seed, int iteration, int count, int max_vertices,
                         int roulette_after, int threads = 0, bool keep_vertices = true);

}  // namespace lessons
