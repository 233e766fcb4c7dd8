// The plumbing every lesson shares: command line, scene loading, rendering, writing the image
// and the report. A lesson's main() describes the lesson and its illumination model; this runs it.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "metrics.h"
#include "render.h"
#include "scene.h"

namespace CLI {
class App;
}

namespace lessons {

// A lesson's illumination model, made for one scene.
struct Model {
    RadianceFn radiance;
    // Optional: the same model splitting its radiance into named layers, each written as an
    // image <out>_<name> with its share of the total printed (used when layer_names is set).
    LayeredRadianceFn layered;
    std::vector<std::string> layer_names;
    // Optional: a model that also adds light to other pixels than its sample's (lesson 5's light
    // paths). When set, it is used instead of radiance and layered (render_splatting).
    SplattingRadianceFn splatting;
    // One line per thing the model approximates or ignores in this scene, printed before the
    // render and stored in the report.
    std::vector<std::string> notes;
    // Why the model's answer differs from the rendering equation's in this scene, however many
    // samples it takes (its bias); empty when it converges to the true image. Printed, and in
    // the report as "biased" and "bias".
    std::vector<std::string> biased_because;
};

struct Lesson {
    std::string name;         // e.g. "01_ray_casting": the executable and the report's "chapter"
    std::string description;  // first line of --help
    int default_spp = 1;
    std::function<void(CLI::App&)> add_options;  // the lesson's own flags (may be empty)
    std::function<Model(const Scene&)>
        make_model;  // throws InputError if the scene cannot be shown
};

// The common options, as parsed from the command line.
struct CommonOptions {
    std::string scene = "scenes/cornell_box.toml";
    std::string out;  // output prefix; default out/<lesson>_<scene name>
    int spp = 0;      // 0: the lesson's default
    int width = 0, height = 0;
    int threads = 0;
    uint64_t seed = 0;
    std::string report;
    float exposure = 0.0f;
    bool quiet = false;
    // Speed against error (docs/speed-vs-error.md)
    std::string reference;           // EXR to measure the error against
    double time_budget = 0.0;        // > 0: render whole passes of 1 spp until this many seconds
    std::string convergence;         // CSV of error against time at 1, 2, 4, ... spp
    std::string variance;            // prefix of an EXR of the per-pixel variance of the mean
    std::vector<std::string> naive;  // naive methods to demonstrate (docs/robustness.md)
    float clamp = 0.0f;              // > 0: clamp sample luminance (biased)
    std::string sampler = "independent";  // or "kronecker" (RenderSettings::kronecker)
};

// Parses the command line, renders, writes <out>.exr, <out>.png and the report.
// Exit codes: 0 done; 1 a failure while writing output; 2 bad input (command line, scene file,
// mesh), reported on one line naming the file, line and field.
int run_lesson(int argc, char** argv, const Lesson& lesson);

// Render one scene with a model, as run_lesson does, without the command line (for tests).
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
    size_t splat_bytes = 0;  // splatting models: the most memory one pass's splats held
};
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
    int spp = 1;                       // samples per pixel, when there is no time budget
    double time_budget = 0.0;          // > 0: passes of one sample per pixel until this is spent
    const Image* reference = nullptr;  // for checkpoints
    std::function<void(const Checkpoint&)> on_checkpoint;  // called if reference is set
};
RenderResult render_progressive(const Scene& scene, const Model& model, const ProgressivePlan& plan,
                                const RenderSettings& settings, int* spp_taken);

}  // namespace lessons
