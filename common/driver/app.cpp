// The shared lesson driver. A run is a few named steps, in this order: read the command line
// (options.cpp), load the scene (with any --naive methods), read the reference and make the
// lesson's model (run_inputs.cpp), render, measure, and write the images and the report
// (run_outputs.cpp); this file runs them, and stops a render cleanly on Ctrl-C.
#include "driver/app.h"

#include <signal.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>

#include "driver/run_outputs.h"
#include "io/input_error.h"

namespace lessons {

namespace {

// Ctrl-C (SIGINT) or SIGTERM: the first asks the render to stop after the tiles in progress, so
// the image so far is written; the second exits at once. Only async-signal-safe calls here.
std::atomic<bool> g_stop_requested{false};

extern "C" void on_stop_signal(int signal_number) {
    if (g_stop_requested.exchange(true)) std::_Exit(128 + signal_number);
    const char message[] =
        "\ninterrupted: finishing the tiles in progress, then writing the image so far (press "
        "Ctrl-C again to quit at once)\n";
    [[maybe_unused]] const ssize_t n = write(STDERR_FILENO, message, sizeof message - 1);
}

void install_stop_handlers() {
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

// Parses argv into `o` and the lesson's own flags; an exit status if the run stops here (--help,
// or a bad flag: 2).
std::optional<int> read_command_line(int argc, char** argv, const Lesson& lesson, CLI::App& app,
                                     CommonOptions& o) {
    try {
        parse_lesson_arguments(std::vector<std::string>(argv, argv + argc), lesson, app, o);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const InputError& e) {
        std::cerr << lesson.name << ": error: " << e.what() << " (see --help)\n";
        return 2;
    }
    return std::nullopt;
}

// Creates the folder of the output prefix.
void make_output_folder(const CommonOptions& o) {
    const std::filesystem::path dir = std::filesystem::path(o.out).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir);
}

void print_run_header(const Lesson& lesson, const CommonOptions& o, const RunInputs& in) {
    std::cerr << lesson.name << ": " << in.scene.source << ", " << in.scene.width << "x"
              << in.scene.height << ", "
              << (o.time_budget > 0.0 ? std::to_string(o.time_budget) + " s budget"
                                      : std::to_string(o.spp) + " spp")
              << ", " << resolve_thread_count(o.threads) << " threads\n";
    for (const std::string& note : in.model->notes) std::cerr << "  note: " << note << "\n";
    for (const std::string& why : in.model->biased_because)
        std::cerr << "  biased: " << why << "\n";
    for (const std::string& why : in.model->consistent_bias)
        std::cerr << "  biased but consistent: " << why << "\n";
}

RunResult render_run(const CommonOptions& o, const RunInputs& in) {
    RenderSettings settings = render_settings(o);
    settings.progress = !o.quiet;
    settings.stop = &g_stop_requested;
    install_stop_handlers();
    RunResult run;
    ProgressivePlan plan;
    plan.part = o.part;
    plan.keep_films = o.is_part();
    plan.spp = o.spp;
    plan.time_budget = o.time_budget;
    if (!o.reference.empty()) {
        plan.reference = &in.reference;
        plan.on_checkpoint = [&](const Checkpoint& c) {
            run.checkpoints.push_back(c);
            if (!o.quiet)
                std::fprintf(stderr, "  %6d spp %8.2f s   mse %.4g  relmse %.4g\n", c.spp,
                             c.seconds, c.error.mse, c.error.relmse);
        };
    }
    run.spp_taken = o.spp;
    run.render = render_progressive(in.scene, *in.model, plan, settings, &run.spp_taken);
    return run;
}

// Each layer's share of the image's total luminance, as a printable line.
std::vector<std::string> layer_shares(const RenderResult& r, const Model& model) {
    return lessons::layer_shares(r.image, r.layers, model.layer_names);
}

}  // namespace

namespace {

// Step 2: the scene, the reference and the model, and the output folder; an exit status (2) if
// the input is bad, said on one line naming the file, line and field.
std::optional<int> prepare_or_refuse(const CommonOptions& o, const Lesson& lesson, RunInputs& in) {
    try {
        prepare_run(o, lesson, in);
        make_output_folder(o);
    } catch (const InputError& e) {
        std::cerr << lesson.name << ": error: " << e.what() << "\n";
        return 2;
    } catch (const std::filesystem::filesystem_error& e) {
        std::cerr << lesson.name << ": error: --out " << o.out << ": " << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        std::cerr << lesson.name << ": error: " << o.scene
                  << ": out of memory while loading the scene and its meshes (is a file far "
                     "larger than it should be? see --max-file-mb)\n";
        return 2;
    }
    return std::nullopt;
}

// Step 4: what the render says of itself (samples left out, the layers' shares) and its error
// against the reference, if one was given.
std::optional<ErrorMetrics> measure(const Lesson& lesson, const CommonOptions& o,
                                    const RunInputs& in, const RunResult& run,
                                    std::vector<std::string>& shares) {
    const RenderResult& r = run.render;
    if (r.nan_samples + r.inf_samples > 0)
        std::cerr << lesson.name << ": warning: " << r.nan_samples << " NaN and " << r.inf_samples
                  << " infinite samples were left out of the average (" << r.nan_pixels << " and "
                  << r.inf_pixels << " pixels)\n";
    shares = layer_shares(r, *in.model);
    if (!o.quiet)
        for (const std::string& line : shares) std::cerr << "  " << line << "\n";
    if (o.reference.empty()) return std::nullopt;
    const ErrorMetrics error = compare_images(r.image, in.reference);
    if (!o.quiet)
        std::fprintf(stderr, "%s: against %s: mse %.6g, rmse %.6g, relmse %.6g, mae %.6g\n",
                     lesson.name.c_str(), o.reference.c_str(), error.mse, error.rmse, error.relmse,
                     error.mae);
    return error;
}

// Step 5: the images and the report; the exit status (0, 130 if interrupted, 1 if a file could
// not be written).
int write_outputs(const Lesson& lesson, const CommonOptions& o, const RunInputs& in,
                  const RunResult& run, const std::optional<ErrorMetrics>& error,
                  const std::vector<std::string>& shares) {
    int status = 0;
    if (run.render.interrupted) {
        std::cerr << lesson.name << ": interrupted after " << run.spp_taken
                  << " complete samples per pixel; writing what was rendered\n";
        status = 130;  // 128 + SIGINT, as a shell reports an interrupted command
    }
    try {
        write_images(lesson, o, in, run);
    } catch (const std::exception& e) {
        std::cerr << lesson.name << ": error: " << e.what() << "\n";
        if (status == 0) status = 1;
    }
    if (!o.report.empty()) {
        try {
            write_run_report(lesson, o, in, run, error, shares);
        } catch (const std::exception& e) {
            std::cerr << lesson.name << ": error: " << e.what() << "\n";
            status = 1;
        }
    }
    return status;
}

}  // namespace

int run_lesson(int argc, char** argv, const Lesson& lesson) {
    CLI::App app(lesson.description, lesson.name);
    CommonOptions o;
    if (const std::optional<int> status = read_command_line(argc, argv, lesson, app, o))
        return *status;
    RunInputs in;
    if (const std::optional<int> status = prepare_or_refuse(o, lesson, in)) return *status;
    if (!o.quiet) print_run_header(lesson, o, in);

    RunResult run;
    try {
        run = render_run(o, in);
    } catch (const InputError& e) {  // a pass that cannot be made (lesson 6: over its cap)
        std::cerr << lesson.name << ": error: " << e.what() << "\n";
        return 2;
    }
    std::vector<std::string> shares;
    const std::optional<ErrorMetrics> error = measure(lesson, o, in, run, shares);
    const int status = write_outputs(lesson, o, in, run, error, shares);
    if (!o.quiet && status == 0)
        std::fprintf(stderr, "%s: wrote %s.exr and %s.png in %.2f s (%.2f Mrays/s)\n",
                     lesson.name.c_str(), o.out.c_str(), o.out.c_str(), run.render.stats.seconds,
                     mrays_per_second(run.render.stats));
    return status;
}

}  // namespace lessons
