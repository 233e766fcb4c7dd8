// bench_bvh's measurements (see measure.h).
#include "measure.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <thread>

#include "04_rendering_equation/rendering_equation.h"
#include "io/scene_file.h"
#include "lights/lights.h"
#include "render/progressive.h"
#include "scene/scene.h"

#ifdef LESSONS_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace lessons::bench {

bool wanted(const std::vector<std::string>& only, const std::string& name) {
    return only.empty() || std::find(only.begin(), only.end(), name) != only.end();
}

bool wants_ray_sets(const Options& o) {
    return wanted(o.only_sets, "primary") || wanted(o.only_sets, "shadow") ||
           wanted(o.only_sets, "diffuse") || wanted(o.only_sets, "random");
}

bool wants_meshes(const Options& o) {
    return wants_ray_sets(o) || wanted(o.only_sets, "build");
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
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

// ---- Builds ----

// The best of kPasses builds of one mesh on each thread count, and the bytes per triangle.
struct BuildFigures {
    std::vector<double> ms;                   // ours, per thread count
    double per_tri = 0.0, bvh_per_tri = 0.0;  // the scene's geometry and BVH, its BVH alone
#ifdef LESSONS_HAVE_EMBREE
    std::vector<double> embree_ms;
    double embree_per_tri = 0.0;
#endif
};

// Ours and Embree's taken in turn, on 1 thread then on all, in every pass.
BuildFigures time_builds(const TriangleMesh& mesh, const std::vector<int>& thread_counts,
                         [[maybe_unused]] bool embree_robust) {
    BuildFigures f;
    f.ms.assign(thread_counts.size(), kInfinity);
#ifdef LESSONS_HAVE_EMBREE
    f.embree_ms.assign(thread_counts.size(), kInfinity);
#endif
    for (int pass = 0; pass < kPasses; ++pass)
        for (size_t k = 0; k < thread_counts.size(); ++k) {
            // Like Embree's, which is timed once its vertex and index buffers are filled.
            Scene scene = uncommitted_scene(mesh);
            const auto start = Clock::now();
            scene.commit(thread_counts[k]);
            f.ms[k] = std::min(f.ms[k], seconds_since(start) * 1e3);
            f.per_tri = static_cast<double>(scene.geometry_bytes()) / mesh.triangles.size();
            f.bvh_per_tri = static_cast<double>(scene.bvh().memory_bytes()) / mesh.triangles.size();
#ifdef LESSONS_HAVE_EMBREE
            const EmbreeScene e(mesh, thread_counts[k], embree_robust);
            f.embree_ms[k] = std::min(f.embree_ms[k], e.build_ms);
            f.embree_per_tri = e.bytes / mesh.triangles.size();
#endif
        }
    return f;
}

// ---- Ray throughput ----

// A mesh as our scene and as Embree's: the same triangles.
struct TracedMesh {
    const TriangleMesh& mesh;
    const Scene& scene;
#ifdef LESSONS_HAVE_EMBREE
    const EmbreeScene& embree;
#endif
};

// A set's rays traced with one query on `threads` threads: the best of kPasses, ours and
// Embree's alternating.
Row ray_row(const TracedMesh& m, const RaySet& set, const std::string& query, int threads) {
    const Scene& scene = m.scene;
    const bool closest = query == "closest";
    auto trace_ours = [&](size_t begin, size_t end) {
        size_t hits = 0;
        for (size_t i = begin; i < end; ++i)
            hits +=
                closest ? scene.intersect(set.rays[i]).has_value() : scene.occluded(set.rays[i]);
        return hits;
    };
    Trace ours;
#ifdef LESSONS_HAVE_EMBREE
    const EmbreeScene& embree = m.embree;
    auto trace_embree = [&](size_t begin, size_t end) {
        return closest ? embree.closest(set.rays, begin, end) : embree.any(set.rays, begin, end);
    };
    Trace theirs;
#endif
    for (int pass = 0; pass < kPasses; ++pass) {
#ifdef LESSONS_HAVE_EMBREE
        // Ours first in even passes, Embree's first in odd ones.
        if (pass % 2 == 1) keep_best(theirs, trace_once(set.rays, threads, trace_embree));
#endif
        keep_best(ours, trace_once(set.rays, threads, trace_ours));
#ifdef LESSONS_HAVE_EMBREE
        if (pass % 2 == 0) keep_best(theirs, trace_once(set.rays, threads, trace_embree));
#endif
    }
    Row r{m.mesh.name,  m.mesh.triangles.size(),
          set.name,     query,
          threads,      ours.mrays,
          std::nullopt, "hits ours " + std::to_string(ours.hits)};
#ifdef LESSONS_HAVE_EMBREE
    r.embree = theirs.mrays;
    r.note += ", embree " + std::to_string(theirs.hits);
#endif
    return r;
}

// ---- Lesson 4 ----

// Best of kPasses renders per thread count, the counts taken in turn (1, all, all, 1, ...), so
// that the scaling is not the machine's drift between two renders.
std::vector<RenderStats> best_renders(const Scene& scene, const Model& model, int spp,
                                      const std::vector<int>& thread_counts) {
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
    return best;
}

}  // namespace

// Build time and memory at every size, on 1 thread and on all (the value columns: milliseconds;
// ratio = Embree's time over ours, so above 1 means ours builds faster).
void measure_builds(const std::vector<TriangleMesh>& meshes, const Options& o,
                    const std::vector<int>& thread_counts, Table& table) {
    for (const TriangleMesh& mesh : meshes) {
        if (!wanted(o.only_sets, "build")) break;
        const BuildFigures f = time_builds(mesh, thread_counts, o.embree_robust);
        for (size_t k = 0; k < thread_counts.size(); ++k) {
            Row r{mesh.name,
                  mesh.triangles.size(),
                  "build",
                  "-",
                  thread_counts[k],
                  f.ms[k],
                  std::nullopt,
                  "ours " + fixed(f.per_tri, 1) + " B/tri (BVH " + fixed(f.bvh_per_tri, 1) + ")"};
#ifdef LESSONS_HAVE_EMBREE
            r.embree = f.embree_ms[k];
            r.note += ", embree " + fixed(f.embree_per_tri, 1) + " B/tri";
#endif
            table.add(r);
        }
    }
}

// Every scene: the 10k mesh (about 1 MB with its BVH) stays in this machine's 2 MB L2 cache, so
// its ratios say how the arithmetic compares, apart from memory.
void measure_ray_sets(const std::vector<TriangleMesh>& meshes, const Options& o,
                      const std::vector<int>& thread_counts, [[maybe_unused]] int all_threads,
                      Table& table) {
    const bool any_ray_set = wants_ray_sets(o);
    for (const TriangleMesh& mesh : meshes) {
        if (!any_ray_set) break;
        const Scene scene = suite_scene(mesh);
        const std::vector<RaySet> sets = make_ray_sets(scene, mesh, o.ray_count);
#ifdef LESSONS_HAVE_EMBREE
        const EmbreeScene embree(mesh, all_threads, o.embree_robust);
        const TracedMesh traced{mesh, scene, embree};
#else
        const TracedMesh traced{mesh, scene};
#endif
        for (const RaySet& set : sets) {
            if (!wanted(o.only_sets, set.name)) continue;
            for (const std::string query : {"closest", "any"}) {
                if (!o.only_query.empty() && query != o.only_query) continue;
                for (int threads : thread_counts) table.add(ray_row(traced, set, query, threads));
            }
        }
    }
}

void measure_render(const Options& o, const std::vector<int>& thread_counts, Table& table) {
    if (!(wanted(o.only_scenes, "cornell_box") && wanted(o.only_sets, "render"))) return;
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {256, 256});
    const PathTracingModel model(scene, {});
    const int spp = o.quick ? 8 : 32;
    const std::vector<RenderStats> best = best_renders(scene, model, spp, thread_counts);
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
              fixed(stats.rays / stats.seconds * 1e-6, 2) + " Mrays/s, " + fixed(stats.seconds, 2) +
                  " s for " + std::to_string(spp) + " spp at 256x256 (best of " +
                  std::to_string(kPasses) + ")"};
        if (threads > 1) r.note += ", scaling " + fixed(samples / single, 2) + "x";
        table.add(r);
    }
}

}  // namespace lessons::bench
