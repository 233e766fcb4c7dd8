// Lesson 7, section 2: the path a state of the chain stands for, by lesson 5's strategies
// (multiplexed MLT: Hachisuka, Kaplanyan and Dachsbacher, "Multiplexed Metropolis Light
// Transport", SIGGRAPH 2014).
//
// A state picks a path length and a strategy. The connection stream's first number picks the
// length, k segments (k + 1 vertices), with probability q_k = 1 / (k (k + 1)) (renormalised
// below the longest length allowed): every length has its chance, the long ones a small one,
// and the light of a length over q_k stays bounded however fast light fades with bounces
// (rho^k k^2). The chain's states still visit each length in proportion to its light, whatever
// q: q only shapes where large steps and the bootstrap look. Its second number picks one of
// lesson 5's k + 1 strategies (s, t), s + t = k + 1, uniformly; the camera stream places the film
// position and makes the camera subpath of t vertices, the light stream the light subpath of s
// vertices (the connection stream a light sample when s = 1), and lesson 5's connect joins them.
// The state's contribution is that strategy's, times its MIS weight (lesson 5's, over the
// strategies of paths of k segments), times (k + 1) / q_k, the inverse of the probability of having
// picked both: its expectation over the choices is lesson 5's estimate of the light on paths of
// every length. Nothing of lesson 5 is rewritten: a state is lesson 5's estimator with one strategy
// drawn instead of all summed.
#pragma once

#include <cstdint>

#include "05_bidirectional/subpaths.h"
#include "07_metropolis/primary_samples.h"

namespace lessons {

// The streams of a state's primary samples.
enum PathStream : int { kCameraStream = 0, kLightStream = 1, kConnectionStream = 2, kStreams = 3 };

struct PathContribution {
    Color value{0.0f};   // the light the state adds at `pixel` (0: none)
    uint32_t pixel = 0;  // row-major, in the whole image
};

// The path length, in segments (1 .. longest), that a uniform number u picks, and its
// probability q_k = 1 / (k (k + 1)) / (1 - 1 / (longest + 1)).
int path_length(float u, int longest, double* probability);

// The contribution of the path that the state's numbers make, of at most `longest` segments.
// Starts the state's path (x.start_path()) and draws its numbers from x's streams.
PathContribution multiplexed_path(const Bidir& b, PrimarySamples& x, int longest);

}  // namespace lessons
