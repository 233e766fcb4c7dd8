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

int part_width(const Scene& scene, const RenderPart& part) {
    return part.x1 > 0 ? part.x1 - part.x0 : scene.width;
}
int part_height(const Scene& scene, const RenderPart& part) {
    return part.x1 > 0 ? part.y1 - part.y0 : scene.height;
}

}  // namespace

ProgressiveFilms::ProgressiveFilms(const Scene& scene, const Model& model, float clamp,
                                   const RenderPart& part)
    : scene_(scene),
      model_(model),
      part_(part),
      films_(1 + model.layer_names.size(),
             Film(part_width(scene, part), part_height(scene, part))) {
    if (clamp > 0.0f) films_[0].set_clamp(clamp);
}

RenderStats ProgressiveFilms::render_into(std::vector<Film>& films, int end,
                                          const RenderSettings& settings) {
    RenderSettings s = settings;
    if (part_.x1 > 0) {
        s.image_width = scene_.width;
        s.image_height = scene_.height;
        s.crop_x = part_.x0;
        s.crop_y = part_.y0;
    }
    const int begin = part_.first_sample + done_, stop = part_.first_sample + end;
    return render(scene_.camera, films, s, model_, begin, stop);
}

bool ProgressiveFilms::render_to(int end, const RenderSettings& settings) {
    // A model rendered in passes adds whole passes only; others, with whole_batches, render the
    // batch into films of its own that join these only when it is complete.
    const bool apart = part_.whole_batches && !model_.passes;
    if (apart) {
        if (batch_.empty()) batch_ = films_;
        for (Film& f : batch_) f.clear();
    }
    const RenderStats s = render_into(apart ? batch_ : films_, end, settings);
    total_.seconds += s.seconds;
    total_.rays += s.rays;
    total_.splat_bytes = std::max(total_.splat_bytes, s.splat_bytes);
    if (s.stopped) {
        // A model rendered in passes keeps the passes it finished whole (render/render.h);
        // elsewhere the finished tiles of the batch count, but not as whole samples (unless
        // apart: then the batch is dropped).
        if (model_.passes) done_ += s.complete_passes;
        interrupted_ = true;
        return false;
    }
    if (apart)
        for (size_t k = 0; k < films_.size(); ++k) films_[k].add(batch_[k]);
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
    Progress progress(
        "render",
        static_cast<uint64_t>(passes.films()[0].width()) * passes.films()[0].height() * spp,
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
        if (!passes.render_to(clock ? passes.samples() + 1 : std::min(plan.spp, next_checkpoint),
                              quiet))
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
    ProgressiveFilms passes(scene, model, settings.clamp, plan.part);
    const bool checkpoints = plan.reference && plan.on_checkpoint;
    if (plan.time_budget > 0.0 || checkpoints)
        render_with_checkpoints(passes, plan, settings);
    else if (settings.stop)
        render_in_batches(passes, plan.spp, settings);
    else
        passes.render_to(plan.spp, settings);  // one call: pixel by pixel, all samples at once
    if (spp_taken) *spp_taken = passes.samples();
    RenderResult r = passes.result();
    if (plan.keep_films) r.films = passes.take_films();
    return r;
}

}  // namespace lessons
