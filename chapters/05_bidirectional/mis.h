// Lesson 5, section 3: multiple importance sampling over every strategy. Reference: E. Veach,
// "Robust Monte Carlo Methods for Light Transport Simulation", PhD thesis, Stanford, 1997
// ("Veach 1997" below), section 10.2.
//
// A path of n vertices x_0 (on a light) ... x_{n-1} (the camera) can be made by n strategies at
// most: s vertices from the light subpath and t = n - s from the camera subpath, joined by one
// segment. Strategy s makes the path with density
//   p_s = p_L(x_0) ... p_L(x_{s-1}) * p_C(x_s) ... p_C(x_{n-2})
// (each vertex by the density of the side that made it: pdf_fwd on its own side, pdf_rev from
// the other). The power heuristic with exponent 2 (Veach 1997, section 9.2) weighs the strategy
// used against all of them,
//   w_s = p_s^2 / sum_i p_i^2 = 1 / sum_i (p_i / p_s)^2,
// and the ratios need no products of whole paths (Veach 1997, eq. 10.9, the ratio p_{i+1} / p_i
// written with densities per unit area): moving the join one vertex towards the camera multiplies
// the density by p_L(x_s) / p_C(x_s), one towards the light by p_C(x_{s-1}) / p_L(x_{s-1}). Only
// the densities at the join's two ends, and at their neighbours, depend on the join itself; they
// are computed here, the rest were stored as the subpaths were traced.
//
// Left out of the sum: strategies that would join a segment at a mirror or glass (a delta BSDF
// has no density to meet), and every strategy whose density is 0, which cannot make the path:
// s = 0 for a point light (no camera path hits a point), s >= 2 and light tracing for the
// environment (it starts no light subpaths), and any strategy that needs a light the sampler
// never chooses or light leaving the back of a one-sided lamp. A delta choice (mirror, glass)
// is the same from both sides (specular surfaces: Veach 1997, section 10.3), so its densities
// are left out of every ratio (taken as 1), and the vertices on either side of a chain of them
// get the densities of the whole chain's unfolded length (exact for flat mirrors only: see
// through_delta_chains in ratio_walk.h). The light sample (s = 1) picks x_0 by lesson 3's density
// (by solid angle where it can), the light subpath by the light's area: each strategy's ratio
// uses its own.
#pragma once

#include <span>

#include "05_bidirectional/ratio_walk.h"
#include "05_bidirectional/subpaths.h"

namespace lessons {

// Paths of one segment, a lamp seen directly, have two strategies: the camera's ray hitting the
// lamp (s = 0, t = 2) and the light subpath's first point joined to the camera (s = 1, t = 1).
// The power heuristic gives them almost wholly to the second: a point on a small lamp is far
// likelier to be picked from the lamp (one over its area) than hit by the one ray a pass sends
// through its pixel. But light tracing scatters its points over the lamp's pixels at random,
// while in a pixel that the lamp's image covers wholly every camera ray of the pixel meets the
// lamp: there, unless something in front hides part of it, the camera's estimate is the lamp's
// radiance averaged over the pixel, exact for a uniform lamp. So in such a pixel the camera
// takes the whole weight (s = 0: 1, s = 1: 0); at the lamp's outline, where light tracing's many
// points do better than the pixel's few rays, the power heuristic stays. Any weights that sum to
// one over the strategies of each path keep the estimate (the weighted sum of Veach 1997,
// eq. 10.3) unbiased; these depend only on the path (the pixel that x_0 projects to, and the
// primitive it lies on), so both strategies compute the same ones.
//
// Whether `on_light` (x_0 of a one-segment path: a point on an emissive primitive, reached by a
// camera ray or starting a light subpath) lies in a pixel (the one light tracing would splat it
// to) whose four corner rays all meet that primitive: its image is convex (a quad, a triangle,
// a sphere seen from outside), so then it covers the whole pixel.
bool pixel_inside_lamp(const Bidir& b, const Vertex& on_light);

// A hook for another technique that a later lesson adds beside these strategies, one at each
// vertex x_j of the path: its density there is strategy j's (x_0 .. x_{j-1} from a light subpath
// that starts at x_0, x_j .. x_{n-1} from the camera subpath) times a factor of its own, so it is
// weighed by the strategies' own walk (ratio_walk.h). ratio_at(j, n, started, d_j) is its density
// at x_j, on a path of n vertices, over the density of the strategy s that made the path, given
// `started`, strategy j's ratio to s with x_0 made as a light subpath's start
// (FirstVertex::started), and x_j's densities d_j; 0 where it cannot make the path.
class ExtraTechnique {
public:
    virtual ~ExtraTechnique() = default;
    virtual double ratio_at(int j, int n, double started, const VertexDensities& d_j) const = 0;
};

// The power-heuristic weight of strategy (s, t) for the path light[0 .. s-1] + camera[t-1 .. 0].
// The vertices the strategy made itself, if any: `light_sample` instead of light[0] when s = 1
// (a light sample at z_{t-1}), `camera_end` instead of camera[0] when t = 1 (the camera, joined
// to a light vertex). With `extra`, its technique at every vertex that can make the path (x_s
// included) counts too; without (this lesson), the strategies alone.
float mis_weight(const Bidir& b, std::span<const Vertex> light, int s,
                 std::span<const Vertex> camera, int t, const Vertex* light_sample,
                 const Vertex* camera_end, const ExtraTechnique* extra = nullptr);

}  // namespace lessons
