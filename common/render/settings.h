// How a render runs: threads, seed, sampler, jitter, progress, the stop flag, the clamp and the
// crop. The render loop (render/render.h) reads them, and so does a model that prepares each of
// its passes (Model::begin_pass: on how many threads, from which seed).
#pragma once

#include <atomic>
#include <cstdint>

namespace lessons {

class Progress;

struct RenderSettings {
    int threads = 0;  // 0: one per hardware thread
    uint64_t seed = 0;
    bool jitter = true;    // uniformly jittered position in the pixel; false: the pixel center
    bool progress = true;  // progress on stderr
    // Set (e.g. by a signal handler) to stop: workers take no new tile, and the render returns
    // with the tiles in progress finished. Pixel by pixel, pixels of untouched tiles then lack
    // these samples; pass by pass, the interrupted pass is dropped whole (render/render.h).
    const std::atomic<bool>* stop = nullptr;
    float clamp = 0.0f;  // > 0: clamp every sample's luminance to this (biased; Film::set_clamp)
    // Where each sample's random numbers come from: independent (PCG32), or a stratified sequence
    // per pixel (Rng::kronecker, Rng::sobol).
    enum class Sampler { Independent, Kronecker, Sobol } sampler = Sampler::Independent;
    // Progress shared by several render calls (passes of one render); else each call has its own.
    Progress* shared_progress = nullptr;
    // A crop (--pixels): the films hold pixels [crop_x, crop_x + film width) x [crop_y, ...) of
    // an image_width x image_height image. Each pixel is rendered as in the whole image (its
    // camera ray and its random numbers are those of its place in the whole image).
    // image_width == 0: the films are the whole image. A model that splats takes no crop.
    int image_width = 0, image_height = 0;
    int crop_x = 0, crop_y = 0;
};

// The number of worker threads `requested` means (0: one per hardware thread).
int resolve_thread_count(int requested);

}  // namespace lessons
