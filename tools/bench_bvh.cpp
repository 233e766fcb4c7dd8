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
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "geometry/spawn.h"
#include "io/scene_file.h"
#include "lights/lights.h"
#include "render/app.h"
#include "rendering_equation.h"
#include "sampling/rng.h"
#include "sampling/sampling.h"
#include "scene/scene.h"

#ifdef LESSONS_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace lessons {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// ---- Scenes: triangles only, so that both libraries see exactly the same geometry ----

struct TriangleMesh {
    std::string name;
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
    Camera camera;
    Vec3 light;  // a point light for the shadow rays
};

TriangleMesh cornell_box_mesh(const std::string& path) {
    const Scene scene = load_scene(path);
    TriangleMesh mesh{"cornell_box", {}, {}, scene.camera, {}};
    for (const Quad& q : scene.quads()) {
        const auto base = static_cast<uint32_t>(mesh.positions.size());
        mesh.positions.push_back(q.corner);
        mesh.positions.push_back(q.corner + q.edge_u);
        mesh.positions.push_back(q.corner + q.edge_u + q.edge_v);
        mesh.positions.push_back(q.corner + q.edge_v);
        mesh.triangles.push_back({{base, base + 1, base + 2}, 0, false});
        mesh.triangles.push_back({{base, base + 2, base + 3}, 0, false});
    }
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), scene.positions().begin(), scene.positions().end());
    for (Triangle t : scene.triangles()) {
        for (uint32_t& v : t.v) v += base;
        t.material = 0;
        mesh.triangles.push_back(t);
    }
    // The shadow rays' target: just below the middle of the lamp (on it, a ray could end on
    // the lamp or stop just short of it, depending on rounding).
    mesh.light = scene.bounds().centroid();
    if (!scene.area_lights().empty()) {
        const AreaLight& lamp = scene.area_lights()[0];
        mesh.light = lamp.center +
                     1e-3f * glm::length(scene.bounds().max - scene.bounds().min) * lamp.normal;
    }
    return mesh;
}

// A cube subdivided n x n per face, pushed onto the unit sphere and displaced along its normal
// by a sum of sines: 12 n^2 triangles, none degenerate, with bumps that shadow each other.
TriangleMesh displaced_sphere(int n) {
    TriangleMesh mesh;
    mesh.name = "sphere_" + std::to_string(12 * n * n);
    auto radius = [](const Vec3& d) {
        return 1.0f + 0.12f * std::sin(9.0f * d.x) * std::sin(11.0f * d.y) * std::sin(10.0f * d.z) +
               0.04f * std::sin(37.0f * d.x + 23.0f * d.y) * std::sin(41.0f * d.z);
    };
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int face = 0; face < 6; ++face) {
        const Vec3 normal = axes[face / 2] * (face % 2 ? -1.0f : 1.0f);
        const Vec3 u = axes[(face / 2 + 1) % 3] * (face % 2 ? -1.0f : 1.0f);
        const Vec3 v = axes[(face / 2 + 2) % 3];
        const auto base = static_cast<uint32_t>(mesh.positions.size());
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const Vec3 d =
                    glm::normalize(normal + (2.0f * i / n - 1.0f) * u + (2.0f * j / n - 1.0f) * v);
                mesh.positions.push_back(radius(d) * d);
            }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const uint32_t a = base + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
                mesh.triangles.push_back({{a, b, d}, 0, false});
                mesh.triangles.push_back({{a, d, c}, 0, false});
            }
    }
    // Shared cube edges repeat their vertices; the mesh stays closed because the positions are
    // computed identically on both faces.
    mesh.camera = Camera(Vec3(0.3f, 0.8f, -3.2f), Vec3(0.0f), Vec3(0, 1, 0), 45.0f, 1.0f);
    mesh.light = Vec3(2.0f, 3.0f, -2.0f);
    return mesh;
}

// The mesh as a scene, before commit() builds its BVH.
Scene uncommitted_scene(const TriangleMesh& mesh) {
    Scene scene;
    Material white;
    scene.add_material(white);
    scene.add_mesh(mesh.positions, {}, {}, mesh.triangles);
    return scene;
}

Scene suite_scene(const TriangleMesh& mesh) {
    Scene scene = uncommitted_scene(mesh);
    scene.commit();
    return scene;
}

// ---- Ray sets ----

struct RaySet {
    std::string name;
    std::vector<Ray> rays;
};

std::vector<RaySet> make_ray_sets(const Scene& scene, const TriangleMesh& mesh, size_t count) {
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
    RaySet primary{"primary", {}};
    primary.rays.reserve(count);
    for (int y = 0; y < side && primary.rays.size() < count; ++y)
        for (int x = 0; x < side && primary.rays.size() < count; ++x)
            primary.rays.push_back(mesh.camera.generate_ray(x + 0.5f, y + 0.5f, side, side));

    std::vector<SurfaceInteraction> hits;
    for (const Ray& r : primary.rays)
        if (const auto h = scene.intersect(r)) hits.push_back(scene.interaction(r, *h));

    RaySet shadow{"shadow", {}}, diffuse{"diffuse", {}}, random{"random", {}};
    Rng rng(2026, 11, 22);
    for (size_t i = 0; !hits.empty() && shadow.rays.size() < count; ++i) {
        const SurfaceInteraction& si = hits[i % hits.size()];
        const SurfacePoint from{si.p, si.p_error, si.front_face() ? si.n_geo : -si.n_geo};
        shadow.rays.push_back(spawn_ray_to(from, mesh.light));
        const Frame frame(from.n);
        diffuse.rays.push_back(spawn_ray(
            from, frame.to_world(sample_cosine_hemisphere(Vec2(rng.uniform(), rng.uniform())))));
    }
    const Bounds3 box = scene.bounds();
    for (size_t i = 0; i < count; ++i) {
        const Vec3 u(rng.uniform(), rng.uniform(), rng.uniform());
        const Vec3 origin = box.min + u * (box.max - box.min);
        random.rays.push_back(
            Ray{origin, sample_uniform_sphere(Vec2(rng.uniform(), rng.uniform()))});
    }
    return {primary, shadow, diffuse, random};
}

// ---- Timing: trace every ray of a set on `threads` threads; returns Mrays/s ----

struct Trace {
    double mrays = 0.0;
    size_t hits = 0;
};

// One pass over the set.
Trace trace_once(const std::vector<Ray>& rays, int threads,
                 const std::function<size_t(size_t, size_t)>& trace_range) {
    std::vector<size_t> hits(threads, 0);
    const auto start = Clock::now();
    std::vector<std::thread> pool;
    const size_t chunk = (rays.size() + threads - 1) / threads;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            const size_t begin = std::min(rays.size(), t * chunk);
            const size_t end = std::min(rays.size(), begin + chunk);
            hits[t] = trace_range(begin, end);
        });
    for (std::thread& th : pool) th.join();
    Trace trace{rays.size() / seconds_since(start) * 1e-6, 0};
    for (size_t h : hits) trace.hits += h;
    return trace;
}

// Each figure is the best of this many passes; ours and Embree's passes alternate (ours first,
// then Embree's first, ...), so that the machine's drift (10-25% from minute to minute here)
// falls on both alike.
constexpr int kPasses = 3;

void keep_best(Trace& best, const Trace& pass) {
    if (pass.mrays > best.mrays) best = pass;
}

#ifdef LESSONS_HAVE_EMBREE
// ---- Embree 3: the same triangles, default build (robust with --embree-robust),
// rtcIntersect1 / rtcOccluded1 ----

std::atomic<ssize_t> g_embree_bytes{0};  // Embree's threads report here

bool embree_memory_monitor(void*, ssize_t bytes, bool) {
    g_embree_bytes += bytes;
    return true;
}

// Our ray as Embree's: the same origin, direction and (0, t_max) interval.
RTCRay embree_ray(const Ray& r) {
    RTCRay ray;
    ray.org_x = r.origin.x, ray.org_y = r.origin.y, ray.org_z = r.origin.z;
    ray.dir_x = r.dir.x, ray.dir_y = r.dir.y, ray.dir_z = r.dir.z;
    ray.tnear = 0.0f;
    ray.tfar = r.t_max;
    ray.time = 0.0f;
    ray.mask = ~0u;
    ray.id = 0;
    ray.flags = 0;
    return ray;
}

struct EmbreeScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    double build_ms = 0.0;
    double bytes = 0.0;

    EmbreeScene(const TriangleMesh& mesh, int build_threads, bool robust) {
        const std::string config = "threads=" + std::to_string(build_threads);
        device = rtcNewDevice(config.c_str());
        rtcSetDeviceMemoryMonitorFunction(device, embree_memory_monitor, nullptr);
        g_embree_bytes = 0;
        scene = rtcNewScene(device);
        if (robust) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                              RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                              mesh.positions.size()));
        for (size_t i = 0; i < mesh.positions.size(); ++i)
            for (int k = 0; k < 3; ++k) v[3 * i + k] = mesh.positions[i][k];
        auto* idx = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(unsigned), mesh.triangles.size()));
        for (size_t i = 0; i < mesh.triangles.size(); ++i)
            for (int k = 0; k < 3; ++k) idx[3 * i + k] = mesh.triangles[i].v[k];
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(scene, geometry);
        rtcReleaseGeometry(geometry);
        const auto start = Clock::now();
        rtcCommitScene(scene);
        build_ms = seconds_since(start) * 1e3;
        bytes = static_cast<double>(g_embree_bytes.load());  // geometry buffers and BVH
    }
    ~EmbreeScene() {
        rtcReleaseScene(scene);
        rtcReleaseDevice(device);
    }
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    size_t closest(const std::vector<Ray>& rays, size_t begin, size_t end) const {
        size_t hits = 0;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (size_t i = begin; i < end; ++i) {
            RTCRayHit rh;
            rh.ray = embree_ray(rays[i]);
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &context, &rh);
            hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
        return hits;
    }
    size_t any(const std::vector<Ray>& rays, size_t begin, size_t end) const {
        size_t hits = 0;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (size_t i = begin; i < end; ++i) {
            RTCRay ray = embree_ray(rays[i]);
            rtcOccluded1(scene, &context, &ray);
            hits += ray.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
        }
        return hits;
    }
};
#endif

// ---- Output: a table on stdout and, with --csv, one CSV row per measurement ----

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

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

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

// ---- --scaling: how cost grows with the triangle count ----

// A number in a row's note after `key` (e.g. "ours 104.2 B/tri": key "ours "), or NaN.
double note_number(const std::string& note, const std::string& key) {
    const size_t at = note.find(key);
    return at == std::string::npos ? std::nan("") : std::atof(note.c_str() + at + key.size());
}

struct ScalingPoint {
    double triangles = 0, ours_ms = 0, embree_ms = NAN, ours_bytes = 0, embree_bytes = NAN,
           ours_mrays = 0, embree_mrays = NAN;
    double ours_all_ms = NAN, embree_all_ms = NAN;  // the build on every thread
};

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

void report_scaling(const std::vector<Row>& rows, int threads) {
    const std::vector<ScalingPoint> points = scaling_points(rows, threads);
    std::printf("\nHow cost grows (log-log least-squares slopes over %zu sizes; random rays on %d "
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
    line("closest-hit Mrays/s ~ triangles^", &ScalingPoint::ours_mrays, &ScalingPoint::embree_mrays);
}

void write_scaling_csv(const std::string& path, const std::vector<Row>& rows, int threads) {
    std::ofstream out(path);
    out << "triangles,ours_build_ms,embree_build_ms,ours_bytes,embree_bytes,ours_mrays,"
           "embree_mrays,ours_build_all_threads_ms,embree_build_all_threads_ms\n";
    const auto value = [](double v) { return std::isnan(v) ? std::string() : fixed(v, 3); };
    for (const ScalingPoint& p : scaling_points(rows, threads))
        out << fixed(p.triangles, 0) << ',' << value(p.ours_ms) << ',' << value(p.embree_ms)
            << ',' << value(p.ours_bytes) << ',' << value(p.embree_bytes) << ','
            << value(p.ours_mrays) << ',' << value(p.embree_mrays) << ','
            << value(p.ours_all_ms) << ',' << value(p.embree_all_ms) << '\n';
    std::cout << "wrote " << path << "\n";
}

int run(int argc, char** argv) {
    bool quick = false;
    std::string csv;
    size_t ray_count = 0;
    std::vector<std::string> only_scenes, only_sets;
    std::string only_query;  // empty: both
    bool embree_robust = false;
    bool scaling = false;
    const char* usage =
        "usage: bench_bvh [--quick] [--csv FILE] [--rays N] [--scene NAME]... [--set NAME]...\n"
        "                 [--query closest|any] [--embree-robust] [--scaling]\n"
        "  --scaling: build time, memory and incoherent (random) closest-hit throughput at\n"
        "             10k, 100k, 1M and 10M triangles, ours and Embree's, with the log-log slopes\n"
        "             (--csv: one row per size)\n"
        "  --scene: cornell_box, sphere_10092, sphere_99372, sphere_1002252\n"
        "  --set:   primary, shadow, diffuse, random, build, render (lesson 4, Cornell box)\n"
        "  --query: closest or any (the ray sets' queries; default both)\n";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--quick") {
            quick = true;
        } else if (a == "--csv" && i + 1 < argc) {
            csv = argv[++i];
        } else if (a == "--rays" && i + 1 < argc) {
            char* end = nullptr;
            const char* text = argv[++i];
            ray_count = std::strtoul(text, &end, 10);
            if (*end != '\0' || ray_count == 0) {
                std::cerr << "bench_bvh: error: --rays: not a positive integer: '" << text << "'\n";
                return 2;
            }
        } else if (a == "--scene" && i + 1 < argc) {
            only_scenes.push_back(argv[++i]);
        } else if (a == "--set" && i + 1 < argc) {
            only_sets.push_back(argv[++i]);
        } else if (a == "--scaling") {
            scaling = true;
        } else if (a == "--embree-robust") {
            embree_robust = true;
        } else if (a == "--query" && i + 1 < argc && only_query.empty()) {
            only_query = argv[++i];
        } else {
            std::cerr << usage;
            return a == "--help" || a == "-h" ? 0 : 2;
        }
    }
    if (ray_count == 0) ray_count = quick ? 200000 : 1000000;
    std::vector<Row> rows;
    auto wanted = [](const std::vector<std::string>& only, const std::string& name) {
        return only.empty() || std::find(only.begin(), only.end(), name) != only.end();
    };
    const int all_threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<int> thread_counts = {1};
    if (all_threads > 1) thread_counts.push_back(all_threads);

    auto add = [&](Row r) {
        if (embree_robust && r.embree) r.note += ", embree robust";  // the CSV says so too
        print_row(r);
        rows.push_back(r);
    };

    // 10k, 100k, 1M triangles; --scaling adds 10M (12 x 913^2 = 10,002,828).
    std::vector<int> sphere_sides = {29, 91, 289};
    if (scaling) {
        if (!only_scenes.empty() || !only_sets.empty() || !only_query.empty() || quick) {
            std::cerr << "bench_bvh: error: --scaling takes its own scenes, sets and query\n";
            return 2;
        }
        sphere_sides.push_back(913);
        for (int n : sphere_sides) only_scenes.push_back("sphere_" + std::to_string(12 * n * n));
        only_sets = {"build", "random"};
        only_query = "closest";
    }
    for (const std::string& name : only_scenes) {
        bool known = name == "cornell_box";
        for (int n : sphere_sides) known |= name == "sphere_" + std::to_string(12 * n * n);
        if (!known) {
            std::cerr << "bench_bvh: error: --scene: no scene named '" << name << "'\n" << usage;
            return 2;
        }
    }
    for (const std::string& name : only_sets)
        if (name != "primary" && name != "shadow" && name != "diffuse" && name != "random" &&
            name != "build" && name != "render") {
            std::cerr << "bench_bvh: error: --set: nothing named '" << name << "'\n" << usage;
            return 2;
        }
    if (!only_query.empty() && only_query != "closest" && only_query != "any") {
        std::cerr << "bench_bvh: error: --query: nothing named '" << only_query << "'\n" << usage;
        return 2;
    }

    // Meshes are made only for the rows asked for: a build, or a ray set.
    const bool any_ray_set = wanted(only_sets, "primary") || wanted(only_sets, "shadow") ||
                             wanted(only_sets, "diffuse") || wanted(only_sets, "random");
    const bool mesh_rows = any_ray_set || wanted(only_sets, "build");
    if (!mesh_rows && !(wanted(only_scenes, "cornell_box") && wanted(only_sets, "render"))) {
        std::cerr << "bench_bvh: error: --scene and --set leave nothing to measure (render: only "
                     "with cornell_box)\n";
        return 2;
    }

#ifdef LESSONS_HAVE_EMBREE
    std::printf("Embree %s%s, ", RTC_VERSION_STRING, embree_robust ? " (robust)" : "");
#else
    if (embree_robust) {
        std::cerr << "bench_bvh: error: --embree-robust: Embree is not built in\n";
        return 2;
    }
    std::printf("Embree: not built in (install libembree-dev and re-run cmake), ");
#endif
    std::printf("%d hardware threads, %zu rays per set%s\n\n", all_threads, ray_count,
                quick ? " (--quick)" : "");
    std::printf("%-15s %9s %-8s %-8s %2s %10s %10s %6s  %s\n", "scene", "triangles", "rays",
                "query", "th", "ours", "embree", "ratio", "");
    std::vector<TriangleMesh> meshes;
    if (mesh_rows && wanted(only_scenes, "cornell_box"))
        meshes.push_back(
            cornell_box_mesh(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml"));
    for (int n : sphere_sides)
        if (mesh_rows && wanted(only_scenes, "sphere_" + std::to_string(12 * n * n)))
            meshes.push_back(displaced_sphere(n));

    // Build time and memory at every size, on 1 thread and on all (the value columns:
    // milliseconds; ratio = Embree's time over ours, so above 1 means ours builds faster).
    // Each time is the best of kPasses builds, ours and Embree's taken in turn, on 1 thread
    // then on all, in every pass.
    for (const TriangleMesh& mesh : meshes) {
        if (!wanted(only_sets, "build")) break;
        std::vector<double> ms(thread_counts.size(), kInfinity);
        double per_tri = 0.0, bvh_per_tri = 0.0;
#ifdef LESSONS_HAVE_EMBREE
        std::vector<double> embree_ms(thread_counts.size(), kInfinity);
        double embree_per_tri = 0.0;
#endif
        for (int pass = 0; pass < kPasses; ++pass)
            for (size_t k = 0; k < thread_counts.size(); ++k) {
                // Like Embree's, which is timed once its vertex and index buffers are filled.
                Scene scene = uncommitted_scene(mesh);
                const auto start = Clock::now();
                scene.commit(thread_counts[k]);
                ms[k] = std::min(ms[k], seconds_since(start) * 1e3);
                per_tri = static_cast<double>(scene.geometry_bytes()) / mesh.triangles.size();
                bvh_per_tri =
                    static_cast<double>(scene.bvh().memory_bytes()) / mesh.triangles.size();
#ifdef LESSONS_HAVE_EMBREE
                const EmbreeScene e(mesh, thread_counts[k], embree_robust);
                embree_ms[k] = std::min(embree_ms[k], e.build_ms);
                embree_per_tri = e.bytes / mesh.triangles.size();
#endif
            }
        for (size_t k = 0; k < thread_counts.size(); ++k) {
            Row r{mesh.name,
                  mesh.triangles.size(),
                  "build",
                  "-",
                  thread_counts[k],
                  ms[k],
                  std::nullopt,
                  "ours " + fixed(per_tri, 1) + " B/tri (BVH " + fixed(bvh_per_tri, 1) + ")"};
#ifdef LESSONS_HAVE_EMBREE
            r.embree = embree_ms[k];
            r.note += ", embree " + fixed(embree_per_tri, 1) + " B/tri";
#endif
            add(r);
        }
    }

    // Ray throughput.
    // Every scene: the 10k mesh (about 1 MB with its BVH) stays in this machine's 2 MB L2
    // cache, so its ratios say how the arithmetic compares, apart from memory.
    for (const TriangleMesh& mesh : meshes) {
        if (!any_ray_set) break;
        const Scene scene = suite_scene(mesh);
        const std::vector<RaySet> sets = make_ray_sets(scene, mesh, ray_count);
#ifdef LESSONS_HAVE_EMBREE
        const EmbreeScene embree(mesh, all_threads, embree_robust);
#endif
        for (const RaySet& set : sets) {
            if (!wanted(only_sets, set.name)) continue;
            for (const std::string query : {"closest", "any"}) {
                if (!only_query.empty() && query != only_query) continue;
                for (int threads : thread_counts) {
                    const bool closest = query == "closest";
                    auto trace_ours = [&](size_t begin, size_t end) {
                        size_t hits = 0;
                        for (size_t i = begin; i < end; ++i)
                            hits += closest ? scene.intersect(set.rays[i]).has_value()
                                            : scene.occluded(set.rays[i]);
                        return hits;
                    };
                    Trace ours;
#ifdef LESSONS_HAVE_EMBREE
                    auto trace_embree = [&](size_t begin, size_t end) {
                        return closest ? embree.closest(set.rays, begin, end)
                                       : embree.any(set.rays, begin, end);
                    };
                    Trace theirs;
#endif
                    for (int pass = 0; pass < kPasses; ++pass) {
#ifdef LESSONS_HAVE_EMBREE
                        // Ours first in even passes, Embree's first in odd ones.
                        if (pass % 2 == 1)
                            keep_best(theirs, trace_once(set.rays, threads, trace_embree));
#endif
                        keep_best(ours, trace_once(set.rays, threads, trace_ours));
#ifdef LESSONS_HAVE_EMBREE
                        if (pass % 2 == 0)
                            keep_best(theirs, trace_once(set.rays, threads, trace_embree));
#endif
                    }
                    Row r{mesh.name,    mesh.triangles.size(),
                          set.name,     query,
                          threads,      ours.mrays,
                          std::nullopt, "hits ours " + std::to_string(ours.hits)};
#ifdef LESSONS_HAVE_EMBREE
                    r.embree = theirs.mrays;
                    r.note += ", embree " + std::to_string(theirs.hits);
#endif
                    add(r);
                }
            }
        }
    }

    // Lesson 4 on the Cornell box: samples and rays per second, 1 and all threads.
    if (wanted(only_scenes, "cornell_box") && wanted(only_sets, "render")) {
        const Scene scene =
            load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {256, 256});
        const LightSampler lights(scene);
        const Model model = make_path_tracing_model(scene, lights, {});
        // Best of kPasses renders per thread count, the counts taken in turn (1, all, all, 1,
        // ...), so that the scaling is not the machine's drift between two renders.
        const int spp = quick ? 8 : 32;
        std::vector<RenderStats> best(thread_counts.size());
        for (int pass = 0; pass < kPasses; ++pass)
            for (size_t k = 0; k < thread_counts.size(); ++k) {
                const size_t c = pass % 2 == 0 ? k : thread_counts.size() - 1 - k;
                RenderSettings settings;
                settings.progress = false;
                settings.threads = thread_counts[c];
                const RenderStats stats = render_scene(scene, model, spp, settings).stats;
                if (pass == 0 || stats.seconds < best[c].seconds) best[c] = stats;
            }
        double single = 0.0;
        for (size_t c = 0; c < thread_counts.size(); ++c) {
            const int threads = thread_counts[c];
            const RenderStats& stats = best[c];
            const double samples = 256.0 * 256.0 * spp / stats.seconds * 1e-6;
            if (threads == 1) single = samples;
            Row r{"cornell_box",
                  0,
                  "render",
                  "lesson4",
                  threads,
                  samples,
                  std::nullopt,
                  fixed(stats.rays / stats.seconds * 1e-6, 2) + " Mrays/s, " +
                      fixed(stats.seconds, 2) + " s for " + std::to_string(spp) +
                      " spp at 256x256 (best of " + std::to_string(kPasses) + ")"};
            if (threads > 1) r.note += ", scaling " + fixed(samples / single, 2) + "x";
            add(r);
        }
    }
    if (scaling) {
        report_scaling(rows, all_threads);
        if (!csv.empty()) write_scaling_csv(csv, rows, all_threads);
    } else if (!csv.empty()) {
        write_csv(csv, rows);
    }
    return 0;
}

}  // namespace
}  // namespace lessons

int main(int argc, char** argv) {
    return lessons::run(argc, argv);
}
