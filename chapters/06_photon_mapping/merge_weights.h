// Lesson 6, section 7: the MIS weights of vertex merging (vcm; merging.cpp runs the merges).
// Lesson 5 weighs each strategy by the power heuristic over every technique that can make the
// path (mis.h); vertex connection and merging adds a merge at the path's vertices, as lesson 5's
// extra technique (ExtraTechnique, mis.h), and weighs each merge against all of them by the same
// walk over the densities' ratios (ratio_walk.h).
//
// Merging at x_j takes x_0 .. x_j from the light subpath (x_j landing within r of the camera
// subpath's x_j) and x_j .. x_{n-1} from the camera subpath. Its density is strategy j's with x_j
// made twice, once from each side, the light side's landing anywhere in the disk of area pi r^2
// about the camera's: p_merge(j) = p_j p_L(x_j) pi r^2, times N, as each camera subpath meets
// the photons of N light subpaths where a join meets one (Georgiev et al. 2012, section 4.2;
// Hachisuka et al. 2012, eq. 9):
//   p_merge(j) = p_j p_L(x_j) eta,   eta = N pi r^2.
// Merges need a vertex that scatters by a non-delta BSDF with a light subpath of two vertices or
// more (x_0 leaves no photon) and a camera subpath of two or more.
#pragma once

#include <span>

#include "05_bidirectional/mis.h"
#include "05_bidirectional/ratio_walk.h"
#include "05_bidirectional/subpaths.h"

namespace lessons {

// The merges as lesson 5's extra technique: at x_j, 1 <= j <= n - 2, not a mirror or glass,
// p_merge(j) / p_s = (p_j / p_s, x_0 started by a light subpath) eta p_L(x_j); 0 elsewhere, and
// everywhere when eta is 0. Lesson 5's mis_weight with it weighs a join against every merge.
class MergeTechnique final : public ExtraTechnique {
public:
    explicit MergeTechnique(double eta) : eta_(eta) {}
    double ratio_at(int j, int n, double started, const VertexDensities& d_j) const override;

private:
    double eta_;  // N pi r^2: N light subpaths' photons gathered within radius r
};

// The power-heuristic weight of merging at x_s = camera[t - 1]: the light subpath
// light[0 .. s-1] went on to `photon`, a vertex within r of camera[t - 1], and the two are taken
// as one, x_s (s >= 1, t >= 2). Against every join and every other merge of the path, with
// eta = N pi r^2 as above. The light side's densities are the photon's (where it landed, where
// its light came from), the camera side's camera[t - 1]'s, and the BSDF at x_s is
// camera[t - 1]'s: exactly mis_weight's with MergeTechnique when the photon lies on
// camera[t - 1], and within the merge's own blur otherwise (Georgiev et al. 2012 make the same
// choice).
float merge_weight(const Bidir& b, std::span<const Vertex> light, int s, const Vertex& photon,
                   std::span<const Vertex> camera, int t, double eta);

// The same weight in the two halves a merge brings together, so that each is computed once: the
// light side once per photon, the camera side once per camera vertex, and per pair only the two
// densities of scattering at x_s (per steradian, by camera[t - 1]'s BSDF):
//   reverse  arriving from x_{s+1} (the camera's side), towards x_{s-1} (the photon's light);
//   forward  arriving from x_{s-1}, towards x_{s+1}.
// The power heuristic against the merge itself: w = 1 / (1 + the other techniques' terms), those
// terms being light.own_join + reverse^2 light.per_reverse2 + camera.fixed + forward^2
// camera.per_forward2 (merge_weights.cpp).
struct MergeLightSide {
    bool possible = false;      // whether a merge can make the path at all
    double per_reverse2 = 0.0;  // the joins and merges between x_s and the light
    double own_join = 0.0;      // strategy s, the join of x_{s-1} to x_s
};
struct MergeCameraSide {
    Vec3 towards_camera{0.0f};  // unit, from camera[t - 1] to camera[t - 2]
    double fixed = 0.0;         // strategy s + 1, the join of x_s to x_{s+1}
    double per_forward2 = 0.0;  // every other join and merge between x_s and the camera
    bool possible() const { return towards_camera != Vec3(0.0f); }
};
// light: y_0 .. y_{s-1}; photon: y_s.
MergeLightSide merge_light_side(const Bidir& b, std::span<const Vertex> light, const Vertex& photon,
                                double eta);
MergeCameraSide merge_camera_side(std::span<const Vertex> camera, int t, double eta);
float merge_weight(const MergeLightSide& light, const MergeCameraSide& camera, double reverse,
                   double forward);

}  // namespace lessons
