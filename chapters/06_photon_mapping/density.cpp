// Lesson 6, section 4: the photons' radiance estimate (see density.h).
#include "06_photon_mapping/density.h"

#include <cmath>

namespace lessons {

bool photon_on_same_side(const Photon& p, const Vec3& n_geo, const Vec3& wo) {
    // Each normal turned to the side its light (or view) arrives from.
    const Vec3 lit_side = glm::dot(p.n, p.wi) >= 0.0f ? p.n : -p.n;
    const Vec3 seen_side = glm::dot(n_geo, wo) >= 0.0f ? n_geo : -n_geo;
    return glm::dot(lit_side, seen_side) > 0.0f;
}

std::optional<Color> photon_term(const Photon& p, const SurfaceInteraction& si, const Bsdf& bsdf,
                                 const Vec3& wo, Kernel kernel, float radius) {
    if (!photon_on_same_side(p, si.n_geo, wo)) return std::nullopt;
    const Vec3 d = p.p - si.p;
    const float K = kernel_weight(kernel, glm::dot(d, d), radius);
    if (!(K > 0.0f)) return std::nullopt;
    // |wi . n_s| / |wi . n_p|: the camera side's shading cosine over the cosine the photon's
    // density holds, at its own surface (its geometric normal n_p). On a smooth-shaded mesh a
    // photon from a neighbouring facet can arrive nearly tangent to x's facet: x's n_g would
    // give it an unbounded weight.
    const float cos_geo = std::fabs(glm::dot(p.wi, p.n));
    const float shading = cos_geo > 0.0f ? bsdf.abs_cos(p.wi) / cos_geo : 0.0f;
    // K(|y_p - x|) f(wo, wi_p) beta_p: one photon's term of the estimate.
    return K * shading * bsdf.eval(wo, p.wi) * p.beta;
}

RadianceEstimate reflected_radiance(const PhotonGrid& grid, const SurfaceInteraction& si,
                                    const Bsdf& bsdf, const Vec3& wo, Kernel kernel,
                                    int light_paths, uint32_t min_vertex, uint32_t max_vertex) {
    RadianceEstimate estimate;
    if (light_paths <= 0 || bsdf.is_delta()) return estimate;  // a mirror gathers no photons
    Color sum(0.0f);
    grid.for_each_within(si.p, [&](const Photon& p) {
        if (p.vertex < min_vertex || p.vertex > max_vertex) return;
        if (const std::optional<Color> term = photon_term(p, si, bsdf, wo, kernel, grid.radius())) {
            sum += *term;
            ++estimate.photons;
        }
    });
    estimate.L = sum / static_cast<float>(light_paths);
    return estimate;
}

}  // namespace lessons
