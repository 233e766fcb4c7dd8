// Lesson 6, section 3: the light subpaths of one iteration and their photons (see photons.h).
#include "photons.h"

#include "accel/parallel.h"
#include "sampling/rng.h"

namespace lessons {

size_t LightPaths::bytes() const {
    return vertices.capacity() * sizeof(Vertex) + start.capacity() * sizeof(uint32_t) +
           photons.capacity() * sizeof(Photon);
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

LightPaths trace_photons(const Bidir& b, uint64_t seed, int iteration, int count, int max_vertices,
                         int roulette_after, int threads, bool keep_vertices) {
    const size_t n = count > 0 ? static_cast<size_t>(count) : 0;
    // One part per thread, each a contiguous range of subpaths with arrays of its own.
    std::vector<LightPaths> parts(static_cast<size_t>(part_count(n, threads, 256)));
    parallel_parts(n, threads, 256, [&](size_t begin, size_t end, int part) {
        LightPaths& out = parts[static_cast<size_t>(part)];
        const uint64_t rays_before = rays_traced_by_this_thread();
        std::vector<Vertex> path;
        for (size_t j = begin; j < end; ++j) {
            Rng rng(seed ^ kPhotonSeed, static_cast<uint64_t>(iteration), j);
            light_subpath(b, rng, max_vertices, roulette_after, path);
            out.start.push_back(static_cast<uint32_t>(out.vertices.size()));
            for (size_t i = 1; i < path.size(); ++i)
                if (leaves_photon(path[i]))
                    out.photons.push_back(
                        photon_at(path[i], static_cast<uint32_t>(j), static_cast<uint32_t>(i)));
            if (keep_vertices) out.vertices.insert(out.vertices.end(), path.begin(), path.end());
        }
        out.rays = rays_traced_by_this_thread() - rays_before;
    });

    // The parts in order: subpath j's vertices start where the parts before it ended.
    LightPaths all;
    all.count = static_cast<int>(n);
    size_t vertices = 0, photons = 0;
    for (const LightPaths& part : parts) {
        all.rays += part.rays;
        vertices += part.vertices.size();
        photons += part.photons.size();
    }
    all.vertices.reserve(vertices);
    all.photons.reserve(photons);
    all.start.reserve(n + 1);
    for (LightPaths& part : parts) {
        const uint32_t offset = static_cast<uint32_t>(all.vertices.size());
        for (const uint32_t s : part.start) all.start.push_back(offset + s);
        all.vertices.insert(all.vertices.end(), part.vertices.begin(), part.vertices.end());
        all.photons.insert(all.photons.end(), part.photons.begin(), part.photons.end());
        part = LightPaths{};  // its memory back before the next part is copied
    }
    all.start.push_back(static_cast<uint32_t>(all.vertices.size()));
    return all;
}

}  // namespace lessons
