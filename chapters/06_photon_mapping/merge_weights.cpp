// Lesson 6, section 7: the MIS weights of vertex merging (see merge_weights.h).
#include "06_photon_mapping/merge_weights.h"

#include <cmath>
#include <vector>

namespace lessons {

double MergeTechnique::ratio_at(int j, int n, double started, const VertexDensities& d_j) const {
    // No photon at x_0 (a light subpath of one vertex) or at the camera, none at a mirror or
    // glass; and no merges at eta = 0.
    if (!(eta_ > 0.0) || j < 1 || j > n - 2 || d_j.delta) return 0.0;
    return started * eta_ * d_j.from_light;  // (p_j / p_s) p_L(x_j) eta
}

// The weight of one merge from its two halves (below), with the two densities of scattering at
// x_s by camera[t - 1]'s BSDF, the photon's arrival from x_{s-1} standing for its direction.
float merge_weight(const Bidir& b, std::span<const Vertex> light, int s, const Vertex& photon,
                   std::span<const Vertex> camera, int t, double eta) {
    const MergeCameraSide camera_side = merge_camera_side(camera, t, eta);
    if (!camera_side.possible()) return 0.0f;
    const Bsdf& bsdf = *camera[t - 1].bsdf;
    const Vec3 to_light = direction(photon, light[s - 1]);  // the photon's si.wo
    const Vec3& to_camera = camera_side.towards_camera;
    return merge_weight(merge_light_side(b, light.first(s), photon, eta), camera_side,
                        bsdf.pdf_seen_from(to_camera, to_light),
                        bsdf.pdf_seen_from(to_light, to_camera));
}

// A merge's weight in two halves (merge_weights.h). Against the merge at x_s itself, the power
// heuristic's terms are the ratios of lesson 5's walk (mis.cpp's other_techniques, with the merges
// as its extra technique) divided by p_merge(s) / p_s = started eta p_L(x_s) / own:
// x_0's own density cancels, and every term on the light side holds the camera side's density
// of scattering at x_s towards x_{s-1} once (squared), every term on the camera side but the
// first the light side's density of scattering at x_s towards x_{s+1}. Each half is computed
// with that density 1 (per steradian), and the two densities are put in per photon.

MergeLightSide merge_light_side(const Bidir& b, std::span<const Vertex> light, const Vertex& photon,
                                double eta) {
    const int s = static_cast<int>(light.size());  // the photon is x_s
    MergeLightSide side;
    if (s < 1 || !(eta > 0.0)) return side;
    auto x = [&](int i) -> const Vertex& { return i < s ? light[i] : photon; };
    thread_local std::vector<VertexDensities> d;
    d.assign(s + 1, {});
    for (int i = 0; i < s; ++i) d[i] = {light[i].pdf_fwd, light[i].pdf_rev, light[i].delta};
    d[s] = {photon.pdf_fwd, 1.0, false};
    const Vertex& q = light[s - 1];
    d[s - 1].from_camera = to_area_density(1.0f, photon, q);  // scattering at x_s: 1 per sr
    if (s > 1) d[s - 2].from_camera = density_towards(b, q, &photon, light[s - 2]);
    through_delta_chains(x, s + 1, d);
    // x_0's densities (a light sample at x_s picks it for strategy 1).
    FirstVertex x0_density(light[0], d[0], s + 2);
    if (s == 1) x0_density.sampled = light_sample_density(b, light[0], photon);
    const double merged =
        x0_density.started * eta * d[s].from_light;  // p_merge(s) / p_s, times own
    if (!(merged > 0.0) || !std::isfinite(merged)) return side;
    double sum = 0.0;
    towards_light(
        d, s, [&](int k, double m) { return x0_density(k) * m; },
        [&](int k, double m) {
            return k >= 1 && !d[k].delta ? x0_density.started * m * eta * d[k].from_light : 0.0;
        },
        sum);
    side.possible = true;
    side.per_reverse2 = sum / merged / merged;
    // Strategy s itself (unless x_{s-1} is a mirror or glass, or strategy s cannot pick x_0):
    // p_s / p_merge(s) = own / merged.
    const double own = x0_density(s);
    side.own_join = q.delta || !(own > 0.0) ? 0.0 : (own / merged) * (own / merged);
    return side;
}

MergeCameraSide merge_camera_side(std::span<const Vertex> camera, int t, double eta) {
    MergeCameraSide side;
    const Vertex& z = camera[t - 1];
    if (t < 2 || !(eta > 0.0) || z.type != VertexType::Surface || !z.bsdf || z.bsdf->is_delta())
        return side;
    side.towards_camera = direction(z, camera[t - 2]);
    // The camera side's vertices x_s .. x_{n-1} as y_0 .. y_{t-1}: y_i = camera[t - 1 - i].
    auto y = [&](int i) -> const Vertex& { return camera[t - 1 - i]; };
    thread_local std::vector<VertexDensities> d;
    d.assign(t, {});
    for (int i = 0; i < t; ++i) d[i] = {y(i).pdf_rev, y(i).pdf_fwd, y(i).delta};
    d[0].from_light = 1.0;  // p_L(x_s): it cancels
    d[0].delta = false;
    d[1].from_light = to_area_density(1.0f, z, y(1));  // scattering at x_s: 1 per sr
    through_delta_chains(y, t, d);
    // The join at x_s .. x_{s+1} (strategy s + 1) needs no density of the merge's: its ratio to
    // the merge is 1 / (eta p_C(x_s)).
    const double first = 1.0 / (eta * divisor(d[0].from_camera));
    side.fixed = d[1].delta ? 0.0 : first * first;
    towards_camera(
        d, 0, t, 1, [&](int k, double m) { return k == 1 ? 0.0 : m / eta; },
        [&](int k, double m) { return k <= t - 2 && !d[k].delta ? m * d[k].from_light : 0.0; },
        side.per_forward2);
    return side;
}

float merge_weight(const MergeLightSide& light, const MergeCameraSide& camera, double reverse,
                   double forward) {
    if (!light.possible || !camera.possible()) return 0.0f;
    const double others = light.own_join + reverse * reverse * light.per_reverse2 + camera.fixed +
                          forward * forward * camera.per_forward2;
    return static_cast<float>(1.0 / (1.0 + others));
}

}  // namespace lessons
