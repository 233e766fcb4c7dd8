// bench_bvh's output (bench_bvh.cpp): a table on stdout and, with --csv, one CSV row per
// measurement; with --scaling, how cost grows with the triangle count.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace lessons::bench {

struct Row {
    std::string scene;
    size_t triangles = 0;
    std::string rays;  // ray set, or "build" / "render"
    std::string query;
    int threads = 1;
    double ours = 0.0;             // Mrays/s (build: ms; render: Msamples/s)
    std::optional<double> embree;  // the same for Embree
    std::string note;              // e.g. bytes per triangle, hit counts
};

// v with `digits` digits after the point.
std::string fixed(double v, int digits);

// The table's column heads, on stdout.
void print_table_head();

// The rows measured: each printed as it comes, and kept for the CSV and the scaling report.
struct Table {
    bool embree_robust = false;  // Embree's figures are of its robust mode: each row says so
    std::vector<Row> rows;
    void add(Row r);
};

// One CSV row per measurement.
void write_csv(const std::string& path, const std::vector<Row>& rows);

// --scaling: the log-log slopes of build time, memory and random closest-hit throughput against
// the triangle count (throughput on `threads` threads), on stdout; and one CSV row per size.
void report_scaling(const std::vector<Row>& rows, int threads);
void write_scaling_csv(const std::string& path, const std::vector<Row>& rows, int threads);

}  // namespace lessons::bench
