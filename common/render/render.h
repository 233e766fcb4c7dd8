// The render loop: every pixel sample through a lesson's radiance function, on all cores.
//
// The image is cut into 16x16 tiles that worker threads take in turn. Each pixel sample k of
// pixel i draws its random numbers from Rng(seed, i, k), and the film's sums do not depend on
// the order samples are added in (film.h); so the image is bit for bit the same for any number
// of threads, for any split of the samples into passes, and for any split of the image into
// crops rendered apart (RenderSettings::image_width).
//
// Splatting models (lesson 5's light paths) also add light to pixels other than their own.
// They are rendered one pass per sample index k: each tile keeps its own list of splats, and
// after the pass the lists are added to the pass's image in tile order, then every pixel's
// value (its own sample plus what was splatted onto it) joins the film as its sample k. The
// order of every sum is fixed, so these images too are the same for any number of threads and
// any split into passes, and each film sample is a whole independent estimate of its pixel (so
// the film's variance stays right, for independent samples: --sampler independent). The memory for splats is one pass's worth, at most.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "geometry/math.h"
#include "render/film.h"
#include "sampling/rng.h"
#include "scene/camera.h"

namespace lessons {

class Progress;

// A lesson's illumination model: the radiance arriving at the camera along a primary ray.
// Random numbers, if the model needs any, come from `rng`.
using RadianceFn = std::function<Color(const Ray& ray, Rng& rng)>;
// A model that also splits its answer into layers (e.g. light by number of bounces): it returns
// the radiance and adds each layer's share into `layers` (zeroed before each call).
using LayeredRadianceFn = std::function<Color(const Ray& ray, Rng& rng, std::span<Color> layers)>;

// Light that a sample adds to some pixel of the image, as its share of film `film`.
struct Splat {
    uint32_t pixel;  // row-major index
    uint32_t film;   // 0: the image; 1 + k: layer k
    Color value;
};
// A model that splats: it returns the radiance of its own pixel sample (of pixel `pixel`, the
// row-major index), adds each layer's share into `layers` (zeroed before each call), and appends
// light for other pixels to `splats`.
using SplattingRadianceFn = std::function<Color(const Ray& ray, Rng& rng, uint32_t pixel,
                                                std::span<Color> layers,
                                                std::vector<Splat>& splats)>;

struct RenderSettings {
    int threads = 0;  // 0: one per hardware thread
    uint64_t seed = 0;
    bool jitter = true;    // uniformly jittered position in the pixel; false: the pixel center
    bool progress = true;  // progress on stderr
    // Set (e.g. by a signal handler) to stop: workers take no new tile, and the render returns
    // with the tiles in progress finished. Pixels of untouched tiles then lack this pass.
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
    // image_width == 0: the films are the whole image. Splatting models take no crop.
    int image_width = 0, image_height = 0;
    int crop_x = 0, crop_y = 0;
};

struct RenderStats {
    double seconds = 0.0;
    uint64_t rays = 0;        // rays traced (primary, shadow and secondary)
    bool stopped = false;     // settings.stop was set before every tile was done
    size_t splat_bytes = 0;   // splatting renders: the most memory one pass's splats held
    int complete_passes = 0;  // splatting renders: sample indices added to the film in full
};

// Adds samples [sample_begin, sample_end) of every pixel to the film.
RenderStats render(const Camera& camera, Film& film, const RenderSettings& settings,
                   const RadianceFn& radiance, int sample_begin, int sample_end);
// The same with layers: films[0] receives the radiance, films[1 + k] layer k.
RenderStats render_layers(const Camera& camera, std::span<Film> films,
                          const RenderSettings& settings, const LayeredRadianceFn& radiance,
                          int sample_begin, int sample_end);

// The same for a splatting model, one pass per sample index (see above). A pass interrupted by
// settings.stop is dropped whole: every pixel then has the samples of the passes before it.
// `before_pass(k)`, if given, is called before pass k's samples (render/model.h's begin_pass).
RenderStats render_splatting(const Camera& camera, std::span<Film> films,
                             const RenderSettings& settings, const SplattingRadianceFn& radiance,
                             int sample_begin, int sample_end,
                             const std::function<void(int)>& before_pass = {});

int resolve_thread_count(int requested);

}  // namespace lessons
