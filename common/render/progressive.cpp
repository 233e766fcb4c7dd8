// Progressive rendering (see progressive.h).
#include "render/progressive.h"

#include <algorithm>

#include "render/progress.h"

namespace lessons {

RenderResult render_scene(const Scene& scene, const Model& model, int spp,
                          const RenderSettings& settings) {
    ProgressivePlan plan;
    plan.spp = spp;
    return render_progressive(scene, model, plan, settings, nullptr);
}

ProgressiveFilms::ProgressiveFilms(const Scene& scene, const Model& model, float clamp)
    : scene_(scene), model_(model), films_(1 + model.layer_names.size(), Film(scene.width, scene.height)) {
    if (clamp > 0.0f) films_[0].set_clamp(clamp);
}

bool ProgressiveFilms::render_to(int end, const RenderSettings& settings) {
    RenderStats s;
    if (model_.splatting)
        s = render_splatting(scene_.camera, films_, settings, model_.splatting, done_, end);
    else if (model_.layer_names.empty())
        s = render(scene_.camera, films_[0], settings, model_.radiance, done_, end);
    else
        s = render_layers(scene_.camera, films_, settings, model_.layered, done_, end);
    total_.seconds += s.seconds;
    total_.rays += s.rays;
    total_.splat_bytes = std::max(total_.splat_bytes, s.splat_bytes);
    if (s.stopped) {
        // A splatting model keeps the passes it finished whole (render_splatting); elsewhere
        // the finished tiles of the batch count, but not as whole samples.
        if (model_.splatting) done_ += s.complete_passes;
        interrupted_ = true;
        return false;
    }
    done_ = end;
    return true;
}

RenderResult ProgressiveFilms::result() const {
    RenderResult r;
    const Film& film = films_[0];
    r.stats = total_;
    r.image = film.mean();
    r.variance = film.variance_of_mean();
    r.nan_pixels = film.nan_pixels();
    r.inf_pixels = film.inf_pixels();
    r.nan_samples = film.nan_samples();
    r.inf_samples = film.inf_samples();
    r.firefly_pixels = film.firefly_pixels();
    r.clamped_samples = film.clamped_samples();
    r.splat_bytes = total_.splat_bytes;
    r.interrupted = interrupted_;
    for (size_t k = 1; k < films_.size(); ++k) {
        r.layers.push_back(films_[k].mean());
        r.layer_variances.push_back(films_[k].variance_of_mean());
    }
    return r;
}

namespace {

// Interruptible: doubling batches of whole passes (1, 1, 2, 4, ... spp), so that a stop leaves
// every pixel with at least the samples of the batches done. One progress display for all.
void render_in_batches(ProgressiveFilms& passes, int spp, const RenderSettings& settings) {
    Progress progress("render",
                      static_cast<uint64_t>(passes.scene().width) * passes.scene().height * spp,
                      settings.progress);
    RenderSettings batch_settings = settings;
    batch_settings.shared_progress = &progress;
    for (int batch = 1; passes.samples() < spp;) {
        if (!passes.render_to(std::min(spp, passes.samples() + batch), batch_settings)) break;
        if (passes.samples() >= batch) batch *= 2;
    }
    progress.finish();
}

// Whole passes up to each checkpoint (1, 2, 4, ... spp), or one at a time against a clock;
// the checkpoints' own work happens between the timed render calls.
void render_with_checkpoints(ProgressiveFilms& passes, const ProgressivePlan& plan,
                             const RenderSettings& settings) {
    RenderSettings quiet = settings;
    quiet.progress = false;
    const bool checkpoints = plan.reference && plan.on_checkpoint;
    const bool clock = plan.time_budget > 0.0;
    for (int next_checkpoint = 1;;) {
        if (!passes.render_to(clock ? passes.samples() + 1 : std::min(plan.spp, next_checkpoint), quiet))
            break;
        const bool finished =
            clock ? passes.stats().seconds >= plan.time_budget : passes.samples() >= plan.spp;
        if (checkpoints && (passes.samples() == next_checkpoint || finished))
            plan.on_checkpoint({passes.samples(), passes.stats().seconds,
                                compare_images(passes.films()[0].mean(), *plan.reference)});
        while (next_checkpoint <= passes.samples()) next_checkpoint *= 2;
        if (finished) break;
    }
}

}  // namespace

RenderResult render_progressive(const Scene& scene, const Model& model, const ProgressivePlan& plan,
                                const RenderSettings& settings, int* spp_taken) {
    ProgressiveFilms passes(scene, model, settings.clamp);
    const bool checkpoints = plan.reference && plan.on_checkpoint;
    if (plan.time_budget > 0.0 || checkpoints)
        render_with_checkpoints(passes, plan, settings);
    else if (settings.stop)
        render_in_batches(passes, plan.spp, settings);
    else
        passes.render_to(plan.spp, settings);  // one call: pixel by pixel, all samples at once
    if (spp_taken) *spp_taken = passes.samples();
    return passes.result();
}

}  // namespace lessons
