// Lesson 5, section 3: the MIS weights of the strategies (see mis.h).
#include "mis.h"

#include <vector>

namespace lessons {

namespace {

// One vertex of the path as the weights see it: the density of making it from the light side,
// from the camera side, and whether it scattered by a delta BSDF.
struct VertexDensities {
    double from_light = 0.0, from_camera = 0.0;
    bool delta = false;
};

// A density of 0 belongs to a delta choice here (the strategies that would need it are left out
// by the delta flags), and counts as 1 in the ratios (pbrt's remap0). The one other zero, a light
// the sampler never chooses (its power is not finite), would count as 1 too: such a scene is
// refused long before (scene files bound every emission and size).
double nonzero(double pdf) {
    return pdf != 0.0 ? pdf : 1.0;
}

}  // namespace

float mis_weight(const Bidir& b, std::span<const Vertex> light, int s,
                 std::span<const Vertex> camera, int t, const Vertex* light_sample,
                 const Vertex* camera_end) {
    const int n = s + t;
    // x_i, from the light end: light[i] for i < s, then camera[n - 1 - i].
    auto x = [&](int i) -> const Vertex& {
        if (i < s) return (s == 1 && light_sample) ? *light_sample : light[i];
        const int j = n - 1 - i;
        return (t == 1 && camera_end) ? *camera_end : camera[j];
    };
    thread_local std::vector<VertexDensities> d;
    d.assign(n, {});
    for (int i = 0; i < n; ++i) {
        const Vertex& v = x(i);
        d[i] = i < s ? VertexDensities{v.pdf_fwd, v.pdf_rev, v.delta}
                     : VertexDensities{v.pdf_rev, v.pdf_fwd, v.delta};
    }
    // The join, q = x_{s-1} to p = x_s: their densities from the other side, and their
    // neighbours'. When s = 0, p is on a light: the light subpath would have started there.
    const Vertex* q = s > 0 ? &x(s - 1) : nullptr;
    const Vertex& p = x(s);
    d[s].from_light = q ? density_towards(b, *q, s > 1 ? &x(s - 2) : nullptr, p)
                        : light_origin_density(b, p);
    if (t > 1)
        d[s + 1].from_light = q ? density_towards(b, p, q, x(s + 1))
                                : light_emission_density(b, p, x(s + 1));
    if (q) d[s - 1].from_camera = density_towards(b, p, t > 1 ? &x(s + 1) : nullptr, *q);
    if (s > 1) d[s - 2].from_camera = density_towards(b, *q, &p, x(s - 2));
    // The join's ends are joined, not scattered.
    d[s].delta = false;
    if (q) d[s - 1].delta = false;

    // The light sample (s = 1, t >= 2) picks x_0 with its own density, not the light subpath's
    // start: strategy 1 has it in place of p_L(x_0), and the ratios between strategies 0, 1 and 2
    // swap it in and out.
    const double sampled_x0 =
        n >= 3 ? nonzero(x(0).pdf_light_sample) : nonzero(d[0].from_light);
    const double started_x0 = nonzero(d[0].from_light);
    auto from_light = [&](int i, int strategy) {
        return i == 0 && strategy == 1 ? sampled_x0 : nonzero(d[i].from_light);
    };

    const bool sky = x(0).infinite, point_light = x(0).point_light;
    double sum = 0.0;
    // Strategies with the join nearer the camera: x_{k-1} made from the light side instead.
    double ratio = 1.0;
    for (int k = s + 1; k < n; ++k) {
        ratio *= from_light(k - 1, k) / nonzero(d[k - 1].from_camera);
        if (k == 2) ratio *= started_x0 / sampled_x0;  // x_0: a light sample no longer
        // The sky starts no light subpaths: only a light sample (s = 1, t >= 2) finds it.
        if (sky && (k >= 2 || k == n - 1)) break;
        if (!d[k - 1].delta && !d[k].delta) sum += ratio * ratio;
    }
    // Strategies with the join nearer the light: x_k made from the camera side instead.
    ratio = 1.0;
    for (int k = s - 1; k >= 0; --k) {
        ratio *= nonzero(d[k].from_camera) / from_light(k, k + 1);
        if (k == 1) ratio *= sampled_x0 / started_x0;  // x_0: now from a light sample
        const bool joins = k == 0 ? !point_light : !d[k - 1].delta && !d[k].delta;
        if (joins) sum += ratio * ratio;
    }
    return static_cast<float>(1.0 / (1.0 + sum));
}

}  // namespace lessons
