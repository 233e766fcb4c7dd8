// bench_bvh's measurements (bench_bvh.cpp): our build and Embree's, ray throughput of both on
// the same rays, and lesson 4's render of the Cornell box. Each figure is the best of kPasses.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "report.h"
#include "scenes.h"

namespace lessons::bench {

// What to measure: the command line's choices (bench_bvh.cpp, usage).
struct Options {
    bool quick = false;
    std::string csv;
    size_t ray_count = 0;
    std::vector<std::string> only_scenes, only_sets;
    std::string only_query;  // empty: both
    bool embree_robust = false;
    bool scaling = false;
};

// Whether `name` is kept by a filter that keeps only the names in `only` (all, if it is empty).
bool wanted(const std::vector<std::string>& only, const std::string& name);
// Whether the ray-set filter keeps any of the four sets; whether it keeps a set or the builds,
// the rows that need the meshes.
bool wants_ray_sets(const Options& o);
bool wants_meshes(const Options& o);

// Build time and memory of every mesh, on each thread count (a row each).
void measure_builds(const std::vector<TriangleMesh>& meshes, const Options& o,
                    const std::vector<int>& thread_counts, Table& table);
// Ray throughput of every mesh, for each ray set, query and thread count (a row each); Embree's
// scene is built on all_threads.
void measure_ray_sets(const std::vector<TriangleMesh>& meshes, const Options& o,
                      const std::vector<int>& thread_counts, int all_threads, Table& table);
// Lesson 4 on the Cornell box: samples and rays per second, on each thread count (a row each).
void measure_render(const Options& o, const std::vector<int>& thread_counts, Table& table);

}  // namespace lessons::bench
