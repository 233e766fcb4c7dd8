// The lesson driver's first step: the command line. The flags every lesson shares, a part's
// --samples and --pixels, and the options that change the image, as a part's header keeps them
// (see run.h).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>

#include "driver/run.h"
#include "farm/part_header.h"
#include "io/input_error.h"
#include "io/scene_file.h"

namespace lessons {

namespace {

// What to render and where to write it: the scene, the output, the samples and their part, the
// image's size, threads, seed, report, exposure, progress.
void add_output_options(CLI::App& app, CommonOptions& o) {
    app.add_option("--scene", o.scene,
                   "Scene file (TOML, or glTF), see docs/scene-format.md; or the name of a "
                   "scene the suite ships (cornell_box, hard/cornell_tiny), when no such file "
                   "is here")
        ->capture_default_str();
    app.add_option("--out", o.out,
                   "Output prefix: writes PREFIX.exr (linear radiance) and PREFIX.png (sRGB); "
                   "default out/<lesson>_<scene>");
    app.add_option("--spp", o.spp, "Samples per pixel (default: the lesson's)")
        ->check(CLI::Range(1, 1 << 24));
    app.add_option("--samples", o.samples,
                   "A part of a render split across jobs (docs/farm.md): render sample indices "
                   "A .. B-1 of every pixel (--spp N is --samples 0:N) and write a part EXR, "
                   "which merge (build/bin/merge; installed, illumination-merge) joins with the "
                   "others");
    app.add_option("--pixels", o.pixels,
                   "A part that is a crop X0:X1,Y0:Y1 of the image (pixels X0 .. X1-1 and "
                   "Y0 .. Y1-1, in the whole image's coordinates), written as a part EXR");
    app.add_option("--width", o.width, "Image width in pixels, overriding the scene")
        ->check(CLI::Range(1, kMaxImageSide));
    app.add_option("--height", o.height, "Image height in pixels, overriding the scene")
        ->check(CLI::Range(1, kMaxImageSide));
    app.add_option("--threads", o.threads,
                   "Worker threads, for the BVH's build and the render (0: one per core)")
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
}

// Speed against error: the reference, the time budget, the convergence CSV, the variance image.
void add_measuring_options(CLI::App& app, CommonOptions& o) {
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
}

// What changes the image itself: the naive methods, the sampler, the furnace's albedo, the clamp.
void add_image_options(CLI::App& app, CommonOptions& o) {
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
    app.add_option("--clamp", o.clamp,
                   "Clamp each sample's luminance to this value (removes fireflies; biased, and "
                   "the report says so)")
        ->check(CLI::PositiveNumber);
}

// The input's limits.
void add_limit_options(CLI::App& app, CommonOptions& o) {
    app.add_option("--max-scene-mb", o.limits.scene_mb,
                   "Largest scene file read, in MiB (a scene is text; meshes are other files)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--max-file-mb", o.limits.file_mb,
                   "Largest file a scene may name (OBJ mesh, texture, environment map), in MiB")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
}

void add_common_options(CLI::App& app, CommonOptions& o) {
    add_output_options(app, o);
    add_measuring_options(app, o);
    add_image_options(app, o);
    add_limit_options(app, o);
}

// "A:B" with 0 <= A < B <= limit, or throws naming `flag`.
void parse_range(const std::string& text, const std::string& flag, long long limit, int& begin,
                 int& end, const std::string& what) {
    long long a = 0, b = 0;
    if (!parse_pair(text, ':', a, b) || b <= a || b > limit)
        throw InputError(
            "command line", 0, flag,
            "'" + text + "' is not " + what + " A:B with 0 <= A < B <= " + std::to_string(limit));
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
        "--help",        "--scene",    "--out",          "--spp",        "--samples",
        "--pixels",      "--width",    "--height",       "--threads",    "--seed",
        "--report",      "--exposure", "--quiet",        "--reference",  "--time",
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

}  // namespace lessons
