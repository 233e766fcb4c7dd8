// Lesson 4: the rendering equation, by Monte Carlo path tracing.
//
//   L_o(p, wo) = L_e(p, wo) + integral over the hemisphere of L_i(p, wi) f(p, wo, wi) cos(theta_i)
//   dwi
//
// with L_i(p, wi) = L_o(p', -wi), the outgoing radiance of the surface p' that the ray from p
// meets first. In operator form L = E + K L, whose solution is the series
//   L = E + K E + K^2 E + K^3 E + ...
// (emission, direct light, light after one indirect bounce, ...). A path tracer estimates the
// whole series with one random path per sample: at each vertex it adds the emission it sees,
// weighted by the path's throughput beta (the product of f cos / p so far), samples a new
// direction from the BSDF, and continues.
//
// Next-event estimation (NEE) adds, at each vertex, a light sample towards a light; emitters
// then found by BSDF-sampled rays are weighted by multiple importance sampling, so no light is
// counted twice. Russian roulette ends paths at random once their throughput is small, dividing
// the survivors by their survival probability, which keeps the estimate unbiased.
#pragma once

#include <optional>

#include "app.h"
#include "bsdf.h"
#include "lights.h"
#include "scene.h"

namespace lessons {

// Paths longer than this are cut even without a depth limit: a path trapped by total internal
// reflection keeps throughput 1, so Russian roulette alone would never end it.
inline constexpr int kLongestPath = 1000;

struct PathOptions {
    bool next_event = true;    // false: the plain estimator, BSDF sampling only
    int max_depth = 0;         // 0: unlimited; else at most this many path segments (depth 1:
                               // emitters seen directly; depth 2 adds direct light; ...)
    int roulette_after = 3;    // bounces before Russian roulette may end a path; < 0: never
    int bounce_layers = 0;     // record bounces 0 .. N-1 as separate layers, plus the rest
    bool light_paths = false;  // also connect every vertex to a light path (with next_event)
};

// Light paths (--light-paths): besides the camera path, one light path per sample, one segment
// long: light leaves a point q of an emitter (sampled by LightSampler::sample_emission) and first
// lands on Y. Every non-delta camera vertex X is connected to Y by a shadow ray, which samples
// the paths ... X, Y, q a third way: next-event estimation at Y needs the camera path to find Y
// first, and cannot when Y is small or bright seen from X (the ceiling in the one-unit gap above
// the lamp of the Ray Tracing in One Weekend box, lit by the lamp's upper face). The three
// strategies for the last two segments are weighted by the power heuristic (Veach 1997, ch. 10:
// this is bidirectional path tracing with light subpaths of at most two vertices).
struct LightVertex {
    SurfaceInteraction y;  // Y; y.wo points back towards q
    Color beta;            // L_e cos(theta_q) / (p_A(q) p(q -> Y)): the light path's throughput
    PrimRef emitter;
    Vec3 q{0.0f}, n_q{0.0f};      // the point on the light, and its normal on the emitting side
    float pdf_next_event = 0.0f;  // next-event estimation's solid-angle density of q, from Y
};
std::optional<LightVertex> trace_light_path(const Scene& scene, const LightSampler& lights,
                                            Rng& rng);
// The light that the light path brings to camera vertex X through Y, towards x.wo, MIS-weighted:
// times the camera path's beta, it is light that has bounced twice more.
Color connect_light_vertex(const Scene& scene, const LightSampler& lights,
                           const SurfaceInteraction& x, const Bsdf& bsdf_x, const LightVertex& lv);

// The radiance along a camera ray: one path sample. If `bounces` is not empty, the
// contribution of light that has bounced k times is also added to bounces[k] (the last entry
// collects everything beyond).
Color path_trace(const Scene& scene, const LightSampler& lights, const Ray& ray, Rng& rng,
                 const PathOptions& options, std::span<Color> bounces = {});

Model make_path_tracing_model(const Scene& scene, const LightSampler& lights,
                              const PathOptions& options);

}  // namespace lessons
