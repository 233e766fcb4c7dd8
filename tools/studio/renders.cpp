// The worker: one pass at a time, in turn for every render with work (the panes and the
// background reference), each pass published as a snapshot that requests read (studio.h).
#include <algorithm>

#include "render/metrics.h"
#include "studio_internal.h"

namespace lessons::studio {

void make_films(PaneState& state, float clamp, int target, int threads) {
    state.films =
        std::make_unique<ProgressiveFilms>(state.inputs.scene, *state.inputs.model, clamp);
    state.settings = render_settings(state.options);
    state.settings.threads = threads;
    state.settings.stop = &state.stop;
    state.target = target;
}

std::shared_ptr<PaneState> Studio::next_job(std::unique_ptr<ProgressiveFilms>& films) {
    auto has_work = [](const std::shared_ptr<PaneState>& p) {
        return p && !p->done && p->films && !p->stop;
    };
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait(lock, [&] { return quit_ || std::any_of(panes_.begin(), panes_.end(), has_work); });
    if (quit_) return nullptr;
    // In turn: the next pane after the last one served that has work.
    std::shared_ptr<PaneState> job;
    for (size_t k = 1; k <= panes_.size() && !job; ++k) {
        const size_t i = (turn_ + k) % panes_.size();
        if (has_work(panes_[i])) job = panes_[turn_ = i];
    }
    // The worker alone touches the films while it renders into them.
    films = std::move(job->films);
    job->busy = true;
    return job;
}

std::shared_ptr<Snapshot> Studio::snapshot_of(const PaneState& job,
                                              const ProgressiveFilms& films) const {
    auto snapshot = std::make_shared<Snapshot>();
    snapshot->spp = films.samples();
    snapshot->result = films.result();
    snapshot->wall_seconds = std::chrono::duration<double>(Clock::now() - job.started).count();
    std::shared_ptr<const Image> reference;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        reference = job.reference;
        if (job.snapshot) {
            snapshot->chart = job.snapshot->chart;
            snapshot->passes = job.snapshot->passes;
        }
    }
    snapshot->passes += 1;
    for (const Color& c : snapshot->result.image.pixels) snapshot->image_luminance += luminance(c);
    for (const Image& layer : snapshot->result.layers) {
        double sum = 0.0;
        for (const Color& c : layer.pixels) sum += luminance(c);
        snapshot->layer_luminance.push_back(sum);
    }
    if (reference)
        snapshot->chart.push_back({snapshot->spp, snapshot->result.stats.seconds,
                                   compare_images(snapshot->result.image, *reference)});
    return snapshot;
}

void Studio::worker_loop() {
    std::unique_ptr<ProgressiveFilms> films;
    while (std::shared_ptr<PaneState> job = next_job(films)) {
        std::shared_ptr<Snapshot> snapshot;
        std::string failure;
        try {
            snapshot = render_pass(*job, *films);
        } catch (const std::bad_alloc&) {
            failure = "out of memory while rendering (a smaller image, or fewer layers)";
        } catch (const std::exception& e) {
            failure = e.what();
        }
        const bool finished = snapshot && snapshot->spp >= job->target;
        if (finished && job->is_reference) cache_reference(*job, snapshot->result);
        {
            // What becomes of the films is decided once, here: back to the render if it goes
            // on, else freed (below, outside the lock).
            std::lock_guard<std::mutex> lock(mutex_);
            job->busy = false;
            if (!failure.empty()) {
                job->failure = failure;
                job->done = true;
            } else if (snapshot && !job->stop) {
                if (!finished) job->films = std::move(films);
                publish(*job, snapshot, finished);
            }
        }
        films.reset();
    }
}

std::shared_ptr<Snapshot> Studio::render_pass(PaneState& job, ProgressiveFilms& films) {
    const int end = std::min(job.target, films.samples() + job.batch);
    const auto t0 = Clock::now();
    // Stopped (replaced by a new render, or the studio quits): nothing to publish.
    if (!films.render_to(end, job.settings)) return nullptr;
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    // Passes of about a quarter of a second: the page sees frames often, a restart waits for
    // at most one pass.
    if (dt < 0.12 && job.batch < 1024)
        job.batch *= 2;
    else if (dt > 0.5 && job.batch > 1)
        job.batch /= 2;
    return snapshot_of(job, films);
}

void Studio::publish(PaneState& job, const std::shared_ptr<Snapshot>& snapshot, bool finished) {
    snapshot->version = next_version_++;
    job.snapshot = snapshot;
    job.done = finished;
    if (!finished || !job.is_reference) return;
    // Every pane of this scene, size and albedo measures against it from now on.
    auto image = std::make_shared<const Image>(snapshot->result.image);
    const double noise = mean_variance(snapshot->result.variance);
    for (size_t i = 0; i + 1 < panes_.size(); ++i) {
        PaneState* p = panes_[i].get();
        if (p && !p->reference && same_image(*p, job)) {
            p->reference = image;
            p->reference_noise = noise;
            p->reference_source = "rendered by the studio: " + job.reference_path + ".exr";
        }
    }
}

}  // namespace lessons::studio
