// Lesson 5, section 3: the MIS weights of the strategies (see mis.h).
#include "05_bidirectional/mis.h"

#include <cmath>
#include <vector>

namespace lessons {

namespace {

// One vertex of the path as the weights see it: the density of making it from the light side,
// from the camera side, and whether it scattered by a delta BSDF.
struct VertexDensities {
    double from_light = 0.0, from_camera = 0.0;
    bool delta = false;
};

// A density at a vertex the current strategy made itself, as a divisor: never 0 there (it made
// the vertex), but a density rounded to 0 must not divide (taken as 1, as pbrt's remap0). Every
// other density of 0 means what it says: the strategy that needs it cannot make the path, and
// leaves the sum (a light the sampler never chooses, the back of a one-sided lamp).
double divisor(double pdf) {
    return pdf > 0.0 ? pdf : 1.0;
}

// |cos| at vertex v of the segment towards w (1 at a point: the camera, a point light).
double abs_cos(const Vertex& v, const Vertex& w) {
    return v.n == Vec3(0.0f) ? 1.0 : std::fabs(glm::dot(v.n, direction(v, w)));
}

// A chain of mirror or glass vertices x_i .. x_j between two vertices that scatter
// non-deltas, x_{i-1} and x_{j+1}, is made the same way from both sides, so its own densities
// are left out (1). What differs is where the chain lands: a direction sampled at x_{i-1} with
// density p (per steradian) reaches x_{j+1} with density p |cos| / D^2 per unit area (the
// conversion from solid angle to area, Veach 1997, eq. 8.10), D the chain's unfolded length
// (exact for flat mirrors; refraction and curved glass also change the solid angle, which this
// leaves out: a matter of efficiency, as any weights that sum to one keep the estimate
// unbiased). Without it, a vertex right beside a glass ball (a floor it touches) would look far
// likelier to be found from the camera than it is.
template <class VertexAt>
void through_delta_chains(VertexAt&& x, int n, std::vector<VertexDensities>& d) {
    for (int i = 1; i < n - 1; ++i) {
        if (!d[i].delta) continue;
        int j = i;
        while (j + 1 < n - 1 && d[j + 1].delta) ++j;
        const Vertex &before = x(i - 1), &after = x(j + 1);
        if (before.directional) {
            // Parallel light keeps its cross-section through flat mirrors: per m^2 across the
            // beam, times |cos| where it lands (and no camera path reaches the light).
            d[j + 1].from_light = d[i].from_light / abs_cos(x(i), before) * abs_cos(after, x(j));
        } else if (!before.infinite) {
            double unfolded = 0.0;
            for (int k = i - 1; k <= j; ++k) unfolded += glm::length(x(k + 1).p - x(k).p);
            // p at x_{i-1} from x_i's density, and p at x_{j+1} from x_j's, back to solid angle.
            const double d_first = glm::length(x(i).p - before.p);
            const double d_last = glm::length(after.p - x(j).p);
            const double light_side = d[i].from_light * d_first * d_first / abs_cos(x(i), before);
            const double camera_side = d[j].from_camera * d_last * d_last / abs_cos(x(j), after);
            d[j + 1].from_light = light_side * abs_cos(after, x(j)) / (unfolded * unfolded);
            d[i - 1].from_camera = camera_side * abs_cos(before, x(i)) / (unfolded * unfolded);
        }
        for (int k = i; k <= j; ++k) d[k].from_light = d[k].from_camera = 1.0;
        i = j;
    }
}

// The power heuristic's terms (p_k / p_s)^2 of the techniques whose join or merge lies between x_s
// and the camera, k = s + 1 .. n - 1, added to `sum`. As the join moves past x_{k-1} towards the
// camera, the ratio of the rest of the path's densities, m, changes by p_L(x_{k-1}) /
// p_C(x_{k-1}) (Veach 1997, eq. 10.9; from k = first on: before it, x_0's density is the
// technique's own, in join); join(k, m) is strategy k's ratio, merge(k, m) the merge at x_k's (0
// where there is none). A zero on the way makes every technique beyond it impossible. Strategies
// that would join at a mirror or glass have no density to meet and are left out.
template <class Join, class Merge>
void towards_camera(const std::vector<VertexDensities>& d, int s, int n, int first, Join&& join,
                    Merge&& merge, double& sum) {
    double m = 1.0;
    for (int k = s + 1; k < n; ++k) {  // the join nearer the camera: x_{k-1} from the light
        if (k >= first) m *= d[k - 1].from_light / divisor(d[k - 1].from_camera);
        const double ratio = join(k, m);
        if (!d[k - 1].delta && !d[k].delta) sum += ratio * ratio;
        const double merged = merge(k, m);
        sum += merged * merged;
    }
}

// The same for the techniques between x_s and the light, k = s - 1 .. 0: m changes by
// p_C(x_k) / p_L(x_k) as the join moves past x_k (k >= 1) towards the light.
template <class Join, class Merge>
void towards_light(const std::vector<VertexDensities>& d, int s, Join&& join, Merge&& merge,
                   double& sum) {
    double m = 1.0;
    for (int k = s - 1; k >= 0; --k) {  // the join nearer the light: x_k from the camera
        if (k >= 1) m *= d[k].from_camera / divisor(d[k].from_light);
        const double ratio = join(k, m);
        if (k == 0 || (!d[k - 1].delta && !d[k].delta)) sum += ratio * ratio;
        const double merged = merge(k, m);
        sum += merged * merged;
    }
}

}  // namespace

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
// chains' unfolded (through_delta_chains).
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

// x_0 is made differently by different techniques (Veach 1997, 10.2.2): strategy 0's camera path
// hits it (no camera path hits a point or directional light: 0); strategy 1's light sample picks it
// (lesson 3's density, by solid angle where it can; for a lamp seen directly, n = 2, strategy 1 is
// light tracing and starts there); every other strategy starts its light subpath there (the sky
// starts none: 0), and so does every merge.
struct FirstVertex {
    double hit = 0.0, sampled = 0.0, started = 0.0;
    FirstVertex(const Vertex& x0, const VertexDensities& d0, int n)
        : hit(x0.delta_light() ? 0.0 : d0.from_camera),
          sampled(n >= 3 ? x0.pdf_light_sample : (x0.infinite ? 0.0 : d0.from_light)),
          started(x0.infinite ? 0.0 : d0.from_light) {}
    double operator()(int technique) const {
        return technique == 0 ? hit : technique == 1 ? sampled : started;
    }
};

// The relative densities of every technique for one path, against strategy (s, t) that made it,
// the path x_0 .. x_{n-1} being light[0 .. s-1] + camera[t-1 .. 0] (with the vertices the
// strategy made itself, as in mis_weight). Returns the sum over the connection strategies k != s
// of (p_k / p_s)^2 and, with merging (eta > 0), over the merges at every vertex j != s of
// (p_merge(j) / p_s)^2; `merged` (if not null) receives p_merge(s) / p_s, the merge at x_s itself
// (0 where none can be made).
double other_techniques(const Bidir& b, std::span<const Vertex> light, int s,
                        std::span<const Vertex> camera, int t, const Vertex* light_sample,
                        const Vertex* camera_end, double eta, double* merged) {
    const int n = s + t;
    const TechniquePath x{light, camera, s, t, light_sample, camera_end};
    thread_local std::vector<VertexDensities> d;
    technique_densities(b, x, d);
    const FirstVertex x0_density(x(0), d[0], n);
    // p_k / p_s = (x_0's density in strategy k / in s) times the ratio of the rest
    // (towards_camera, towards_light).
    //
    // Lesson 6's merges: merging at x_j takes x_0 .. x_j from the light subpath (x_j landing
    // within r of the camera subpath's x_j) and x_j .. x_{n-1} from the camera subpath. Its
    // density is strategy j's with x_j made twice, once from each side, the light side's landing
    // anywhere in the disk of area pi r^2 about the camera's: p_merge(j) = p_j p_L(x_j) pi r^2,
    // times N, as each camera subpath meets the photons of N light subpaths where a join meets
    // one (Georgiev et al. 2012, section 4.2; Hachisuka et al. 2012, eq. 9). eta = N pi r^2.
    // Merges need a vertex that scatters by a non-delta BSDF with a light subpath of two
    // vertices or more (x_0 leaves no photon) and a camera subpath of two or more.
    const double own_x0 = divisor(x0_density(s));
    auto merge_ratio = [&](int j, double m_j) {
        if (j < 1 || j > n - 2 || d[j].delta) return 0.0;
        return x0_density.started / own_x0 * m_j * eta * d[j].from_light;
    };
    double sum = 0.0;
    auto join = [&](int k, double m) { return x0_density(k) / own_x0 * m; };
    auto merge = [&](int k, double m) { return eta > 0.0 ? merge_ratio(k, m) : 0.0; };
    towards_camera(d, s, n, 2, join, merge, sum);
    towards_light(d, s, join, merge, sum);
    if (merged) *merged = eta > 0.0 ? merge_ratio(s, 1.0) : 0.0;
    return sum;
}

}  // namespace

float mis_weight(const Bidir& b, std::span<const Vertex> light, int s,
                 std::span<const Vertex> camera, int t, const Vertex* light_sample,
                 const Vertex* camera_end, double merge_eta) {
    const int n = s + t;
    // A lamp seen directly, inside its image: the camera's alone (pixel_inside_lamp, mis.h).
    if (n == 2) {
        const Vertex& x0 = s == 0 ? camera[1] : (s == 1 && light_sample) ? *light_sample : light[0];
        if (pixel_inside_lamp(b, x0)) return s == 0 ? 1.0f : 0.0f;
    }
    // The power heuristic (Veach 1997, section 9.2): 1 / sum over all techniques k of
    // (p_k / p_s)^2, the strategy's own term being 1; with merging, the merge at x_s counts too.
    double merged = 0.0;
    const double others = other_techniques(b, light, s, camera, t, light_sample, camera_end,
                                           merge_eta, merge_eta > 0.0 ? &merged : nullptr);
    return static_cast<float>(1.0 / (1.0 + others + merged * merged));
}

// A merge's weight in two halves (mis.h). Against the merge at x_s itself, the power heuristic's
// terms are the same ratios as above divided by p_merge(s) / p_s = started eta p_L(x_s) / own:
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

float merge_weight(const Bidir& b, std::span<const Vertex> light, int s, const Vertex& photon,
                   std::span<const Vertex> camera, int t, double merge_eta) {
    const MergeCameraSide camera_side = merge_camera_side(camera, t, merge_eta);
    if (!camera_side.possible()) return 0.0f;
    const Bsdf& bsdf = *camera[t - 1].bsdf;
    const Vec3 to_light = direction(photon, light[s - 1]);  // the photon's si.wo
    const Vec3& to_camera = camera_side.towards_camera;
    return merge_weight(merge_light_side(b, light.first(s), photon, merge_eta), camera_side,
                        bsdf.pdf_seen_from(to_camera, to_light),
                        bsdf.pdf_seen_from(to_light, to_camera));
}

}  // namespace lessons
