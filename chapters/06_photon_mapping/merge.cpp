// Lesson 6, section 7: merging (vcm; see photon_mapping.h). Lesson 5 joins the camera subpath's
// vertex z_{t-1} to a light subpath's y_{s-1} by a segment; merging takes a photon, the light
// subpath's vertex y_s, that landed within r of z_{t-1}, as if both were one vertex x_s. The
// path x_0 .. x_s .. x_{n-1} (y_0 .. y_{s-1}, then z_{t-1} .. z_0; n = s + t) carries
//   beta_L(y_s) f(z_{t-1}) beta_C(z_{t-1}) K(|y_s - z_{t-1}|) / N
// (the radiance estimate of density.h at z_{t-1}, for this photon), weighted by MIS against
// every join and every other merge that could make the same path (merge_weight, mis.h, with
// eta = N pi r^2: a merge is N times likelier than a join where the light subpath's density of
// landing in the disk, p_L(x_s) pi r^2, is high).
#include <cmath>

#include "density.h"
#include "mis.h"
#include "photon_mapping.h"

namespace lessons {

Color merges(const Bidir& b, const PhotonPass& pass, std::span<const Vertex> camera,
             const PhotonOptions& options) {
    const int longest = options.paths.max_depth > 0 ? options.paths.max_depth : kLongestPath;
    const int N = std::max(pass.paths.count, 1);
    const double eta = static_cast<double>(N) * kPi * pass.radius * pass.radius;
    Color L(0.0f);
    for (int t = 2; t <= static_cast<int>(camera.size()); ++t) {
        const Vertex& z = camera[t - 1];
        if (z.type != VertexType::Surface || !z.connectible() || z.bsdf->is_delta()) continue;
        Color sum(0.0f);
        pass.grid.for_each_within(z.p, [&](const Photon& p) {
            const int s = static_cast<int>(p.vertex);  // the light subpath's vertices before it
            if (s + t - 1 > longest) return;
            const std::optional<Color> term =
                photon_term(p, z.si, *z.bsdf, z.si.wo, options.kernel, pass.radius);
            if (!term || is_black(*term)) return;
            const std::span<const Vertex> light(&pass.paths.vertices[pass.paths.start[p.path]],
                                                static_cast<size_t>(s));
            const float w = merge_weight(b, light, s, pass.paths.vertex_of(p), camera, t, eta);
            sum += w * *term;
        });
        L += z.beta * sum;
    }
    return L / static_cast<float>(N);
}

}  // namespace lessons
