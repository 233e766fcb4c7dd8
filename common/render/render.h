// The render loop: every pixel sample through a lesson's model (render/model.h), on all cores.
//
// The image is cut into 16x16 tiles that worker threads take in turn. Each pixel sample k of
// pixel i draws its random numbers from Rng(seed, i, k), and the film's sums do not depend on
// the order samples are added in (film.h); so the image is bit for bit the same for any number
// of threads, for any split of the samples into calls, and for any split of the image into
// crops rendered apart (RenderSettings::image_width).
//
// One loop, two orders, as the model says of itself:
// - pixel by pixel (a model without `passes`): each tile's pixels take all their samples in turn.
// - pass by pass (`passes`): one pass per sample index k, Model::begin_pass(k) before it. Each
//   tile keeps its own list of splats, and after the pass the lists are added to the pass's
//   image in tile order, then every pixel's value (its own sample plus what was splatted onto
//   it) joins the film as its sample k. The order of every sum is fixed, so these images too are
//   the same for any number of threads and any split into calls, and each film sample is a
//   whole independent estimate of its pixel (so the film's variance stays right, for
//   independent samples: --sampler independent). The memory for splats is one pass's worth, at
//   most. A pass interrupted by settings.stop is dropped whole: every pixel then has the
//   samples of the passes before it.
//
// How the lessons to come fit it: a Metropolis chain owns the order of its samples, so its model
// renders in passes, pass k being a fixed group of chains that begin_pass runs whole (on
// settings.threads threads, each chain from its own seed, their splats summed in chain order
// into an image of the pass that sample() then reads at `pixel`); media change what sample()
// traces, not the loop (docs/architecture.md).
#pragma once

#include <cstdint>
#include <span>

#include "render/film.h"
#include "render/model.h"
#include "render/settings.h"
#include "scene/camera.h"

namespace lessons {

struct RenderStats {
    double seconds = 0.0;
    uint64_t rays = 0;        // rays traced (primary, shadow and secondary; begin_pass's too)
    bool stopped = false;     // settings.stop was set before every tile was done
    size_t splat_bytes = 0;   // pass by pass: the most memory one pass's splats held
    int complete_passes = 0;  // pass by pass: sample indices added to the film in full
};

// Adds samples [sample_begin, sample_end) of every pixel to the films: films[0] receives the
// radiance, films[1 + k] the model's layer k. In the model's order (above); throws
// std::logic_error for films that are not one per image and layer, for a model that splats
// without passes or into a crop, and for a splat outside the image or its layers.
RenderStats render(const Camera& camera, std::span<Film> films, const RenderSettings& settings,
                   const Model& model, int sample_begin, int sample_end);

}  // namespace lessons
