// The lesson driver's last step: the images (or a part's EXR), the convergence CSV and the
// JSON report of a run (see run_outputs.h).
#include "driver/run_outputs.h"

#include <cstdio>
#include <stdexcept>

#include "farm/part.h"
#include "io/image.h"
#include "io/report.h"

namespace lessons {

namespace {

void write_convergence_csv(const std::string& path, const std::vector<Checkpoint>& checkpoints) {
    write_atomically(path, [&](const std::string& tmp) {
        std::FILE* f = std::fopen(tmp.c_str(), "w");
        if (!f) throw std::runtime_error(path + ": cannot write");
        std::fprintf(f, "seconds,spp,mse,rmse,relmse,mae\n");
        for (const Checkpoint& c : checkpoints)
            std::fprintf(f, "%.6f,%d,%.9g,%.9g,%.9g,%.9g\n", c.seconds, c.spp, c.error.mse,
                         c.error.rmse, c.error.relmse, c.error.mae);
        if (std::fclose(f) != 0) throw std::runtime_error(path + ": cannot write");
    });
}

// A part's header: where it belongs, and what it holds.
PartHeader part_header(const Lesson& lesson, const CommonOptions& o, const RunInputs& in,
                       const RunResult& run) {
    PartHeader h;
    h.lesson = lesson.name;
    h.scene = o.scene;
    h.scene_hash = in.scene_hash;
    h.options = o.image_options;
    h.seed = o.seed;
    h.image_width = in.scene.width;
    h.image_height = in.scene.height;
    const bool crop = o.part.x1 > 0;
    h.x0 = crop ? o.part.x0 : 0;
    h.y0 = crop ? o.part.y0 : 0;
    h.x1 = crop ? o.part.x1 : in.scene.width;
    h.y1 = crop ? o.part.y1 : in.scene.height;
    h.sample_begin = o.part.first_sample;
    h.sample_end = o.part.first_sample + run.spp_taken;
    h.planned_end = o.part.first_sample + o.spp;
    h.films.push_back("image");
    for (const std::string& name : in.model->layer_names) h.films.push_back(name);
    h.seconds = run.render.stats.seconds;
    h.rays = run.render.stats.rays;
    h.threads = resolve_thread_count(o.threads);
    h.exposure = o.exposure;
    h.notes = in.model->notes;
    h.bias = run_bias(o, in);
    h.build = this_build();
    h.cpu = this_cpu();
    return h;
}

}  // namespace

// The EXR and PNG of the image and of every layer, the variance and the convergence CSV; a part
// writes its part EXR and the PNG of what it holds.
void write_images(const Lesson& lesson, const CommonOptions& o, const RunInputs& in,
                  const RunResult& run) {
    const Model& model = *in.model;
    const RenderResult& r = run.render;
    if (o.is_part()) {
        write_part(o.out + ".exr", part_header(lesson, o, in, run), r.films);
        if (!o.variance.empty()) write_exr(r.variance, o.variance + ".exr");
        if (!o.convergence.empty()) write_convergence_csv(o.convergence, run.checkpoints);
        write_png(r.image, o.out + ".png", o.exposure);
        return;
    }
    write_exr(r.image, o.out + ".exr");
    if (!o.variance.empty()) write_exr(r.variance, o.variance + ".exr");
    if (!o.convergence.empty()) write_convergence_csv(o.convergence, run.checkpoints);
    write_png(r.image, o.out + ".png", o.exposure);
    for (size_t k = 0; k < r.layers.size(); ++k) {
        write_exr(r.layers[k], o.out + "_" + model.layer_names[k] + ".exr");
        write_png(r.layers[k], o.out + "_" + model.layer_names[k] + ".png", o.exposure);
    }
}

double mrays_per_second(const RenderStats& s) {
    return s.seconds > 0 ? s.rays / s.seconds * 1e-6 : 0.0;
}

namespace {

// Whether the run's expected image differs from the rendering equation's, whether it converges
// to it all the same, and why.
void add_bias(Report& report, const CommonOptions& o, const RunInputs& in) {
    const std::vector<std::string> bias = run_bias(o, in);
    report.set("biased", !bias.empty());
    report.set("consistent", run_consistent(o, in));
    report.set("bias", bias);
}

}  // namespace

void write_run_report(const Lesson& lesson, const CommonOptions& o, const RunInputs& in,
                      const RunResult& run, const std::optional<ErrorMetrics>& error,
                      const std::vector<std::string>& shares) {
    const RenderResult& r = run.render;
    Report report;
    report.set("chapter", lesson.name);
    report.set("scene", in.scene.source);
    // The hash of the scene file and every file it names: a shipped reference's provenance
    // records it, so a reference rendered from other scene files is not taken (references/).
    report.set("scene_files",
               in.scene_hash.empty() ? scene_files_hash(in.scene, o.limits) : in.scene_hash);
    report.set("width", in.scene.width);
    report.set("height", in.scene.height);
    report.set("spp", run.spp_taken);
    if (o.is_part()) {
        report.set("samples", std::to_string(o.part.first_sample) + ":" +
                                  std::to_string(o.part.first_sample + run.spp_taken));
        if (o.part.x1 > 0) report.set("pixels", o.pixels);
        report.set("part", true);
    }
    report.set("firefly_pixels", r.firefly_pixels);
    add_bias(report, o, in);
    if (o.clamp > 0.0f) {
        report.set("clamp", static_cast<double>(o.clamp));
        report.set("clamped_samples", r.clamped_samples);
    }
    if (!o.naive.empty()) report.set("naive", o.naive);
    if (o.albedo >= 0.0f) report.set("albedo", static_cast<double>(o.albedo));
    report.set("interrupted", r.interrupted);
    if (o.time_budget > 0.0) report.set("time_budget", o.time_budget);
    report.set("threads", resolve_thread_count(o.threads));
    report.set("seed", o.seed);
    report.set("seconds", r.stats.seconds);
    report.set("rays", r.stats.rays);
    report.set("mrays_per_second", mrays_per_second(r.stats));
    report.set("nan_pixels", r.nan_pixels);
    report.set("inf_pixels", r.inf_pixels);
    report.set("nan_samples", r.nan_samples);
    report.set("inf_samples", r.inf_samples);
    report.set("image", o.out + ".exr");
    if (error) {
        report.set("reference", o.reference);
        report.set("mse", error->mse);
        report.set("rmse", error->rmse);
        report.set("relmse", error->relmse);
        report.set("mae", error->mae);
        // 1 / (MSE x seconds): constant for an unbiased estimator (MSE ~ 1 / time).
        report.set("efficiency", error->mse > 0.0 && r.stats.seconds > 0.0
                                     ? 1.0 / (error->mse * r.stats.seconds)
                                     : 0.0);
    }
    report.set("notes", in.model->notes);
    if (!shares.empty()) report.set("layers", shares);
    // Every model rendered in passes reports it (pm and ppm: 0, they splat nothing).
    if (in.model->passes) report.set("splat_bytes", static_cast<uint64_t>(r.splat_bytes));
    in.model->report(report);
    report.write(o.report);
}

}  // namespace lessons
