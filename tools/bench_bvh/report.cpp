// bench_bvh's output (see report.h).
#include "report.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>

namespace lessons::bench {

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

void print_table_head() {
    std::printf("%-15s %9s %-8s %-8s %2s %10s %10s %6s  %s\n", "scene", "triangles", "rays",
                "query", "th", "ours", "embree", "ratio", "");
}

namespace {

void print_row(const Row& r) {
    std::string ratio = "-", embree = "-";
    if (r.embree) {
        embree = fixed(*r.embree, 2);
        ratio = fixed(r.rays == "build" ? *r.embree / r.ours : r.ours / *r.embree, 2);
    }
    std::printf("%-15s %9zu %-8s %-8s %2d %10s %10s %6s  %s\n", r.scene.c_str(), r.triangles,
                r.rays.c_str(), r.query.c_str(), r.threads, fixed(r.ours, 2).c_str(),
                embree.c_str(), ratio.c_str(), r.note.c_str());
    std::fflush(stdout);
}

}  // namespace

void Table::add(Row r) {
    if (embree_robust && r.embree) r.note += ", embree robust";  // the CSV says so too
    print_row(r);
    rows.push_back(r);
}

void write_csv(const std::string& path, const std::vector<Row>& rows) {
    std::ofstream out(path);
    out << "scene,triangles,rays,query,threads,ours_mrays,embree_mrays,ratio,ours_value,"
           "embree_value,unit,note\n";
    for (const Row& r : rows) {
        const bool ray_row = r.rays != "build" && r.rays != "render";
        out << r.scene << ',' << r.triangles << ',' << r.rays << ',' << r.query << ',' << r.threads
            << ',';
        if (ray_row) {
            out << fixed(r.ours, 3) << ',' << (r.embree ? fixed(*r.embree, 3) : "") << ','
                << (r.embree ? fixed(r.ours / *r.embree, 3) : "") << ",,,Mrays/s";
        } else {
            const bool build = r.rays == "build";
            out << ",,"
                << (r.embree ? fixed(build ? *r.embree / r.ours : r.ours / *r.embree, 3) : "")
                << ',' << fixed(r.ours, 3) << ',' << (r.embree ? fixed(*r.embree, 3) : "") << ','
                << (build ? "ms" : "Msamples/s");
        }
        out << ",\"" << r.note << "\"\n";
    }
    std::cout << "wrote " << path << "\n";
}

namespace {

// A number in a row's note after `key` (e.g. "ours 104.2 B/tri": key "ours "), or NaN.
double note_number(const std::string& note, const std::string& key) {
    const size_t at = note.find(key);
    return at == std::string::npos ? std::nan("") : std::atof(note.c_str() + at + key.size());
}

// One size's figures, from its rows: the build's time on one thread and on all, memory, and
// random closest-hit throughput.
struct ScalingPoint {
    double triangles = 0, ours_ms = 0, embree_ms = NAN, ours_bytes = 0, embree_bytes = NAN,
           ours_mrays = 0, embree_mrays = NAN;
    double ours_all_ms = NAN, embree_all_ms = NAN;  // the build on every thread
};

// One point per mesh measured, in the order of its one-thread build row.
std::vector<ScalingPoint> scaling_points(const std::vector<Row>& rows, int threads) {
    std::vector<ScalingPoint> points;
    for (const Row& r : rows) {
        if (r.rays != "build" || r.threads != 1) continue;
        ScalingPoint p;
        p.triangles = static_cast<double>(r.triangles);
        p.ours_ms = r.ours;
        p.embree_ms = r.embree ? *r.embree : NAN;
        p.ours_bytes = note_number(r.note, "ours ") * p.triangles;
        p.embree_bytes = note_number(r.note, "embree ") * p.triangles;
        for (const Row& t : rows) {
            if (t.scene == r.scene && t.rays == "build" && t.threads == threads && threads > 1) {
                p.ours_all_ms = t.ours;
                p.embree_all_ms = t.embree ? *t.embree : NAN;
            }
            if (t.scene == r.scene && t.rays == "random" && t.threads == threads) {
                p.ours_mrays = t.ours;
                p.embree_mrays = t.embree ? *t.embree : NAN;
            }
        }
        points.push_back(p);
    }
    return points;
}

// The least-squares slope of log y against log x: y grows as x^slope.
double log_slope(const std::vector<ScalingPoint>& points, double ScalingPoint::*y) {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const ScalingPoint& p : points) {
        if (!(p.*y > 0.0)) continue;
        const double lx = std::log(p.triangles), ly = std::log(p.*y);
        n += 1;
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    return n < 2 ? std::nan("") : (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

void report_scaling(const std::vector<Row>& rows, int threads) {
    const std::vector<ScalingPoint> points = scaling_points(rows, threads);
    std::printf(
        "\nHow cost grows (log-log least-squares slopes over %zu sizes; random rays on %d "
        "threads):\n",
        points.size(), threads);
    std::printf("  %-34s %8s %8s\n", "", "ours", "embree");
    const auto line = [&](const char* what, double ScalingPoint::*a, double ScalingPoint::*b) {
        std::printf("  %-34s %8.3f %8.3f\n", what, log_slope(points, a), log_slope(points, b));
    };
    line("build time ~ triangles^", &ScalingPoint::ours_ms, &ScalingPoint::embree_ms);
    if (threads > 1)
        line("build time, all threads ~ triangles^", &ScalingPoint::ours_all_ms,
             &ScalingPoint::embree_all_ms);
    line("memory ~ triangles^", &ScalingPoint::ours_bytes, &ScalingPoint::embree_bytes);
    line("closest-hit Mrays/s ~ triangles^", &ScalingPoint::ours_mrays,
         &ScalingPoint::embree_mrays);
}

void write_scaling_csv(const std::string& path, const std::vector<Row>& rows, int threads) {
    std::ofstream out(path);
    out << "triangles,ours_build_ms,embree_build_ms,ours_bytes,embree_bytes,ours_mrays,"
           "embree_mrays,ours_build_all_threads_ms,embree_build_all_threads_ms\n";
    const auto value = [](double v) { return std::isnan(v) ? std::string() : fixed(v, 3); };
    for (const ScalingPoint& p : scaling_points(rows, threads))
        out << fixed(p.triangles, 0) << ',' << value(p.ours_ms) << ',' << value(p.embree_ms) << ','
            << value(p.ours_bytes) << ',' << value(p.embree_bytes) << ',' << value(p.ours_mrays)
            << ',' << value(p.embree_mrays) << ',' << value(p.ours_all_ms) << ','
            << value(p.embree_all_ms) << '\n';
    std::cout << "wrote " << path << "\n";
}

}  // namespace lessons::bench
