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

namespace {

RenderResult result_of(std::vector<Film>& films, const RenderStats& stats) {
    RenderResult r;
    const Film& film = films[0];
    r.stats = stats;
    r.image = film.mean();
    r.variance = film.variance_of_mean();
    r.nan_pixels = film.nan_pixels();
    r.inf_pixels = film.inf_pixels();
    r.nan_samples = film.nan_samples();
    r.inf_samples = film.inf_samples();
    r.firefly_pixels = film.firefly_pixels();
    r.clamped_samples = film.clamped_samples();
    r.splat_bytes = stats.splat_bytes;
    for (size_t k = 1; k < films.size(); ++k) {
        r.layers.push_back(films[k].mean());
        r.layer_variances.push_back(films[k].variance_of_mean());
    }
    return r;
}

// The films of one render, and one call of the right render loop for samples [begin, end).
struct Passes {
    const Scene& scene;
    const Model& model;
    std::vector<Film> films;
    RenderStats total;
    int done = 0;  // samples per pixel in the films
    bool interrupted = false;

    Passes(const Scene& s, const Model& m, float clamp)
        : scene(s), model(m), films(1 + m.layer_names.size(), Film(s.width, s.height)) {
        if (clamp > 0.0f) films[0].set_clamp(clamp);
    }
    // Renders up to sample `end`; false if stopped (then `done` counts what the films hold).
    bool render_to(int end, const RenderSettings& settings) {
        RenderStats s;
        if (model.splatting)
            s = render_splatting(scene.camera, films, settings, model.splatting, done, end);
        else if (model.layer_names.empty())
            s = render(scene.camera, films[0], settings, model.radiance, done, end);
        else
            s = render_layers(scene.camera, films, settings, model.layered, done, end);
        total.seconds += s.seconds;
        total.rays += s.rays;
        total.splat_bytes = std::max(total.splat_bytes, s.splat_bytes);
        if (s.stopped) {
            // A splatting model keeps the passes it finished whole (render_splatting); elsewhere
            // the finished tiles of the batch count, but not as whole samples.
            if (model.splatting) done += s.complete_passes;
            interrupted = true;
            return false;
        }
        done = end;
        return true;
    }
};

// Interruptible: doubling batches of whole passes (1, 1, 2, 4, ... spp), so that a stop leaves
// every pixel with at least the samples of the batches done. One progress display for all.
void render_in_batches(Passes& passes, int spp, const RenderSettings& settings) {
    Progress progress("render",
                      static_cast<uint64_t>(passes.scene.width) * passes.scene.height * spp,
                      settings.progress);
    RenderSettings batch_settings = settings;
    batch_settings.shared_progress = &progress;
    for (int batch = 1; passes.done < spp;) {
        if (!passes.render_to(std::min(spp, passes.done + batch), batch_settings)) break;
        if (passes.done >= batch) batch *= 2;
    }
    progress.finish();
}

// Whole passes up to each checkpoint (1, 2, 4, ... spp), or one at a time against a clock;
// the checkpoints' own work happens between the timed render calls.
void render_with_checkpoints(Passes& passes, const ProgressivePlan& plan,
                             const RenderSettings& settings) {
    RenderSettings quiet = settings;
    quiet.progress = false;
    const bool checkpoints = plan.reference && plan.on_checkpoint;
    const bool clock = plan.time_budget > 0.0;
    for (int next_checkpoint = 1;;) {
        if (!passes.render_to(clock ? passes.done + 1 : std::min(plan.spp, next_checkpoint), quiet))
            break;
        const bool finished =
            clock ? passes.total.seconds >= plan.time_budget : passes.done >= plan.spp;
        if (checkpoints && (passes.done == next_checkpoint || finished))
            plan.on_checkpoint({passes.done, passes.total.seconds,
                                compare_images(passes.films[0].mean(), *plan.reference)});
        while (next_checkpoint <= passes.done) next_checkpoint *= 2;
        if (finished) break;
    }
}

}  // namespace

RenderResult render_progressive(const Scene& scene, const Model& model, const ProgressivePlan& plan,
                                const RenderSettings& settings, int* spp_taken) {
    Passes passes(scene, model, settings.clamp);
    const bool checkpoints = plan.reference && plan.on_checkpoint;
    if (plan.time_budget > 0.0 || checkpoints)
        render_with_checkpoints(passes, plan, settings);
    else if (settings.stop)
        render_in_batches(passes, plan.spp, settings);
    else
        passes.render_to(plan.spp, settings);  // one call: pixel by pixel, all samples at once
    if (spp_taken) *spp_taken = passes.done;
    RenderResult r = result_of(passes.films, passes.total);
    r.interrupted = passes.interrupted;
    return r;
}

}  // namespace lessons
