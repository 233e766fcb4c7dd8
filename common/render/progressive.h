// Rendering a model in whole passes over the image: all samples at once, in doubling batches
// that Ctrl-C can stop between, or pass by pass against a clock with error checkpoints (speed
// against error, docs/speed-vs-error.md). What a lesson's run renders, and what the tests call.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "io/image.h"
#include "render/metrics.h"
#include "render/model.h"
#include "render/render.h"
#include "scene/scene.h"

namespace lessons {

// What a render gives back: the image, its layers, their per-pixel variances and counts.
struct RenderResult {
    Image image;
    std::vector<Image> layers;
    Image variance;
    std::vector<Image> layer_variances;  // per layer, as `variance` is for the image
    RenderStats stats;
    int nan_pixels = 0, inf_pixels = 0;
    uint64_t nan_samples = 0, inf_samples = 0;
    bool interrupted = false;  // stopped by RenderSettings::stop before the planned samples
    int firefly_pixels = 0;
    uint64_t clamped_samples = 0;
    size_t splat_bytes = 0;   // models rendered in passes: the most memory one pass's splats held
    std::vector<Film> films;  // the films themselves, with ProgressivePlan::keep_films
};
// The piece of a render a run makes: a crop of the image and a range of sample indices (a part
// of a render split across jobs, docs/farm.md). The default is the whole image from sample 0.
struct RenderPart {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixels [x0, x1) x [y0, y1); x1 == 0: the whole image
    int first_sample = 0;                // sample indices first_sample, first_sample + 1, ...
    // A stop drops the samples of the batch it interrupts, so that every pixel holds the same
    // samples and the part's sample range is exact (parts must be; a plain run keeps them).
    bool whole_batches = false;
    bool crops(const Scene& scene) const {
        return x1 > 0 && (x0 > 0 || y0 > 0 || x1 < scene.width || y1 < scene.height);
    }
};

// The films of one render and the samples they hold: renders more samples into them, whole
// passes over the image or its crop (render/render.h, in the model's order). Samples first .. first
// + N-1 in any split into calls give the same films, bit for bit.
class ProgressiveFilms {
public:
    ProgressiveFilms(const Scene& scene, const Model& model, float clamp,
                     const RenderPart& part = {});
    // Renders the next samples of every pixel until the films hold `end` of them (indices
    // first_sample .. first_sample + end-1); false if settings.stop stopped it (then samples()
    // counts what the films hold whole).
    bool render_to(int end, const RenderSettings& settings);
    int samples() const { return done_; }
    const RenderPart& part() const { return part_; }
    const RenderStats& stats() const { return total_; }  // summed over the calls
    bool interrupted() const { return interrupted_; }
    const std::vector<Film>& films() const { return films_; }  // [0] the image, [1 + k] layer k
    const Scene& scene() const { return scene_; }
    // The image, its layers and variances so far.
    RenderResult result() const;
    // The films themselves, moved out (the object is done with then).
    std::vector<Film> take_films() { return std::move(films_); }

private:
    RenderStats render_into(std::vector<Film>& films, int end, const RenderSettings& settings);

    const Scene& scene_;
    const Model& model_;
    RenderPart part_;
    std::vector<Film> films_;
    std::vector<Film> batch_;  // whole_batches: the batch being rendered
    RenderStats total_;
    int done_ = 0;
    bool interrupted_ = false;
};

// Renders `spp` samples per pixel in one go (for tests; run_lesson renders progressively).
RenderResult render_scene(const Scene& scene, const Model& model, int spp,
                          const RenderSettings& settings);

// Progressive rendering: whole passes over the image, so that the error can be measured along
// the way and a time budget respected. A checkpoint is taken after 1, 2, 4, 8, ... samples per
// pixel and at the end; its time counts only the rendering, never the checkpoint's own work.
struct Checkpoint {
    int spp;
    double seconds;  // rendering time so far
    ErrorMetrics error;
};
struct ProgressivePlan {
    RenderPart part;                   // the crop and first sample (default: all of the image)
    int spp = 1;                       // samples per pixel, when there is no time budget
    double time_budget = 0.0;          // > 0: passes of one sample per pixel until this is spent
    const Image* reference = nullptr;  // for checkpoints
    std::function<void(const Checkpoint&)> on_checkpoint;  // called if reference is set
    bool keep_films = false;  // RenderResult::films (a part saves them)
};
RenderResult render_progressive(const Scene& scene, const Model& model, const ProgressivePlan& plan,
                                const RenderSettings& settings, int* spp_taken);

}  // namespace lessons
