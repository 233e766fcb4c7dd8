// The steps of a lesson's run, for every front end that runs lessons (the command line's
// run_lesson in driver/app.h, the studio): the options a command line gives (options.cpp),
// and what a run renders with, made before any rendering (run_inputs.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "driver/lesson.h"
#include "io/input_file.h"
#include "render/progressive.h"
#include "scene/scene.h"

namespace lessons {

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
    // Stratified by default (--sampler): unbiased in every lesson, even in every dimension at
    // every sample count, and the lowest error measured (docs/performance.md, "The default").
    std::string sampler = "kronecker";  // or "sobol", "independent" (RenderSettings::Sampler)
    float albedo = -1.0f;  // >= 0: every diffuse reflectance becomes this grey (the furnace demo)
    InputLimits limits;    // the largest scene file and mesh files read (--max-scene-mb, ...)
    // A part of a render split across jobs (docs/farm.md): --samples A:B and --pixels
    // X0:X1,Y0:Y1 as given, and parsed (the crop is checked against the image by prepare_run).
    std::string samples, pixels;
    RenderPart part;
    bool is_part() const { return !samples.empty() || !pixels.empty(); }
    // The options that change the image (not the scene, seed and size, kept apart), one
    // "--flag=value" per line: parts with different ones do not merge.
    std::string image_options;
};

// Parses a command line (args[0] is the program's name) into `o` and the lesson's own flags.
// Throws InputError("command line", 0, "", CLI11's message) for a bad flag, and CLI::CallForHelp
// for --help.
void parse_lesson_arguments(const std::vector<std::string>& args, const Lesson& lesson,
                            CLI::App& app, CommonOptions& o);

// Everything a run renders with, made before any rendering: bad input stops it here. The model
// refers to the scene, so both stay where they are made: filled in place, never copied or moved.
struct RunInputs {
    RunInputs() = default;
    RunInputs(const RunInputs&) = delete;
    RunInputs& operator=(const RunInputs&) = delete;

    Scene scene;
    std::unique_ptr<Model> model;
    Image reference;         // empty without --reference
    std::string scene_hash;  // a part's: scene_files_hash of the scene and the files it names
};
// Loads the scene (applying --naive and --albedo), reads the reference and makes the model;
// throws InputError for bad input.
void prepare_run(const CommonOptions& o, const Lesson& lesson, RunInputs& in);
// Why this run's image differs from the rendering equation's however long it renders: the
// model's reasons, --clamp and --naive (the report's "bias").
// The model's reasons, --clamp and --naive, then what the model converges to only in the limit
// (Model::consistent_bias).
std::vector<std::string> run_bias(const CommonOptions& o, const RunInputs& in);
// Whether the run converges to the rendering equation's image however biased its finite
// renders are (the report's "consistent"): no reason of the model's, no --clamp, no --naive.
bool run_consistent(const CommonOptions& o, const RunInputs& in);
// The render loop's settings for these options (no stop flag, no progress display).
RenderSettings render_settings(const CommonOptions& o);

// The options of a parsed command line that change the image, as CommonOptions::image_options.
std::string image_options(const CLI::App& app);

}  // namespace lessons
