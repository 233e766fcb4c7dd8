// Lesson 6, section 6: where photon mapping and instant radiosity look for light. The camera path
// follows mirrors and glass (their one direction each, as lesson 4 samples them), adding the
// emission it meets (lamps and the sky, seen directly or in mirrors and glass), to the first vertex
// x whose BSDF is not a delta. There pm and ppm gather photons (gather.cpp) and vpl connects its
// virtual lights (vpl.h); both take the direct light at x by lesson 3's light sample.
#pragma once

#include <optional>

#include "05_bidirectional/bidirectional.h"

namespace lessons {

struct FirstDiffuse {
    Color emitted{0.0f};      // the emission met on the way, x's own included, times the throughput
    std::optional<Vertex> x;  // the first non-delta vertex (a Surface vertex: its hit, BSDF and
                              // throughput beta); none if the path escaped or ended first
    int segments = 0;         // from the camera to x
};

// The walk of `ray` to its first non-delta vertex, within `paths`' length (longest_path) and with
// its Russian roulette (after roulette_after segments, lesson 4's rule).
FirstDiffuse first_diffuse_vertex(const Bidir& b, const Ray& ray, Rng& rng,
                                  const BidirOptions& paths);

// A camera-side Surface vertex for the hit `si` with BSDF `bsdf` and throughput beta, as lesson
// 5's joins read one.
Vertex camera_side_vertex(const SurfaceInteraction& si, const Bsdf& bsdf, const Color& beta);

}  // namespace lessons
