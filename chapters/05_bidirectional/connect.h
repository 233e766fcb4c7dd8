// Lesson 5, section 2: joining the subpaths. Strategy (s, t) uses the first s vertices of the
// light subpath and the first t of the camera subpath; its contribution is
//   beta_L(y_{s-1}) f(y_{s-1}) G(y_{s-1}, z_{t-1}) V f(z_{t-1}) beta_C(z_{t-1})
// with G = |cos| |cos| / d^2 and V the visibility of the joining segment. Four kinds:
//   s = 0       the camera path itself reached a light (lesson 4's emission term);
//   s = 1       a light sample at z_{t-1} (lesson 3's and 4's next-event estimation);
//   t = 1       a light vertex joined to the camera and splatted onto the film wherever it
//               lands: light tracing. The camera's importance W (camera.h) plays the part of
//               the BSDF and the cosine at the camera end;
//   otherwise   a shadow ray between a light-subpath and a camera-subpath vertex.
#pragma once

#include <optional>
#include <span>

#include "05_bidirectional/subpaths.h"

namespace lessons {

class ExtraTechnique;  // mis.h

struct StrategySample {
    Color L{0.0f};                  // the unweighted contribution (0: none)
    float weight = 0.0f;            // its MIS weight (mis.h), if asked for
    std::optional<uint32_t> pixel;  // t = 1: the pixel it lands on (row-major)
};

// The general join (s >= 2, t >= 2), unweighted: a shadow ray between light-subpath vertex y and
// camera-subpath vertex z, beta_L(y) f(y) G V f(z) beta_C(z); 0 where either is a mirror or glass,
// not on a surface, or the segment is blocked.
Color join(const Bidir& b, const Vertex& y, const Vertex& z);

// Strategy (s, t) for the two subpaths (light has at least s vertices, camera at least t).
// Draws random numbers only for s = 1 (the light sample). `extra`: another technique counted
// among those of the weight (mis.h), or none.
StrategySample connect(const Bidir& b, std::span<const Vertex> light, int s,
                       std::span<const Vertex> camera, int t, RandomNumbers& rng, bool weighted,
                       const ExtraTechnique* extra = nullptr);

}  // namespace lessons
