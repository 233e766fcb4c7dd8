// The shared lesson driver: command line, scene, render, outputs, report.
#include "app.h"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "image.h"
#include "input_error.h"
#include "report.h"
#include "scene_file.h"

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
    app.add_option("--width", o.width, "Image width in pixels, overriding the scene")
        ->check(CLI::Range(1, kMaxImageSide));
    app.add_option("--height", o.height, "Image height in pixels, overriding the scene")
        ->check(CLI::Range(1, kMaxImageSide));
    app.add_option("--threads", o.threads, "Worker threads (0: one per core)")
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

// Refuses an image whose buffers would not fit in memory, before any work is done.
void check_memory(int width, int height) {
    // Film (two double triples and counts), the mean and variance images and their copies in
    // the result, the PNG bytes: 128 bytes per pixel is a safe upper bound.
    const double bytes_per_pixel = 128.0;
    const double need = bytes_per_pixel * width * height;
    const double physical =
        static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
    if (physical > 0 && need > 0.5 * physical) {
        char msg[200];
        std::snprintf(msg, sizeof msg,
                      "%dx%d needs %.1f GiB for the image buffers, more than half of this "
                      "machine's %.1f GiB",
                      width, height, need / (1 << 30), physical / (1 << 30));
        throw InputError("command line", 0, "--width/--height", msg);
    }
}

std::string default_out(const Lesson& lesson, const std::string& scene_path) {
    return "out/" + lesson.name + "_" + std::filesystem::path(scene_path).stem().string();
}

}  // namespace

RenderResult render_scene(const Scene& scene, const Model& model, int spp,
                          const RenderSettings& settings) {
    std::vector<Film> films(1 + model.layer_names.size(), Film(scene.width, scene.height));
    const Film& film = films[0];
    RenderResult r;
    if (model.layer_names.empty())
        r.stats = render(scene.camera, films[0], settings, model.radiance, 0, spp);
    else
        r.stats = render_layers(scene.camera, films, settings, model.layered, 0, spp);
    for (size_t k = 1; k < films.size(); ++k) r.layers.push_back(films[k].mean());
    r.image = film.mean();
    r.variance = film.variance_of_mean();
    r.nan_pixels = film.nan_pixels();
    r.inf_pixels = film.inf_pixels();
    r.nan_samples = film.nan_samples();
    r.inf_samples = film.inf_samples();
    return r;
}

int run_lesson(int argc, char** argv, const Lesson& lesson) {
    CLI::App app(lesson.description, lesson.name);
    CommonOptions o;
    add_common_options(app, o);
    if (lesson.add_options) lesson.add_options(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << lesson.name << ": error: command line: " << e.what() << " (see --help)\n";
        return 2;
    }
    const int spp = o.spp > 0 ? o.spp : lesson.default_spp;
    if (o.out.empty()) o.out = default_out(lesson, o.scene);

    Scene scene;
    Model model;
    try {
        scene = load_scene(o.scene, {o.width, o.height});
        check_memory(scene.width, scene.height);
        model = lesson.make_model(scene);
        const std::filesystem::path dir = std::filesystem::path(o.out).parent_path();
        if (!dir.empty()) std::filesystem::create_directories(dir);
    } catch (const InputError& e) {
        std::cerr << lesson.name << ": error: " << e.what() << "\n";
        return 2;
    } catch (const std::filesystem::filesystem_error& e) {
        std::cerr << lesson.name << ": error: --out " << o.out << ": " << e.what() << "\n";
        return 2;
    }

    if (!o.quiet) {
        std::cerr << lesson.name << ": " << scene.source << ", " << scene.width << "x"
                  << scene.height << ", " << spp << " spp, " << resolve_thread_count(o.threads)
                  << " threads\n";
        for (const std::string& note : model.notes) std::cerr << "  note: " << note << "\n";
    }

    RenderSettings settings;
    settings.threads = o.threads;
    settings.seed = o.seed;
    settings.progress = !o.quiet;
    const RenderResult r = render_scene(scene, model, spp, settings);

    if (r.nan_samples + r.inf_samples > 0)
        std::cerr << lesson.name << ": warning: " << r.nan_samples << " NaN and " << r.inf_samples
                  << " infinite samples were left out of the average (" << r.nan_pixels << " and "
                  << r.inf_pixels << " pixels)\n";

    // Layers: each one's share of the image's total luminance.
    std::vector<std::string> layer_shares;
    double total_luminance = 0.0;
    for (const Color& c : r.image.pixels) total_luminance += luminance(c);
    for (size_t k = 0; k < r.layers.size(); ++k) {
        double layer_luminance = 0.0;
        for (const Color& c : r.layers[k].pixels) layer_luminance += luminance(c);
        const double share = total_luminance > 0.0 ? layer_luminance / total_luminance : 0.0;
        char line[160];
        std::snprintf(line, sizeof line, "%s: %.2f%% of the image's energy",
                      model.layer_names[k].c_str(), 100.0 * share);
        layer_shares.push_back(line);
        if (!o.quiet) std::cerr << "  " << line << "\n";
    }

    int status = 0;
    try {
        write_exr(r.image, o.out + ".exr");
        write_png(r.image, o.out + ".png", o.exposure);
        for (size_t k = 0; k < r.layers.size(); ++k) {
            write_exr(r.layers[k], o.out + "_" + model.layer_names[k] + ".exr");
            write_png(r.layers[k], o.out + "_" + model.layer_names[k] + ".png", o.exposure);
        }
    } catch (const std::exception& e) {
        std::cerr << lesson.name << ": error: " << e.what() << "\n";
        status = 1;
    }
    const double mrays = r.stats.seconds > 0 ? r.stats.rays / r.stats.seconds * 1e-6 : 0.0;
    if (!o.report.empty()) {
        Report report;
        report.set("chapter", lesson.name);
        report.set("scene", scene.source);
        report.set("width", scene.width);
        report.set("height", scene.height);
        report.set("spp", spp);
        report.set("threads", resolve_thread_count(o.threads));
        report.set("seed", o.seed);
        report.set("seconds", r.stats.seconds);
        report.set("rays", r.stats.rays);
        report.set("mrays_per_second", mrays);
        report.set("nan_pixels", r.nan_pixels);
        report.set("inf_pixels", r.inf_pixels);
        report.set("nan_samples", r.nan_samples);
        report.set("inf_samples", r.inf_samples);
        report.set("image", o.out + ".exr");
        report.set("notes", model.notes);
        if (!layer_shares.empty()) report.set("layers", layer_shares);
        try {
            report.write(o.report);
        } catch (const std::exception& e) {
            std::cerr << lesson.name << ": error: " << e.what() << "\n";
            status = 1;
        }
    }
    if (!o.quiet && status == 0) {
        std::fprintf(stderr, "%s: wrote %s.exr and %s.png in %.2f s (%.2f Mrays/s)\n",
                     lesson.name.c_str(), o.out.c_str(), o.out.c_str(), r.stats.seconds, mrays);
    }
    return status;
}

}  // namespace lessons
