// BSDFs: how a surface scatters light, f(p, wo, wi), for lessons 3 to 5.
//
// The contract, which every estimator relies on:
//   eval(wo, wi)   returns f alone, without the cosine, in 1/sr;
//   pdf(wo, wi)    is the density of sample() producing wi, per unit solid angle;
//   sample(wo, u)  returns {wi, f, pdf, is_delta}, *not* divided by the pdf, so the estimator
//                  f cos(theta_i) / pdf stays visible where it is used; none if it fails.
// wo and wi are unit world-space directions pointing away from the surface.
//
// Delta BSDFs (mirror, smooth glass) scatter into single directions: eval and pdf are 0 for any
// given pair, and sample() returns pdf = the probability of the chosen direction (1 for a
// mirror, F or 1 - F for glass) with f = weight / |cos(theta_i)|, so that f cos / pdf is the
// weight: no estimator special-cases them beyond not combining them with light sampling.
//
// Every BRDF here is reciprocal, f(wo, wi) = f(wi, wo), and conserves energy: its directional
// albedo, the integral of f cos over the hemisphere, is at most 1 (tests/test_bsdf.cpp).
#pragma once

#include <optional>
#include <variant>

#include "geometry/math.h"
#include "materials/material.h"

namespace lessons {

struct SurfaceInteraction;

// What a path carries through a refraction. Radiance (paths from the camera): crossing into a
// denser medium packs the same light into a narrower cone, so radiance scales by
// (n_to / n_from)^2 and the sampled weight is (1 - F) / eta^2. Importance (paths from the lights,
// lesson 5) is the adjoint quantity: their throughput is flux-like and carries (1 - F) alone.
// Only smooth glass tells them apart; every reflection is reciprocal.
enum class Transport { Radiance, Importance };

struct BsdfSample {
    Vec3 wi;
    Color f;    // BSDF value (delta: weight / |cos|)
    float pdf;  // solid-angle density (delta: probability of this discrete choice)
    bool is_delta;
};

// The reflectance of the microfacet Blinn-Phong lobe is normalised exactly: at normal incidence
// (where it is largest) the lobe k_s N(e) (n.h)^e reflects exactly k_s, with
//   N(e) = (e + 2)(e + 4) / (8 pi (2^(-e/2) + e)).
// The common shortcut (e + 8) / (8 pi) reflects up to 6.7% more than it receives (e near 16).
float blinn_phong_normalization(float exponent);
// The lesson-1 exponent for a roughness alpha: e = 2 / alpha^2 - 2 (Walter et al. 2007).
float blinn_phong_exponent(float roughness);
// Lambert plus the normalised Blinn-Phong lobe, for unit n, wo, wi: the BRDF lessons 1 and 2
// evaluate at their point lights, and lessons 3 to 5 sample.
Color blinn_phong_brdf(const Color& k_d, const Color& k_s, float exponent, const Vec3& n,
                       const Vec3& wo, const Vec3& wi);

// ---- The lobes, in the local frame (normal +z); wo.z > 0 for the reflective ones. ----

struct Lambertian {
    Color albedo;  // f = albedo / pi
};

struct GlossyBlinnPhong {  // Lambert base + normalised Blinn-Phong lobe
    Color k_d, k_s;
    float exponent;
};

struct GgxConductor {  // f = D G2 F / (4 cos_o cos_i), F by Schlick with F0 = the metal's colour
    Color f0;
    float alpha;
};

struct PerfectMirror {
    Color reflectance;
};

struct SmoothDielectric {
    float eta;                  // n_inside / n_outside; the local +z side is outside
    Color transmittance{1.0f};  // kept of the light that crosses (a tint: coloured glass)
};

using BsdfLobe =
    std::variant<Lambertian, GlossyBlinnPhong, GgxConductor, PerfectMirror, SmoothDielectric>;

// A BSDF at one surface point: a lobe in the shading frame.
class Bsdf {
public:
    // The scattering of `material` at `si`. Opaque materials are shaded on the side the ray
    // arrived (two-sided); glass keeps its geometric orientation (front = outside).
    Bsdf(const Material& material, const SurfaceInteraction& si);
    Bsdf(const BsdfLobe& lobe, const Vec3& shading_normal, const Vec3& geometric_normal);

    Color eval(const Vec3& wo, const Vec3& wi) const;
    float pdf(const Vec3& wo, const Vec3& wi) const;
    std::optional<BsdfSample> sample(const Vec3& wo, const Vec2& u,
                                     Transport transport = Transport::Radiance) const;

    // The same BSDF as a viewer from wo sees it: the shading-normal fallback (below a tilted
    // interpolated normal, the surface's own) decided by wo rather than by the direction the
    // BSDF was made for. The scene's BSDF at a path vertex is the one seen from the camera's
    // side; lesson 5's light subpaths arrive from the other side and ask for it.
    Bsdf seen_from(const Vec3& wo) const;
    // seen_from(wo).pdf(wo, wi), the same bits, without a copy of the BSDF where wo sees the
    // one it was made for (the weights of lessons 5 and 6 ask for many).
    float pdf_seen_from(const Vec3& wo, const Vec3& wi) const;

    bool is_delta() const;
    // |cos(theta)| of a world direction against the shading normal.
    float abs_cos(const Vec3& w) const { return std::fabs(glm::dot(w, frame_.n)); }
    const Vec3& normal() const { return frame_.n; }

private:
    // Reflection needs wo and wi on the same side of the *geometric* surface, transmission on
    // opposite sides, whatever an interpolated shading normal says: no light through walls.
    bool same_geometric_side(const Vec3& wo, const Vec3& wi) const;

    BsdfLobe lobe_;
    Frame frame_;
    Vec3 n_geo_;
    Vec3 n_interpolated_{0.0f};  // the shading normal on the viewer's side (when it may fall back)
    bool may_fall_back_ = false, fell_back_ = false;
};

}  // namespace lessons
