// Lesson 5, section 3: the MIS weights of the strategies (see mis.h).
#include "05_bidirectional/mis.h"

#include <cmath>
#include <vector>

#include "05_bidirectional/ratio_walk.h"

namespace lessons {

bool pixel_inside_lamp(const Bidir& b, const Vertex& on_light) {
    const std::optional<PrimRef> prim = on_light.primitive();
    if (!prim || on_light.infinite || on_light.delta_light()) return false;
    const Vec3 to_light = on_light.p - b.camera.position();
    const float d2 = glm::dot(to_light, to_light);
    if (!(d2 > 0.0f)) return false;
    const std::optional<Vec2> raster =
        b.camera.raster_position(to_light / std::sqrt(d2), b.width, b.height);
    if (!raster) return false;
    const glm::ivec2 pixel = pixel_at(b, *raster);  // the pixel light tracing splats to
    const float x = static_cast<float>(pixel.x), y = static_cast<float>(pixel.y);
    for (const Vec2 corner :
         {Vec2(x, y), Vec2(x + 1.0f, y), Vec2(x, y + 1.0f), Vec2(x + 1.0f, y + 1.0f)})
        if (!b.scene.meets(*prim, b.camera.generate_ray(corner.x, corner.y, b.width, b.height)))
            return false;
    return true;
}

namespace {

// A technique's path x_0 .. x_{n-1}, from the light end: light[i] for i < s, then
// camera[n - 1 - i], with the vertices the strategy made itself in their places.
struct TechniquePath {
    std::span<const Vertex> light, camera;
    int s, t;
    const Vertex* light_sample;
    const Vertex* camera_end;
    const Vertex& operator()(int i) const {
        if (i < s) return (s == 1 && light_sample) ? *light_sample : light[i];
        const int j = s + t - 1 - i;
        return (t == 1 && camera_end) ? *camera_end : camera[j];
    }
};

// Every vertex's densities from both sides, as the subpaths stored them, with those the join of
// q = x_{s-1} to p = x_s changes made anew (at its ends and their neighbours), and the delta
// chains unfolded (through_delta_chains, ratio_walk.h).
void technique_densities(const Bidir& b, const TechniquePath& x, std::vector<VertexDensities>& d) {
    const int s = x.s, t = x.t, n = s + t;
    d.assign(n, {});
    for (int i = 0; i < n; ++i) {
        const Vertex& v = x(i);
        d[i] = i < s ? VertexDensities{v.pdf_fwd, v.pdf_rev, v.delta}
                     : VertexDensities{v.pdf_rev, v.pdf_fwd, v.delta};
    }
    const Vertex* q = s > 0 ? &x(s - 1) : nullptr;
    const Vertex& p = x(s);
    // p and x_{s+1} from the light side. When s = 0, p is on a light: the light subpath would
    // have started there.
    d[s].from_light =
        q ? density_towards(b, *q, s > 1 ? &x(s - 2) : nullptr, p) : light_origin_density(b, p);
    if (t > 1)
        d[s + 1].from_light =
            q ? density_towards(b, p, q, x(s + 1)) : light_emission_density(b, p, x(s + 1));
    // q and x_{s-2} from the camera side.
    if (q) d[s - 1].from_camera = density_towards(b, p, t > 1 ? &x(s + 1) : nullptr, *q);
    if (s > 1) d[s - 2].from_camera = density_towards(b, *q, &p, x(s - 2));
    // The join's ends are joined, not scattered.
    d[s].delta = false;
    if (q) d[s - 1].delta = false;
    through_delta_chains(x, n, d);
}

// The relative densities of every technique for one path, against strategy (s, t) that made it,
// the path x_0 .. x_{n-1} being light[0 .. s-1] + camera[t-1 .. 0] (with the vertices the
// strategy made itself, as in mis_weight). Returns the sum over the strategies k != s of
// (p_k / p_s)^2 and, with an extra technique (mis.h), over its terms at every vertex j != s;
// `extra_at_s` receives its ratio at x_s itself (0 without one, or where it cannot make the path).
double other_techniques(const Bidir& b, std::span<const Vertex> light, int s,
                        std::span<const Vertex> camera, int t, const Vertex* light_sample,
                        const Vertex* camera_end, const ExtraTechnique* extra, double& extra_at_s) {
    const int n = s + t;
    const TechniquePath x{light, camera, s, t, light_sample, camera_end};
    thread_local std::vector<VertexDensities> d;
    technique_densities(b, x, d);
    const FirstVertex x0_density(x(0), d[0], n);
    // p_k / p_s = (x_0's density in strategy k / in s) times the ratio of the rest
    // (towards_camera, towards_light).
    const double own_x0 = divisor(x0_density(s));
    auto join = [&](int k, double m) { return x0_density(k) / own_x0 * m; };
    // The extra technique at x_j is told strategy j's ratio with x_0 started by a light subpath.
    auto extra_ratio = [&](int j, double m_j) {
        return extra ? extra->ratio_at(j, n, x0_density.started / own_x0 * m_j, d[j]) : 0.0;
    };
    double sum = 0.0;
    towards_camera(d, s, n, 2, join, extra_ratio, sum);
    towards_light(d, s, join, extra_ratio, sum);
    extra_at_s = extra_ratio(s, 1.0);
    return sum;
}

}  // namespace

float mis_weight(const Bidir& b, std::span<const Vertex> light, int s,
                 std::span<const Vertex> camera, int t, const Vertex* light_sample,
                 const Vertex* camera_end, const ExtraTechnique* extra) {
    const int n = s + t;
    // A lamp seen directly, inside its image: the camera's alone (pixel_inside_lamp, mis.h).
    if (n == 2) {
        const Vertex& x0 = s == 0 ? camera[1] : (s == 1 && light_sample) ? *light_sample : light[0];
        if (pixel_inside_lamp(b, x0)) return s == 0 ? 1.0f : 0.0f;
    }
    // The power heuristic (Veach 1997, section 9.2): 1 / sum over all techniques k of
    // (p_k / p_s)^2, the strategy's own term being 1; an extra technique at x_s counts too.
    double extra_at_s = 0.0;
    const double others =
        other_techniques(b, light, s, camera, t, light_sample, camera_end, extra, extra_at_s);
    return static_cast<float>(1.0 / (1.0 + others + extra_at_s * extra_at_s));
}

}  // namespace lessons
