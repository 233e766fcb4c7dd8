// The shared lesson driver. A run is a few named steps, in this order: read the command line,
// load the scene (with any --naive methods), read the reference, make the lesson's model, render,
// measure, and write the images and the report (see app.h).
#include "render/app.h"

#include <signal.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>

#include "io/image.h"
#include "io/input_error.h"
#include "io/report.h"
#include "io/scene_file.h"
#include "render/part.h"

namespace lessons {

namespace {

void add_common_options(CLI::App& app, CommonOptions& o) {
    app.add_option("--scene", o.scene, "Scene file (TOML), see docs/scene-format.md")
        ->capture_default_str();
    app.add_option("--out", o.out,
                   "Output prefix: writes PREFIX.exr (linear radiance) and PREFIX.png (sRGB); "
                   "default out/<lesson>_<scene>");
    app.add_option("--spp", o.spp, "Samples per pixel (default: the lesson's)")
        ->check(CLI::Range(1, 1 << 24));
    app.add_option("--samples", o.samples,
                   "A part of a render split across jobs (docs/farm.md): render sample indices "
                   "A .. B-1 of every pixel (--spp N is --samples 0:N) and write a part EXR, "
                   "which build/bin/merge joins with the others");
    app.add_option("--pixels", o.pixels,
                   "A part that is a crop X0:X1,Y0:Y1 of the image (pixels X0 .. X1-1 and "
                   "Y0 .. Y1-1, in the whole image's coordinates), written as a part EXR");
    app.add_option("--width", o.width, "Image width in pixels, overriding the scene")
        ->check(CLI::Range(1, kMaxImageSide));
    app.add_option("--height", o.height, "Image height in pixels, overriding the scene")
        ->check(CLI::Range(1, kMaxImageSide));
    app.add_option("--threads", o.threads, "Worker threads, for the BVH's build and the render (0: one per core)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    app.add_option("--seed", o.seed, "Seed of the random numbers (same seed: same image)")
        ->capture_default_str();
    app.add_option("--report", o.report, "Write a JSON report of the render to this file");
    app.add_option("--exposure", o.exposure,
                   "PNG exposure in stops: pixel values are scaled by 2^stops, then clamped "
                   "to [0, 1] and sRGB-encoded (the EXR is never scaled)")
        ->check(CLI::Range(-30.0, 30.0))
        ->capture_default_str();
    app.add_flag("--quiet", o.quiet, "No progress output");
    app.add_option("--reference", o.reference,
                   "An EXR of the same size to measure the error against: mse, rmse, relmse, mae "
                   "(printed and reported), and efficiency 1 / (mse x seconds)");
    app.add_option("--time", o.time_budget,
                   "Render whole passes of one sample per pixel until this many seconds of "
                   "rendering are spent (instead of --spp); the report gives the samples taken")
        ->check(CLI::Range(1e-3, 1e6));
    app.add_option("--convergence", o.convergence,
                   "With --reference: write a CSV of seconds, spp and each error metric after 1, "
                   "2, 4, 8, ... samples per pixel (the measuring is not counted as time)");
    app.add_option("--variance", o.variance,
                   "Write the per-pixel sample variance of the mean as PREFIX.exr (it measures the "
                   "error of the mean only for independent samples: --sampler independent)");
    app.add_option("--naive", o.naive,
                   "Use the naive methods the suite replaces, to see them fail: epsilon=E (a "
                   "fixed ray offset), quadratic (textbook sphere test in float), "
                   "moller-trumbore (triangles, not watertight), side-by-dot (the side a ray "
                   "hits from dot(d, n)), shading-normals (no fallback below an interpolated "
                   "normal), light-cosine (|cos| at one-sided lights), adjoint (lesson 5's "
                   "light paths without the adjoint shading-normal correction); comma-separated")
        ->delimiter(',');
    app.add_option(
           "--sampler", o.sampler,
           "Where each sample's random numbers come from: kronecker (the default: a "
           "randomised Kronecker sequence per pixel, the positions in the pixel from a "
           "scrambled Sobol sequence), sobol (Owen-scrambled Sobol points, each pair of "
           "dimensions shuffled apart), both stratified and unbiased, or independent (PCG32: "
           "the error falls as 1/N, the rate the lessons page shows)")
        ->check(CLI::IsMember({"independent", "kronecker", "sobol"}));
    app.add_option("--albedo", o.albedo,
                   "Make every diffuse reflectance (diffuse and glossy materials) this grey, in "
                   "[0, 1]: the furnace demo's ratio of the series L = E + KE + K^2E + ...")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--max-scene-mb", o.limits.scene_mb,
                   "Largest scene file read, in MiB (a scene is text; meshes are other files)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--max-file-mb", o.limits.file_mb,
                   "Largest file a scene may name (OBJ mesh, texture, environment map), in MiB")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--clamp", o.clamp,
                   "Clamp each sample's luminance to this value (removes fireflies; biased, and "
                   "the report says so)")
        ->check(CLI::PositiveNumber);
}

// Refuses an image whose buffers would not fit in memory, before any work is done.
void check_memory(int width, int height) {
    // The film (FilmPixel, 96 bytes), the mean and variance images and their copies in the
    // result, the PNG bytes: 160 bytes per pixel is a safe upper bound.
    const double bytes_per_pixel = 160.0;
    check_fits_in_memory(bytes_per_pixel * width * height,
                         std::to_string(width) + "x" + std::to_string(height) +
                             " needs, for the image buffers,",
                         "command line", "--width/--height");
}

// "A:B" with 0 <= A < B <= limit, or throws naming `flag`.
void parse_range(const std::string& text, const std::string& flag, long long limit,
                 int& begin, int& end, const std::string& what) {
    long long a = 0, b = 0;
    if (!parse_pair(text, ':', a, b) || b <= a || b > limit)
        throw InputError("command line", 0, flag,
                         "'" + text + "' is not " + what + " A:B with 0 <= A < B <= " +
                             std::to_string(limit));
    begin = static_cast<int>(a);
    end = static_cast<int>(b);
}

// --samples and --pixels into o.part (and --samples A:B into o.spp = B - A).
void parse_part_options(const CLI::App& app, CommonOptions& o) {
    for (const char* flag : {"--samples", "--pixels"})
        if (app.count(flag) > 0 && (flag[2] == 's' ? o.samples : o.pixels).empty())
            throw InputError("command line", 0, flag, "is empty");
    if (!o.is_part()) return;
    if (app.count("--spp") > 0 && !o.samples.empty())
        throw InputError("command line", 0, "--samples",
                         "give --spp or --samples, not both (--spp N is --samples 0:N)");
    if (o.time_budget > 0.0)
        throw InputError("command line", 0, "--time",
                         "a part renders a given range of samples (--samples A:B), not for a time");
    if (!o.samples.empty()) {
        int a = 0, b = 0;
        parse_range(o.samples, "--samples", 1 << 24, a, b, "a range of sample indices");
        o.part.first_sample = a;
        o.spp = b - a;
    }
    if (!o.pixels.empty()) {
        const size_t comma = o.pixels.find(',');
        if (comma == std::string::npos)
            throw InputError("command line", 0, "--pixels",
                             "'" + o.pixels + "' is not a crop X0:X1,Y0:Y1");
        parse_range(o.pixels.substr(0, comma), "--pixels", kMaxImageSide, o.part.x0, o.part.x1,
                    "a crop X0:X1,Y0:Y1 whose columns are");
        parse_range(o.pixels.substr(comma + 1), "--pixels", kMaxImageSide, o.part.y0, o.part.y1,
                    "a crop X0:X1,Y0:Y1 whose rows are");
    }
    o.part.whole_batches = true;
}

std::string default_out(const Lesson& lesson, const std::string& scene_path) {
    return "out/" + lesson.name + "_" + std::filesystem::path(scene_path).stem().string();
}

}  // namespace

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

}  // namespace

namespace {

// ---- 1. The command line ----

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

// ---- 2. The scene, the reference and the model ----

// Turns on the --naive methods by name (docs/robustness.md); throws InputError for an unknown one.
void apply_naive_methods(const std::vector<std::string>& methods, NaiveMethods& naive) {
    for (const std::string& method : methods) {
        if (method == "quadratic") {
            naive.textbook_quadratic = true;
        } else if (method == "moller-trumbore") {
            naive.moller_trumbore = true;
        } else if (method == "side-by-dot") {
            naive.side_by_dot = true;
        } else if (method == "shading-normals") {
            naive.raw_shading_normals = true;
        } else if (method == "light-cosine") {
            naive.light_abs_cosine = true;
        } else if (method == "adjoint") {
            naive.no_adjoint_correction = true;
        } else if (method.rfind("epsilon=", 0) == 0) {
            char* end = nullptr;
            const float e = std::strtof(method.c_str() + 8, &end);
            if (*end != '\0' || !(e > 0.0f) || !std::isfinite(e))
                throw InputError("command line", 0, "--naive",
                                 "epsilon must be a positive number, got '" + method + "'");
            naive.fixed_epsilon = e;
        } else {
            throw InputError("command line", 0, "--naive",
                             "unknown method '" + method +
                                 "' (known: epsilon=E, quadratic, moller-trumbore, side-by-dot, "
                                 "shading-normals, light-cosine, adjoint)");
        }
    }
}

// The --reference image, which must have the render's size; empty without --reference.
Image read_reference(const CommonOptions& o, const Scene& scene) {
    if (!o.convergence.empty() && o.reference.empty())
        throw InputError("command line", 0, "--convergence",
                         "needs --reference: the error is measured against it");
    if (o.reference.empty()) return {};
    Image reference;
    try {
        reference = read_exr(o.reference);
    } catch (const std::runtime_error& e) {
        throw InputError("command line", 0, "--reference", e.what());
    }
    if (reference.width != scene.width || reference.height != scene.height)
        throw InputError(o.reference, 0, "--reference",
                         "is " + std::to_string(reference.width) + "x" +
                             std::to_string(reference.height) + ", the render is " +
                             std::to_string(scene.width) + "x" + std::to_string(scene.height) +
                             " (use --width/--height)");
    if (o.part.x1 == 0) return reference;
    // A crop is measured against the same crop of the reference.
    Image crop(o.part.x1 - o.part.x0, o.part.y1 - o.part.y0);
    for (int y = 0; y < crop.height; ++y)
        for (int x = 0; x < crop.width; ++x) crop.at(x, y) = reference.at(o.part.x0 + x, o.part.y0 + y);
    return crop;
}

// --pixels must lie in the image (its size is known once the scene is read).
void check_part(const CommonOptions& o, const Scene& scene) {
    if (o.part.x1 == 0) return;
    if (o.part.x1 > scene.width || o.part.y1 > scene.height)
        throw InputError("command line", 0, "--pixels",
                         "'" + o.pixels + "' reaches outside the " + std::to_string(scene.width) +
                             "x" + std::to_string(scene.height) + " image");
}

// --albedo: every diffuse reflectance (of diffuse and glossy materials) becomes grey `rho`.
void apply_albedo(float rho, Scene& scene) {
    if (rho < 0.0f) return;
    for (uint32_t i = 0; i < scene.materials().size(); ++i) {
        Material m = scene.material(i);
        if (m.type != MaterialType::Diffuse && m.type != MaterialType::Glossy) continue;
        m.albedo = ColorTexture{};
        m.albedo.value = Color(rho);
        scene.replace_material(i, m);
    }
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
    for (const std::string& why : in.model->biased_because) std::cerr << "  biased: " << why << "\n";
}

// ---- 3. Rendering ----

struct RunResult {
    RenderResult render;
    int spp_taken = 0;
    std::vector<Checkpoint> checkpoints;  // with --reference
};
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

// ---- 4. Measuring ----

// Each layer's share of the image's total luminance, as a printable line.
std::vector<std::string> layer_shares(const RenderResult& r, const Model& model) {
    return lessons::layer_shares(r.image, r.layers, model.layer_names);
}

// ---- 5. Writing ----

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

void write_run_report(const Lesson& lesson, const CommonOptions& o, const RunInputs& in,
                      const RunResult& run, const std::optional<ErrorMetrics>& error,
                      const std::vector<std::string>& shares) {
    const RenderResult& r = run.render;
    Report report;
    report.set("chapter", lesson.name);
    report.set("scene", in.scene.source);
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
    const std::vector<std::string> bias = run_bias(o, in);
    report.set("biased", !bias.empty());
    report.set("bias", bias);
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
    if (in.model->splats) report.set("splat_bytes", static_cast<uint64_t>(r.splat_bytes));
    report.write(o.report);
}

}  // namespace

void parse_lesson_arguments(const std::vector<std::string>& args, const Lesson& lesson,
                            CLI::App& app, CommonOptions& o) {
    add_common_options(app, o);
    if (lesson.add_options) lesson.add_options(app);
    try {
        // CLI11 takes the arguments after the program's name, last first.
        std::vector<std::string> reversed(args.rbegin(), args.rend());
        if (!reversed.empty()) reversed.pop_back();
        app.parse(reversed);
    } catch (const CLI::CallForHelp&) {
        throw;
    } catch (const CLI::ParseError& e) {
        throw InputError("command line", 0, "", e.what());
    }
    if (o.spp <= 0) o.spp = lesson.default_spp;
    parse_part_options(app, o);
    if (o.out.empty()) o.out = default_out(lesson, o.scene);
    o.image_options = image_options(app);
}

std::string image_options(const CLI::App& app) {
    // What only places, names, shows, measures or speeds up the render; and the scene, the seed
    // and the image size, which a part's header keeps on their own.
    static const char* const kApart[] = {
        "--help",   "--scene",   "--out",         "--spp",          "--samples",
        "--pixels", "--width",   "--height",      "--threads",      "--seed",
        "--report", "--exposure", "--quiet",      "--reference",    "--time",
        "--convergence", "--variance", "--max-scene-mb", "--max-file-mb"};
    std::vector<std::string> lines;
    for (const CLI::Option* opt : app.get_options()) {
        const std::string name = opt->get_name();
        if (name.empty() ||
            std::find(std::begin(kApart), std::end(kApart), name) != std::end(kApart))
            continue;
        std::string value;
        if (opt->count() > 0) {
            for (const std::string& r : opt->results()) value += (value.empty() ? "" : ",") + r;
        } else {
            value = opt->get_default_str();
        }
        // The sampler by its name even when defaulted: the default changed once (independent,
        // then kronecker), and parts of either must not pass for each other.
        if (name == "--sampler" && value.empty()) value = "kronecker";
        lines.push_back(name + "=" + value);
    }
    std::sort(lines.begin(), lines.end());
    std::string text;
    for (const std::string& l : lines) text += (text.empty() ? "" : "\n") + l;
    return text;
}

void prepare_run(const CommonOptions& o, const Lesson& lesson, RunInputs& in) {
    in.scene = load_scene(o.scene, {o.width, o.height, o.limits, o.threads});
    check_memory(in.scene.width, in.scene.height);
    apply_naive_methods(o.naive, in.scene.naive);
    apply_albedo(o.albedo, in.scene);
    check_part(o, in.scene);
    in.reference = read_reference(o, in.scene);
    in.model = lesson.make_model(in.scene);
    in.model->notes.insert(in.model->notes.end(), in.scene.notes.begin(), in.scene.notes.end());
    // What a part belongs to, taken now: a scene edited while the part renders is not its scene.
    if (o.is_part()) in.scene_hash = scene_files_hash(in.scene, o.limits);
    if (in.model->splats && o.part.crops(in.scene))
        throw InputError("command line", 0, "--pixels",
                         lesson.name + " splats light from every pixel's light subpath onto "
                                       "pixels anywhere in the image, so a crop cannot hold its "
                                       "part: split it by --samples only");
    if (!o.variance.empty() && o.sampler != "independent")
        in.model->notes.push_back("--variance: the samples are stratified (--sampler " + o.sampler +
                                 "), so the sample variance / N is not the error of the mean "
                                 "(usually above it, below it for rare events such as a light "
                                 "path few samples take); --sampler independent measures it");
    if (o.albedo >= 0.0f)
        in.model->notes.push_back("--albedo: every diffuse reflectance is grey " +
                                 std::to_string(o.albedo) + " (the scene's own are ignored)");
}

std::vector<std::string> run_bias(const CommonOptions& o, const RunInputs& in) {
    std::vector<std::string> bias = in.model->biased_because;
    if (o.clamp > 0.0f) bias.push_back("--clamp: bright samples are scaled down");
    if (in.scene.naive.any()) bias.push_back("--naive: the naive methods are wrong on purpose");
    return bias;
}

RenderSettings render_settings(const CommonOptions& o) {
    RenderSettings settings;
    settings.threads = o.threads;
    settings.seed = o.seed;
    settings.progress = false;
    settings.clamp = o.clamp;
    settings.sampler = o.sampler == "kronecker" ? RenderSettings::Sampler::Kronecker
                       : o.sampler == "sobol"   ? RenderSettings::Sampler::Sobol
                                                : RenderSettings::Sampler::Independent;
    return settings;
}

int run_lesson(int argc, char** argv, const Lesson& lesson) {
    CLI::App app(lesson.description, lesson.name);
    CommonOptions o;
    if (const std::optional<int> status = read_command_line(argc, argv, lesson, app, o))
        return *status;

    RunInputs in;
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
    if (!o.quiet) print_run_header(lesson, o, in);

    const RunResult run = render_run(o, in);
    const RenderResult& r = run.render;
    if (r.nan_samples + r.inf_samples > 0)
        std::cerr << lesson.name << ": warning: " << r.nan_samples << " NaN and " << r.inf_samples
                  << " infinite samples were left out of the average (" << r.nan_pixels << " and "
                  << r.inf_pixels << " pixels)\n";

    const std::vector<std::string> shares = layer_shares(r, *in.model);
    if (!o.quiet)
        for (const std::string& line : shares) std::cerr << "  " << line << "\n";
    std::optional<ErrorMetrics> error;
    if (!o.reference.empty()) {
        error = compare_images(r.image, in.reference);
        if (!o.quiet)
            std::fprintf(stderr, "%s: against %s: mse %.6g, rmse %.6g, relmse %.6g, mae %.6g\n",
                         lesson.name.c_str(), o.reference.c_str(), error->mse, error->rmse,
                         error->relmse, error->mae);
    }

    int status = 0;
    if (r.interrupted) {
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
    if (!o.quiet && status == 0)
        std::fprintf(stderr, "%s: wrote %s.exr and %s.png in %.2f s (%.2f Mrays/s)\n",
                     lesson.name.c_str(), o.out.c_str(), o.out.c_str(), r.stats.seconds,
                     mrays_per_second(r.stats));
    return status;
}

}  // namespace lessons
