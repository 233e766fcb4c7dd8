// Lesson 5, section 3: what the weights of mis.h walk over. The power heuristic needs the ratio
// p_k / p_s of every strategy k to the one that made the path, and these come one vertex at a
// time (Veach 1997, eq. 10.9): the densities of each vertex from both sides (VertexDensities),
// with those of mirror and glass chains unfolded (through_delta_chains); x_0's density under each
// strategy (FirstVertex); and the two walks from x_s, towards the camera and towards the light,
// that multiply the ratio by one vertex's p_L / p_C at each step. They are in a header of their
// own because a later lesson that adds a technique of its own weighs it with the same walk.
#pragma once

#include <cmath>
#include <vector>

#include "05_bidirectional/subpaths.h"

namespace lessons {

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
inline double divisor(double pdf) {
    return pdf > 0.0 ? pdf : 1.0;
}

// |cos| at vertex v of the segment towards w (1 at a point: the camera, a point light).
inline double abs_cos(const Vertex& v, const Vertex& w) {
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
// likelier to be found from the camera than it is. x(i) is the path's vertex x_i, d its n
// vertices' densities.
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

// The power heuristic's terms (p_k / p_s)^2 of the strategies whose join lies between x_s and
// the camera, k = s + 1 .. n - 1, added to `sum`. As the join moves past x_{k-1} towards the
// camera, the ratio of the rest of the path's densities, m, changes by p_L(x_{k-1}) /
// p_C(x_{k-1}) (Veach 1997, eq. 10.9; from k = first on: before it, x_0's density is the
// strategy's own, in join); join(k, m) is strategy k's ratio. extra(k, m) is the ratio of another
// technique at x_k (one a later lesson adds; 0 where there is none), whose term is added beside
// the join's. A zero on the way makes every technique beyond it impossible. Strategies that
// would join at a mirror or glass have no density to meet and are left out.
template <class Join, class Extra>
void towards_camera(const std::vector<VertexDensities>& d, int s, int n, int first, Join&& join,
                    Extra&& extra, double& sum) {
    double m = 1.0;
    for (int k = s + 1; k < n; ++k) {  // the join nearer the camera: x_{k-1} from the light
        if (k >= first) m *= d[k - 1].from_light / divisor(d[k - 1].from_camera);
        const double ratio = join(k, m);
        if (!d[k - 1].delta && !d[k].delta) sum += ratio * ratio;
        const double other = extra(k, m);
        sum += other * other;
    }
}

// The same for the techniques between x_s and the light, k = s - 1 .. 0: m changes by
// p_C(x_k) / p_L(x_k) as the join moves past x_k (k >= 1) towards the light.
template <class Join, class Extra>
void towards_light(const std::vector<VertexDensities>& d, int s, Join&& join, Extra&& extra,
                   double& sum) {
    double m = 1.0;
    for (int k = s - 1; k >= 0; --k) {  // the join nearer the light: x_k from the camera
        if (k >= 1) m *= d[k].from_camera / divisor(d[k].from_light);
        const double ratio = join(k, m);
        if (k == 0 || (!d[k - 1].delta && !d[k].delta)) sum += ratio * ratio;
        const double other = extra(k, m);
        sum += other * other;
    }
}

// x_0 is made differently by different strategies (Veach 1997, 10.2.2): strategy 0's camera path
// hits it (no camera path hits a point or directional light: 0); strategy 1's light sample picks
// it (lesson 3's density, by solid angle where it can; for a lamp seen directly, n = 2, strategy 1
// is light tracing and starts there); every other strategy starts its light subpath there (the
// sky starts none: 0), as does any other technique that traces a light subpath. d0 is x_0's
// densities, n the path's vertices; x0_density(k) is strategy k's.
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

}  // namespace lessons
