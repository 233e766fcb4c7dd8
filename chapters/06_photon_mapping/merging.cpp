// Lesson 6, section 7: merging (vcm; see photon_mapping.h). Lesson 5 joins the camera subpath's
// vertex z_{t-1} to a light subpath's y_{s-1} by a segment; merging takes a photon, the light
// subpath's vertex y_s, that landed within r of z_{t-1}, as if both were one vertex x_s. The
// path x_0 .. x_s .. x_{n-1} (y_0 .. y_{s-1}, then z_{t-1} .. z_0; n = s + t) carries
//   beta_L(y_s) f(z_{t-1}) beta_C(z_{t-1}) K(|y_s - z_{t-1}|) / N
// (the radiance estimate of density.h at z_{t-1}, for this photon), weighted by MIS against
// every join and every other merge that could make the same path (merge_weight,
// merge_weights.h, with eta = N pi r^2: a merge is N times likelier than a join where the light
// subpath's density of landing in the disk, p_L(x_s) pi r^2, is high).
#include <algorithm>
#include <cfloat>
#include <cmath>

#include "06_photon_mapping/density.h"
#include "06_photon_mapping/merge_weights.h"
#include "06_photon_mapping/photon_mapping.h"
#include "accel/parallel.h"

namespace lessons {

void store_light_side(Photon& photon, const MergeLightSide& side) {
    // A float holds each term's root; one too large for it is as good as infinite, but must
    // stay finite so that a density of 0 still cancels it.
    auto root = [](double v) {
        const double r = std::sqrt(v);
        return static_cast<float>(r < double{FLT_MAX} ? r : double{FLT_MAX});  // inf, NaN: max
    };
    photon.merge_reverse_root = root(side.per_reverse2);
    photon.merge_own_root = root(side.own_join);
}

MergeLightSide light_side_of(const Photon& photon) {
    const double r = photon.merge_reverse_root, o = photon.merge_own_root;
    return {true, r * r, o * o};
}

float merge_weight(const Photon& p, const MergeCameraSide& camera, const Bsdf& bsdf) {
    const Vec3& to_camera = camera.towards_camera;
    return merge_weight(light_side_of(p), camera, bsdf.pdf_seen_from(to_camera, p.wi),
                        bsdf.pdf_seen_from(p.wi, to_camera));
}

void weigh_photons(const Bidir& b, LightPaths& paths, double eta, int threads) {
    std::vector<uint8_t> keep(paths.photons.size(), 0);
    parallel_parts(paths.photons.size(), threads, 1024, [&](size_t begin, size_t end, int) {
        for (size_t i = begin; i < end; ++i) {
            Photon& p = paths.photons[i];
            const std::span<const Vertex> path = paths.subpath(p.path);
            const MergeLightSide side =
                merge_light_side(b, path.first(p.vertex), path[p.vertex], eta);
            store_light_side(p, side);
            keep[i] = side.possible;
        }
    });
    size_t kept = 0;  // in order: the photons no merge can use are left out
    for (size_t i = 0; i < paths.photons.size(); ++i)
        if (keep[i]) paths.photons[kept++] = paths.photons[i];
    paths.photons.resize(kept);
}

Color merges(const PhotonPass& pass, std::span<const Vertex> camera, const PhotonOptions& options) {
    const int longest = longest_path(options.paths.max_depth);
    const int N = std::max(pass.paths.count, 1);
    const double eta = static_cast<double>(N) * kPi * pass.radius * pass.radius;
    Color L(0.0f);
    for (int t = 2; t <= static_cast<int>(camera.size()); ++t) {
        const Vertex& z = camera[t - 1];
        if (z.type != VertexType::Surface || !z.connectible() || z.bsdf->is_delta()) continue;
        const MergeCameraSide side = merge_camera_side(camera, t, eta);  // once per vertex
        if (!side.possible()) continue;
        Color sum(0.0f);
        pass.grid.for_each_within(z.p, [&](const Photon& p) {
            if (static_cast<int>(p.vertex) + t - 1 > longest) return;
            const std::optional<Color> term =
                photon_term(p, z.si, *z.bsdf, z.si.wo, options.kernel, pass.radius);
            if (!term || is_black(*term)) return;
            sum += merge_weight(p, side, *z.bsdf) * *term;
        });
        L += z.beta * sum;
    }
    return L / static_cast<float>(N);
}

}  // namespace lessons
