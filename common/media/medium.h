// Participating media: a volume that absorbs and scatters light along a ray (fog, smoke, milk).
//
// A medium has, per unit length and per colour channel, an absorption coefficient sigma_a and a
// scattering coefficient sigma_s; their sum sigma_t is the extinction coefficient, the
// probability per unit length that light travelling through it collides with a particle, and
// sigma_s / sigma_t the albedo, the share of collisions that scatter rather than absorb. Where
// light scatters, the phase function (phase.h) says where it goes.
//
// In a homogeneous medium the coefficients are the same everywhere, and the fraction of light
// that crosses a distance d unscattered is Beer and Lambert's transmittance T(d) = exp(-sigma_t d)
// per channel. The radiance along a ray through it, to a surface at distance d (the volume
// rendering equation, without emission by the medium):
//   L(x, w) = T(d) L_surface + integral over t in [0, d] of T(t) sigma_s L_s(x - t w, w) dt,
// for the light arriving at x from direction w (travelling along -w), L_s the in-scattered
// radiance at the point t back along the ray: the phase function times the light arriving there
// from every direction. A path tracer estimates it by sampling the distance t to the next collision
// (sample_free_flight).
#pragma once

#include <string>

#include "geometry/math.h"
#include "media/phase.h"

namespace lessons {

struct Medium {
    std::string name;
    Color sigma_a{0.0f};  // absorption, per unit length (the scene's units), >= 0
    Color sigma_s{0.0f};  // scattering, per unit length, >= 0
    float g = 0.0f;       // the Henyey-Greenstein asymmetry, in (-1, 1)

    Color sigma_t() const { return sigma_a + sigma_s; }
    // sigma_s / sigma_t per channel (0 where sigma_t is 0).
    Color albedo() const;
    HenyeyGreenstein phase() const { return HenyeyGreenstein(g); }
    // exp(-sigma_t d) per channel: the fraction of light crossing `distance` (>= 0, may be
    // infinite) without a collision.
    Color transmittance(float distance) const;
    // Whether light crosses it unchanged (sigma_t = 0 in every channel).
    bool is_vacuum() const { return is_black(sigma_t()); }
};

// The distance a ray goes into a homogeneous medium before its next collision, sampled up to
// t_max (the next surface; infinite if none).
//
// The density of collisions differs per channel (sigma_t is a colour), so no one distance
// sampling fits all three. A channel c is chosen with probability P_c (in proportion to
// `channel_weights`, e.g. the path's throughput; uniform if they are all 0) and t is drawn from
// its exponential density sigma_t,c exp(-sigma_t,c t); the density used to weight the sample is
// the mixture over the channels, pdf(t) = sum_c P_c sigma_t,c exp(-sigma_t,c t) (the one-sample
// model of multiple importance sampling over channels with the balance heuristic: "spectral
// MIS"), so no channel's estimate divides by a density that is small where its light is large.
// If t reaches t_max the ray passes, with probability sum_c P_c exp(-sigma_t,c t_max).
//
// Unbiased estimators from the sample, per channel, wherever the mixture density is positive
// (a channel chosen with probability P_c > 0 and sigma_t,c > 0 covers every distance; with
// P_c = 0 for a channel, the others' densities must still cover its light: any channel with
// sigma_t > 0 does) (`transmittance` is T(t) as a colour):
//   collided: transmittance sigma_s / pdf, times the in-scattered radiance at t;
//   passed:   transmittance / pdf, times the light from the surface at t_max (or beyond).
struct FreeFlight {
    float t = 0.0f;         // where the ray collided, or t_max if it passed
    bool collided = false;  // a collision before t_max
    Color transmittance{1.0f};
    float pdf = 1.0f;  // the mixture density of t (collided) or probability of passing
};
// u_channel and u_distance: uniform numbers in [0, 1).
FreeFlight sample_free_flight(const Medium& medium, float t_max, float u_channel, float u_distance,
                              const Color& channel_weights = Color(1.0f));
// The mixture density sample_free_flight gives a collision at t < t_max, or (passed) the
// probability that it passes t_max: what another strategy needs to weigh this one by MIS.
float free_flight_pdf(const Medium& medium, float t, bool collided,
                      const Color& channel_weights = Color(1.0f));

}  // namespace lessons
