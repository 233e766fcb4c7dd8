// Lesson 6, section 3: the light subpaths of one iteration and their photons (see photons.h).
#include "06_photon_mapping/photons.h"

#include <algorithm>

#include "accel/parallel.h"
#include "sampling/rng.h"

namespace lessons {

std::span<const Vertex> LightPaths::subpath(size_t j) const {
    for (const Part& part : parts)
        if (j >= part.first && j - part.first + 1 < part.start.size()) {
            const size_t i = j - part.first;
            return {part.vertices.data() + part.start[i], part.start[i + 1] - part.start[i]};
        }
    return {};
}

size_t LightPaths::bytes() const {
    size_t bytes = photons.size() * sizeof(Photon);
    if (parts.empty()) return bytes;
    // The subpaths' vertices and one offset each (and one past the last): as one array would
    // hold them, whatever the parts.
    for (const Part& part : parts) bytes += part.vertices.size() * sizeof(Vertex);
    return bytes + (static_cast<size_t>(std::max(count, 0)) + 1) * sizeof(uint32_t);
}

namespace {

// Whether light subpath vertex v (not y_0) leaves a photon: on a surface whose BSDF is not a
// delta (a mirror's or glass's photons could only be found by a camera path that arrives in
// the one reflected direction: with probability 0), carrying some light. The BSDF is asked,
// not Vertex::delta, which lesson 5 sets only where the walk scattered (not at the last vertex).
bool leaves_photon(const Vertex& v) {
    return v.type == VertexType::Surface && v.bsdf && !v.bsdf->is_delta() && !is_black(v.beta) &&
           is_finite(v.beta);
}

Photon photon_at(const Vertex& v, uint32_t path, uint32_t vertex) {
    Photon photon;
    photon.p = v.p;
    photon.wi = v.si.wo;  // towards y_{i-1}: where the light came from
    photon.beta = v.beta;
    photon.n = v.si.n_geo;
    photon.path = path;
    photon.vertex = vertex;
    return photon;
}

}  // namespace

void trace_photons(const Bidir& b, uint64_t seed, int iteration, int count, int max_vertices,
                   int roulette_after, int threads, bool keep_vertices, LightPaths& out) {
    const size_t n = count > 0 ? static_cast<size_t>(count) : 0;
    // One part per thread, each a contiguous range of subpaths with arrays of its own (the last
    // pass's, cleared: their memory is reused).
    const size_t part_total = static_cast<size_t>(part_count(n, threads, 256));
    out.parts.resize(part_total);
    std::vector<std::vector<Photon>> photons(part_total);
    std::vector<uint64_t> rays(part_total, 0);
    parallel_parts(n, threads, 256, [&](size_t begin, size_t end, int index) {
        LightPaths::Part& part = out.parts[static_cast<size_t>(index)];
        part.first = begin;
        part.vertices.clear();
        part.start.clear();
        std::vector<Photon>& own = photons[static_cast<size_t>(index)];
        const uint64_t rays_before = rays_traced_by_this_thread();
        std::vector<Vertex> path;
        for (size_t j = begin; j < end; ++j) {
            Rng rng(seed ^ kPhotonSeed, static_cast<uint64_t>(iteration), j);
            light_subpath(b, rng, max_vertices, roulette_after, path);
            for (size_t i = 1; i < path.size(); ++i)
                if (leaves_photon(path[i]))
                    own.push_back(
                        photon_at(path[i], static_cast<uint32_t>(j), static_cast<uint32_t>(i)));
            if (keep_vertices) {
                part.start.push_back(static_cast<uint32_t>(part.vertices.size()));
                part.vertices.insert(part.vertices.end(), path.begin(), path.end());
            }
        }
        if (keep_vertices) part.start.push_back(static_cast<uint32_t>(part.vertices.size()));
        rays[static_cast<size_t>(index)] = rays_traced_by_this_thread() - rays_before;
    });
    if (!keep_vertices) out.parts.clear();

    // The photons of the parts in order.
    out.count = static_cast<int>(n);
    out.rays = 0;
    out.photons.clear();
    size_t total = 0;
    for (const std::vector<Photon>& own : photons) total += own.size();
    out.photons.reserve(total);
    for (size_t k = 0; k < part_total; ++k) {
        out.rays += rays[k];
        out.photons.insert(out.photons.end(), photons[k].begin(), photons[k].end());
    }
}

LightPaths trace_photons(const Bidir& b, uint64_t seed, int iteration, int count, int max_vertices,
                         int roulette_after, int threads, bool keep_vertices) {
    LightPaths paths;
    trace_photons(b, seed, iteration, count, max_vertices, roulette_after, threads, keep_vertices,
                  paths);
    return paths;
}

}  // namespace lessons
