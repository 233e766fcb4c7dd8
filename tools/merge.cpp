// merge: joins the parts of a render split across jobs into the whole render (docs/farm.md).
//
//   build/bin/merge PART.exr ... --out PREFIX [--reference REF.exr] [--variance PREFIX]
//   build/bin/merge --status PART.exr ... [--spp N] [--out PREFIX]
//
// Parts are the EXRs a lesson writes with --samples A:B and/or --pixels X0:X1,Y0:Y1. A merge
// checks that they belong together (lesson, scene files, options, seed, image size), that no two
// hold the same samples of a pixel, and that together they hold samples 0 .. N-1 of every pixel;
// it then writes PREFIX.exr, PREFIX.png, each layer's PREFIX_NAME.exr/.png and PREFIX.json, a
// report like a lesson's. The image is bit for bit that of one run with --spp N.
//
// --status lists the parts there are (and the files named that are not there yet), the samples
// per pixel reached and the pieces missing; with --out it merges what there is into a preview.
// Exit codes: 0 done, 1 a failure while writing, 2 bad input (naming the part and the field).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "farm/merge_parts.h"
#include "io/image.h"
#include "io/input_error.h"
#include "io/report.h"
#include "render/metrics.h"

using namespace lessons;

namespace {

struct Options {
    std::vector<std::string> parts;
    std::string out, reference, variance, report;
    float exposure = 0.0f;
    bool exposure_given = false;
    bool status = false;
    int spp = 0;
    bool quiet = false;
};

// The merged render: the image, its layers, variance, and the sums of the parts' statistics.
struct Merged {
    std::vector<Film> films;
    Image image;
    std::vector<Image> layers;
};

// Refuses a merge whose films would not fit in memory, before any is made.
void check_memory(const std::vector<PartFile>& parts) {
    const PartHeader& h = parts[0].header;
    const double need = static_cast<double>(h.image_width) * h.image_height *
                        (static_cast<double>(h.films.size()) * sizeof(FilmPixel) + 64.0);
    check_fits_in_memory(need,
                         "merging " + std::to_string(h.films.size()) + " films of " +
                             std::to_string(h.image_width) + "x" + std::to_string(h.image_height) +
                             " needs",
                         parts[0].path, "lessons.image");
}

Merged merge(const std::vector<PartFile>& parts) {
    check_memory(parts);
    Merged m;
    m.films = merge_parts(parts);
    m.image = m.films[0].mean();
    for (size_t k = 1; k < m.films.size(); ++k) m.layers.push_back(m.films[k].mean());
    return m;
}

// The error of the merged image against --reference, if there is one.
std::optional<ErrorMetrics> reference_error(const Options& o, const Image& image) {
    if (o.reference.empty()) return std::nullopt;
    Image reference;
    try {
        reference = read_exr(o.reference);
    } catch (const std::runtime_error& e) {
        throw InputError("command line", 0, "--reference", e.what());
    }
    return compare_images(image, reference, "--reference " + o.reference);
}

// PREFIX.exr and PREFIX.png, each layer's PREFIX_NAME.exr and .png, and with --variance the
// image's per-pixel variance of the mean.
void write_images(const Options& o, const PartHeader& h, const Merged& m) {
    const float exposure = o.exposure_given ? o.exposure : h.exposure;
    const std::filesystem::path dir = std::filesystem::path(o.out).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir);
    write_exr(m.image, o.out + ".exr");
    write_png(m.image, o.out + ".png", exposure);
    for (size_t k = 0; k < m.layers.size(); ++k) {
        write_exr(m.layers[k], o.out + "_" + h.films[k + 1] + ".exr");
        write_png(m.layers[k], o.out + "_" + h.films[k + 1] + ".png", exposure);
    }
    if (!o.variance.empty()) write_exr(m.films[0].variance_of_mean(), o.variance + ".exr");
}

// The parts' figures together: rendering time in all and of the slowest part, rays, and whether
// any part was interrupted.
struct PartTotals {
    double seconds = 0.0, slowest = 0.0;
    uint64_t rays = 0;
    bool partial = false;
};

PartTotals part_totals(const std::vector<PartFile>& parts) {
    PartTotals t;
    for (const PartFile& p : parts) {
        t.seconds += p.header.seconds;
        t.slowest = std::max(t.slowest, p.header.seconds);
        t.rays += p.header.rays;
        t.partial = t.partial || p.header.partial();
    }
    return t;
}

// The report's account of the run: what was merged, from which parts, in how long, and the
// merged film's invalid pixels and samples.
void report_run(Report& report, const Options& o, const std::vector<PartFile>& parts,
                const Film& film, const Coverage& coverage, bool preview, const PartTotals& t) {
    const PartHeader& h = parts[0].header;
    report.set("chapter", h.lesson);
    report.set("scene", h.scene);
    report.set("width", h.image_width);
    report.set("height", h.image_height);
    report.set("spp", coverage.spp_min);
    report.set("preview", preview);
    if (preview) report.set("spp_max", coverage.spp_max);
    report.set("parts", static_cast<int>(parts.size()));
    report.set("partial_parts", t.partial);
    const std::string mixed = mixed_builds(parts);
    report.set("one_build_and_cpu", mixed.empty());
    report.set("firefly_pixels", film.firefly_pixels());
    report.set("biased", !h.bias.empty());
    report.set("bias", h.bias);
    report.set("seed", h.seed);
    report.set("seconds", t.seconds);
    report.set("wall_seconds", t.slowest);
    report.set("rays", t.rays);
    report.set("mrays_per_second", t.seconds > 0.0 ? t.rays / t.seconds * 1e-6 : 0.0);
    report.set("nan_pixels", film.nan_pixels());
    report.set("inf_pixels", film.inf_pixels());
    report.set("nan_samples", film.nan_samples());
    report.set("inf_samples", film.inf_samples());
    report.set("image", o.out + ".exr");
}

// The error against --reference, in the report and on stderr.
void report_error(Report& report, const Options& o, const ErrorMetrics& e, double seconds) {
    if (!o.quiet)
        std::fprintf(stderr, "merge: against %s: mse %.6g, rmse %.6g, relmse %.6g, mae %.6g\n",
                     o.reference.c_str(), e.mse, e.rmse, e.relmse, e.mae);
    report.set("reference", o.reference);
    report.set("mse", e.mse);
    report.set("rmse", e.rmse);
    report.set("relmse", e.relmse);
    report.set("mae", e.mae);
    report.set("efficiency", e.mse > 0.0 && seconds > 0.0 ? 1.0 / (e.mse * seconds) : 0.0);
}

// Each layer's share of the image, in the report and on stderr.
void report_layers(Report& report, const Options& o, const PartHeader& h, const Merged& m) {
    const std::vector<std::string> names(h.films.begin() + 1, h.films.end());
    const std::vector<std::string> shares = layer_shares(m.image, m.layers, names);
    if (!shares.empty()) report.set("layers", shares);
    if (!o.quiet)
        for (const std::string& line : shares) std::cerr << "  " << line << "\n";
}

// The merged render's files and its report (PREFIX.json, or --report).
void write_outputs(const Options& o, const std::vector<PartFile>& parts, const Merged& m,
                   const Coverage& coverage, bool preview) {
    const PartHeader& h = parts[0].header;
    // The error against --reference first: a bad reference writes nothing.
    const std::optional<ErrorMetrics> error = reference_error(o, m.image);
    write_images(o, h, m);
    const PartTotals totals = part_totals(parts);
    Report report;
    report_run(report, o, parts, m.films[0], coverage, preview, totals);
    if (error) report_error(report, o, *error, totals.seconds);
    report.set("notes", h.notes);
    report_layers(report, o, h, m);
    report.write(o.report.empty() ? o.out + ".json" : o.report);
    if (!o.quiet)
        std::fprintf(stderr,
                     "merge: %zu parts, %d spp%s: wrote %s.exr and %s.png (%.2f s of rendering "
                     "in all, the slowest part %.2f s)\n",
                     parts.size(), coverage.spp_min, preview ? " (preview)" : "", o.out.c_str(),
                     o.out.c_str(), totals.seconds, totals.slowest);
}

int status(const Options& o) {
    std::vector<PartFile> parts;
    std::vector<std::string> absent, unreadable;
    for (const std::string& path : o.parts) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
            absent.push_back(path);
            continue;
        }
        try {
            read_part(path);  // the whole part, to see that it is sound; then only its header
            parts.push_back(read_part(path, false));
        } catch (const InputError& e) {
            unreadable.push_back(e.what());
        }
    }
    std::printf("%zu of %zu parts there\n", parts.size(), o.parts.size());
    for (const PartFile& p : parts) {
        const PartHeader& h = p.header;
        std::printf("  %s: pixels %s, samples %s%s, %.2f s\n", p.path.c_str(),
                    h.pixels_text().c_str(), h.samples_text().c_str(),
                    h.partial() ? (" (interrupted; asked for " + std::to_string(h.sample_begin) +
                                   ":" + std::to_string(h.planned_end) + ")")
                                      .c_str()
                                : "",
                    h.seconds);
    }
    for (const std::string& a : absent) std::printf("  %s: not there yet\n", a.c_str());
    for (const std::string& u : unreadable) std::printf("  unreadable: %s\n", u.c_str());
    if (parts.empty()) return 0;
    check_parts_agree(parts);
    check_parts_disjoint(parts);
    const Coverage c = part_coverage(parts, o.spp);
    const PartHeader& h = parts[0].header;
    for (const std::string& b : c.beyond) std::printf("  too many samples: %s\n", b.c_str());
    if (const std::string mixed = mixed_builds(parts); !mixed.empty())
        std::printf("  note: %s: the merge may differ from a single run in the last bits\n",
                    mixed.c_str());
    std::printf("%s on %s, %dx%d, seed %llu: %d to %d of %d spp per pixel, %.1f%% of the samples\n",
                h.lesson.c_str(), h.scene.c_str(), h.image_width, h.image_height,
                static_cast<unsigned long long>(h.seed), c.spp_min, c.spp_max, c.target,
                100.0 * c.fraction);
    const size_t shown = std::min<size_t>(c.missing.size(), 20);
    for (size_t i = 0; i < shown; ++i) std::printf("  missing: %s\n", c.missing[i].c_str());
    if (c.missing.size() > shown)
        std::printf("  ... and %zu more missing pieces\n", c.missing.size() - shown);
    // A named part that is not there (a task still queued, or one that failed) leaves the farm
    // incomplete even when the parts there cover every sample they were asked for: the missing
    // part may be the last sample range, which no part there knows of.
    const size_t not_there = absent.size() + unreadable.size();
    if (not_there > 0)
        std::printf("incomplete: %zu of the %zu parts named %s not there or unreadable\n",
                    not_there, o.parts.size(), not_there == 1 ? "is" : "are");
    else
        std::printf("%s\n", c.complete() ? "complete: merge them" : "incomplete");
    if (!o.out.empty()) {
        if (!c.beyond.empty())
            throw InputError("command line", 0, "--spp",
                             c.beyond[0] + ": no preview of more samples than asked for");
        write_outputs(o, parts, merge(parts), c, !c.complete());
    }
    return 0;
}

int run(const Options& o) {
    if (o.status) return status(o);
    if (o.out.empty()) throw InputError("command line", 0, "--out", "is needed (or --status)");
    std::vector<PartFile> parts;
    for (const std::string& path : o.parts) parts.push_back(read_part(path, false));
    check_parts_agree(parts);
    check_parts_disjoint(parts);
    const Coverage c = part_coverage(parts, o.spp);
    if (c.target == 0) throw InputError("command line", 0, "PARTS", "the parts hold no samples");
    if (!c.beyond.empty())
        throw InputError("command line", 0, "--spp",
                         c.beyond[0] + ": leave it out, or merge without --spp");
    if (const std::string mixed = mixed_builds(parts); !mixed.empty() && !o.quiet)
        std::cerr << "merge: warning: " << mixed
                  << ": the merged image is a correct render, but may differ from a single run "
                     "in the last bits (docs/farm.md)\n";
    if (!c.complete()) {
        std::string msg = "the parts do not cover samples 0:" + std::to_string(c.target) +
                          " of every pixel: missing " + c.missing[0];
        if (c.missing.size() > 1)
            msg += " and " + std::to_string(c.missing.size() - 1) + " more pieces";
        throw InputError("command line", 0, "PARTS", msg + " (merge --status lists them)");
    }
    write_outputs(o, parts, merge(parts), c, false);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app(
        "merge: joins parts of a render (a lesson's --samples/--pixels EXRs) into the "
        "whole render, bit for bit the single run's (docs/farm.md)",
        "merge");
    Options o;
    app.add_option("parts", o.parts, "The part EXRs")->required();
    app.add_option("--out", o.out, "Output prefix: PREFIX.exr, PREFIX.png, PREFIX.json");
    app.add_flag("--status", o.status,
                 "List the parts there are and those not there yet, the samples per pixel "
                 "reached and the pieces missing; with --out, merge what there is as a preview");
    app.add_option("--spp", o.spp,
                   "The samples per pixel the render is to reach (default: the largest end any "
                   "part was asked for)")
        ->check(CLI::Range(1, 1 << 24));
    app.add_option("--reference", o.reference, "An EXR to measure the merged image against");
    app.add_option("--variance", o.variance,
                   "Write the per-pixel variance of the mean as PREFIX.exr (equal to a single "
                   "run's to rounding: the sums of squares are doubles)");
    app.add_option("--exposure", o.exposure, "PNG exposure in stops (default: the parts')")
        ->check(CLI::Range(-30.0, 30.0));
    app.add_option("--report", o.report, "The JSON report (default PREFIX.json)");
    app.add_flag("--quiet", o.quiet, "Print only errors");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    o.exposure_given = app.count("--exposure") > 0;
    try {
        return run(o);
    } catch (const InputError& e) {
        std::cerr << "merge: error: " << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        std::cerr << "merge: error: out of memory while reading the parts\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "merge: error: " << e.what() << "\n";
        return 1;
    }
}
