// bench_bvh: how fast the suite finds what a ray hits, beside Intel's Embree 3 when it is
// installed, and how fast lesson 4 renders (docs/performance.md). A benchmark, not a test: it
// prints figures and asserts nothing about them.
//
//   build/bin/bench_bvh [--quick] [--csv FILE] [--rays N] [--scene NAME]... [--set NAME]...
//                       [--query closest|any] [--embree-robust]
//
// --scene and --set (each may repeat) keep only the named scenes (cornell_box, sphere_10092,
// sphere_99372, sphere_1002252) and measurements (the ray sets primary, shadow, diffuse and
// random; build; render, lesson 4 on the Cornell box). --query keeps one of the two queries. So
// a few rows can be measured at a time, for profiling.
// --embree-robust builds Embree's scenes with RTC_SCENE_FLAG_ROBUST. Embree documents that mode
// as robust traversal without the optimisations that reduce arithmetic accuracy, typically used
// against rays shooting through the edges of neighbouring primitives; it does not call it
// watertight. Of Embree's modes it comes closest to our watertight test (docs/performance.md).
// Without Embree built in, --embree-robust is an error (exit status 2).
//
// Scenes: the Cornell box as triangles, and a displaced sphere generated here at about 10k, 100k
// and 1M triangles. Ray sets: coherent primary rays, shadow rays to a light, cosine-distributed
// diffuse rays from the primary hits, uniformly random rays. Each set is traced with closest-hit
// and any-hit queries, on 1 thread and on every thread; both libraries trace the same rays from
// the same process. Build time and memory per triangle are measured at every size.
//
// The run's steps are here (the options, the checks of the filters, then the measurements);
// scenes.h makes the meshes and rays, measure.h measures, report.h prints and writes the rows.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "measure.h"
#include "report.h"
#include "scenes.h"

#ifdef LESSONS_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace lessons::bench {
namespace {

constexpr const char* kUsage =
    "usage: bench_bvh [--quick] [--csv FILE] [--rays N] [--scene NAME]... [--set NAME]...\n"
    "                 [--query closest|any] [--embree-robust] [--scaling]\n"
    "  --scaling: build time, memory and incoherent (random) closest-hit throughput at\n"
    "             10k, 100k, 1M and 10M triangles, ours and Embree's, with the log-log slopes\n"
    "             (--csv: one row per size)\n"
    "  --scene: cornell_box, sphere_10092, sphere_99372, sphere_1002252\n"
    "  --set:   primary, shadow, diffuse, random, build, render (lesson 4, Cornell box)\n"
    "  --query: closest or any (the ray sets' queries; default both)\n";

// The command line into `o`; an exit status if the run ends here (usage, or a bad option).
std::optional<int> parse_options(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--quick") {
            o.quick = true;
        } else if (a == "--csv" && i + 1 < argc) {
            o.csv = argv[++i];
        } else if (a == "--rays" && i + 1 < argc) {
            char* end = nullptr;
            const char* text = argv[++i];
            o.ray_count = std::strtoul(text, &end, 10);
            if (*end != '\0' || o.ray_count == 0) {
                std::cerr << "bench_bvh: error: --rays: not a positive integer: '" << text << "'\n";
                return 2;
            }
        } else if (a == "--scene" && i + 1 < argc) {
            o.only_scenes.push_back(argv[++i]);
        } else if (a == "--set" && i + 1 < argc) {
            o.only_sets.push_back(argv[++i]);
        } else if (a == "--scaling") {
            o.scaling = true;
        } else if (a == "--embree-robust") {
            o.embree_robust = true;
        } else if (a == "--query" && i + 1 < argc && o.only_query.empty()) {
            o.only_query = argv[++i];
        } else {
            std::cerr << kUsage;
            return a == "--help" || a == "-h" ? 0 : 2;
        }
    }
    if (o.ray_count == 0) o.ray_count = o.quick ? 200000 : 1000000;
    return std::nullopt;
}

// The sizes of the displaced spheres: 10k, 100k, 1M triangles; --scaling adds 10M (12 x 913^2 =
// 10,002,828), and takes its own filters.
std::optional<int> choose_sizes(Options& o, std::vector<int>& sphere_sides) {
    sphere_sides = {29, 91, 289};
    if (!o.scaling) return std::nullopt;
    if (!o.only_scenes.empty() || !o.only_sets.empty() || !o.only_query.empty() || o.quick) {
        std::cerr << "bench_bvh: error: --scaling takes its own scenes, sets and query\n";
        return 2;
    }
    sphere_sides.push_back(913);
    for (int n : sphere_sides) o.only_scenes.push_back("sphere_" + std::to_string(12 * n * n));
    o.only_sets = {"build", "random"};
    o.only_query = "closest";
    return std::nullopt;
}

// Every filter names something there is, and together they leave something to measure; else
// the exit status.
std::optional<int> check_filters(const Options& o, const std::vector<int>& sphere_sides) {
    for (const std::string& name : o.only_scenes) {
        bool known = name == "cornell_box";
        for (int n : sphere_sides) known |= name == "sphere_" + std::to_string(12 * n * n);
        if (!known) {
            std::cerr << "bench_bvh: error: --scene: no scene named '" << name << "'\n" << kUsage;
            return 2;
        }
    }
    for (const std::string& name : o.only_sets)
        if (name != "primary" && name != "shadow" && name != "diffuse" && name != "random" &&
            name != "build" && name != "render") {
            std::cerr << "bench_bvh: error: --set: nothing named '" << name << "'\n" << kUsage;
            return 2;
        }
    if (!o.only_query.empty() && o.only_query != "closest" && o.only_query != "any") {
        std::cerr << "bench_bvh: error: --query: nothing named '" << o.only_query << "'\n"
                  << kUsage;
        return 2;
    }
    // Meshes are made only for the rows asked for: a build, or a ray set.
    if (!wants_meshes(o) &&
        !(wanted(o.only_scenes, "cornell_box") && wanted(o.only_sets, "render"))) {
        std::cerr << "bench_bvh: error: --scene and --set leave nothing to measure (render: only "
                     "with cornell_box)\n";
        return 2;
    }
    return std::nullopt;
}

// What is measured against, the machine and the rays, then the table's head; or, for
// --embree-robust without Embree, the exit status before anything is printed.
std::optional<int> print_head(const Options& o, int all_threads) {
#ifdef LESSONS_HAVE_EMBREE
    std::printf("Embree %s%s, ", RTC_VERSION_STRING, o.embree_robust ? " (robust)" : "");
#else
    if (o.embree_robust) {
        std::cerr << "bench_bvh: error: --embree-robust: Embree is not built in\n";
        return 2;
    }
    std::printf("Embree: not built in (install libembree-dev and re-run cmake), ");
#endif
    std::printf("%d hardware threads, %zu rays per set%s\n\n", all_threads, o.ray_count,
                o.quick ? " (--quick)" : "");
    print_table_head();
    return std::nullopt;
}

// The meshes the filters keep, for the rows asked for: a build, or a ray set.
std::vector<TriangleMesh> make_meshes(const Options& o, const std::vector<int>& sphere_sides) {
    std::vector<TriangleMesh> meshes;
    if (!wants_meshes(o)) return meshes;
    if (wanted(o.only_scenes, "cornell_box"))
        meshes.push_back(
            cornell_box_mesh(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml"));
    for (int n : sphere_sides)
        if (wanted(o.only_scenes, "sphere_" + std::to_string(12 * n * n)))
            meshes.push_back(displaced_sphere(n));
    return meshes;
}

// The table (and the scaling slopes) written to --csv.
void write_results(const Options& o, const std::vector<Row>& rows, int all_threads) {
    if (o.scaling) {
        report_scaling(rows, all_threads);
        if (!o.csv.empty()) write_scaling_csv(o.csv, rows, all_threads);
    } else if (!o.csv.empty()) {
        write_csv(o.csv, rows);
    }
}

// Parse, check, measure (builds, ray sets, lesson 4's render), write.
int run(int argc, char** argv) {
    Options o;
    std::vector<int> sphere_sides;
    if (const std::optional<int> status = parse_options(argc, argv, o)) return *status;
    if (const std::optional<int> status = choose_sizes(o, sphere_sides)) return *status;
    if (const std::optional<int> status = check_filters(o, sphere_sides)) return *status;
    const int all_threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<int> thread_counts = {1};
    if (all_threads > 1) thread_counts.push_back(all_threads);
    if (const std::optional<int> status = print_head(o, all_threads)) return *status;

    const std::vector<TriangleMesh> meshes = make_meshes(o, sphere_sides);
    Table table{o.embree_robust, {}};
    measure_builds(meshes, o, thread_counts, table);
    measure_ray_sets(meshes, o, thread_counts, all_threads, table);
    measure_render(o, thread_counts, table);
    write_results(o, table.rows, all_threads);
    return 0;
}

}  // namespace
}  // namespace lessons::bench

int main(int argc, char** argv) {
    return lessons::bench::run(argc, argv);
}
