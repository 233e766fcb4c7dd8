// The BSDF lobes of lessons 3 to 5 (see bsdf.h for the contract every one of them keeps).
#include "materials/bsdf.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "geometry/interaction.h"
#include "materials/microfacet.h"
#include "materials/optics.h"
#include "sampling/sampling.h"

namespace lessons {

float blinn_phong_normalization(float e) {
    return (e + 2.0f) * (e + 4.0f) / (8.0f * kPi * (std::exp2(-0.5f * e) + e));
}

float blinn_phong_exponent(float roughness) {
    return std::max(2.0f / (roughness * roughness) - 2.0f, 0.0f);
}

Color blinn_phong_brdf(const Color& k_d, const Color& k_s, float exponent, const Vec3& n,
                       const Vec3& wo, const Vec3& wi) {
    Color f = k_d * kInvPi;
    if (!is_black(k_s)) {
        const Vec3 h = glm::normalize(wi + wo);
        const float cos_h = std::max(glm::dot(n, h), 0.0f);
        f += k_s * (blinn_phong_normalization(exponent) * std::pow(cos_h, exponent));
    }
    return f;
}

namespace {

constexpr float kMinAlpha = 1e-3f;  // below this, GGX peaks beyond float range: use a mirror

// ---- Lambertian: f = albedo / pi, sampled by cosine: f cos / pdf = albedo. ----
Color eval(const Lambertian& l, const Vec3& wo, const Vec3& wi) {
    return (wo.z > 0.0f && wi.z > 0.0f) ? l.albedo * kInvPi : Color(0.0f);
}
float pdf(const Lambertian&, const Vec3& wo, const Vec3& wi) {
    return wo.z > 0.0f ? cosine_hemisphere_pdf(wi.z) : 0.0f;
}
std::optional<BsdfSample> sample(const Lambertian& l, const Vec3& wo, const Vec2& u) {
    if (wo.z <= 0.0f) return std::nullopt;
    const Vec3 wi = sample_cosine_hemisphere(u);
    if (wi.z <= 0.0f) return std::nullopt;  // the disk's rim: measure zero, but never divide by 0
    return BsdfSample{wi, eval(l, wo, wi), pdf(l, wo, wi), false};
}

// ---- Glossy: Lambert + normalised Blinn-Phong. The lobe is sampled through its half vector,
// h ~ (e + 1) / (2 pi) (n.h)^e, wi = reflect(wo, h); the Jacobian of h -> wi is 1 / (4 wo.h).
// One of the two lobes is chosen in proportion to its reflectance. ----
float specular_probability(const GlossyBlinnPhong& g) {
    const float d = luminance(g.k_d), s = luminance(g.k_s);
    return d + s > 0.0f ? s / (d + s) : 0.0f;
}
Color eval(const GlossyBlinnPhong& g, const Vec3& wo, const Vec3& wi) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Color(0.0f);
    return blinn_phong_brdf(g.k_d, g.k_s, g.exponent, Vec3(0, 0, 1), wo, wi);
}
float lobe_pdf(const GlossyBlinnPhong& g, const Vec3& wo, const Vec3& wi) {
    const Vec3 h = glm::normalize(wo + wi);
    const float wo_h = glm::dot(wo, h);
    if (h.z <= 0.0f || wo_h <= 0.0f) return 0.0f;
    const float pdf_h = (g.exponent + 1.0f) / (2.0f * kPi) * std::pow(h.z, g.exponent);
    return pdf_h / (4.0f * wo_h);
}
float pdf(const GlossyBlinnPhong& g, const Vec3& wo, const Vec3& wi) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    const float q = specular_probability(g);
    return q * lobe_pdf(g, wo, wi) + (1.0f - q) * cosine_hemisphere_pdf(wi.z);
}
std::optional<BsdfSample> sample(const GlossyBlinnPhong& g, const Vec3& wo, Vec2 u) {
    if (wo.z <= 0.0f || (is_black(g.k_d) && is_black(g.k_s))) return std::nullopt;
    const float q = specular_probability(g);
    Vec3 wi;
    if (u.x < q) {
        u.x = std::min(u.x / q, 0x1.fffffep-1f);  // reuse u.x, rescaled to [0, 1)
        const float cos_h = std::pow(1.0f - u.x, 1.0f / (g.exponent + 1.0f));
        const float sin_h = std::sqrt(std::max(0.0f, 1.0f - cos_h * cos_h));
        const float phi = 2.0f * kPi * u.y;
        const Vec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
        wi = reflect(wo, h);
    } else {
        u.x = std::min((u.x - q) / (1.0f - q), 0x1.fffffep-1f);
        wi = sample_cosine_hemisphere(u);
    }
    if (wi.z <= 0.0f) return std::nullopt;  // reflected below the horizon: no sample
    const float p = pdf(g, wo, wi);
    if (!(p > 0.0f)) return std::nullopt;
    return BsdfSample{wi, eval(g, wo, wi), p, false};
}

// ---- GGX conductor: f = D(h) G2(wo, wi) F(wo.h) / (4 cos_o cos_i), sampled by visible
// normals: pdf(wi) = D_wo(h) / (4 wo.h) = G1(wo) D(h) / (4 cos_o). ----
Color schlick_conductor(const Color& f0, float cos) {
    const float m = std::clamp(1.0f - cos, 0.0f, 1.0f);
    return f0 + (Color(1.0f) - f0) * (m * m * m * m * m);
}
Color eval(const GgxConductor& c, const Vec3& wo, const Vec3& wi) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Color(0.0f);
    const Vec3 h = glm::normalize(wo + wi);
    const float alpha = std::max(c.alpha, kMinAlpha);
    return ggx_D(h, alpha) * ggx_G2(wo, wi, alpha) * schlick_conductor(c.f0, glm::dot(wo, h)) /
           (4.0f * wo.z * wi.z);
}
float pdf(const GgxConductor& c, const Vec3& wo, const Vec3& wi) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    const Vec3 h = glm::normalize(wo + wi);
    const float alpha = std::max(c.alpha, kMinAlpha);
    return ggx_G1(wo, alpha) * ggx_D(h, alpha) / (4.0f * wo.z);
}
std::optional<BsdfSample> sample(const GgxConductor& c, const Vec3& wo, const Vec2& u) {
    if (wo.z <= 0.0f) return std::nullopt;
    const Vec3 h = sample_ggx_visible_normal(wo, std::max(c.alpha, kMinAlpha), u);
    const Vec3 wi = reflect(wo, h);
    if (wi.z <= 0.0f) return std::nullopt;  // masked: shadowed by another microfacet
    const float p = pdf(c, wo, wi);
    if (!(p > 0.0f)) return std::nullopt;
    return BsdfSample{wi, eval(c, wo, wi), p, false};
}

// ---- Perfect mirror: all light into reflect(wo, n), weight R. ----
std::optional<BsdfSample> sample(const PerfectMirror& m, const Vec3& wo, const Vec2&) {
    if (wo.z <= 0.0f) return std::nullopt;
    const Vec3 wi(-wo.x, -wo.y, wo.z);
    return BsdfSample{wi, m.reflectance / wi.z, 1.0f, true};
}

// ---- Smooth dielectric: reflect with probability F (weight F), refract with probability
// 1 - F (weight (1 - F) / eta^2: radiance over n^2 is what crosses the interface; (1 - F) alone
// for importance, see Transport). ----
std::optional<BsdfSample> sample(const SmoothDielectric& d, const Vec3& wo, const Vec2& u,
                                 Transport transport) {
    if (wo.z == 0.0f) return std::nullopt;
    const bool entering = wo.z > 0.0f;
    const float eta = entering ? d.eta : 1.0f / d.eta;  // n on wi's side / n on wo's side
    const Vec3 n(0.0f, 0.0f, entering ? 1.0f : -1.0f);
    const float F = fresnel_dielectric(std::fabs(wo.z), eta);
    if (u.x < F) {
        const Vec3 wi(-wo.x, -wo.y, wo.z);
        return BsdfSample{wi, Color(F / std::fabs(wi.z)), F, true};
    }
    const std::optional<Vec3> wt = refract(wo, n, eta);
    if (!wt || wt->z == 0.0f) return std::nullopt;
    const float scale = transport == Transport::Radiance ? 1.0f / (eta * eta) : 1.0f;
    return BsdfSample{*wt, d.transmittance * ((1.0f - F) * scale / std::fabs(wt->z)), 1.0f - F,
                      true};
}

// Delta lobes have no density to evaluate: any given pair (wo, wi) has measure zero.
Color eval(const PerfectMirror&, const Vec3&, const Vec3&) {
    return Color(0.0f);
}
float pdf(const PerfectMirror&, const Vec3&, const Vec3&) {
    return 0.0f;
}
Color eval(const SmoothDielectric&, const Vec3&, const Vec3&) {
    return Color(0.0f);
}
float pdf(const SmoothDielectric&, const Vec3&, const Vec3&) {
    return 0.0f;
}

BsdfLobe lobe_of(const Material& m, const Vec2& uv) {
    switch (m.type) {
        case MaterialType::Diffuse: return Lambertian{m.albedo.eval(uv)};
        case MaterialType::Glossy:
            return GlossyBlinnPhong{m.albedo.eval(uv), m.specular,
                                    blinn_phong_exponent(m.roughness)};
        case MaterialType::Conductor: return GgxConductor{m.specular, m.roughness};
        case MaterialType::Mirror: return PerfectMirror{m.reflectance};
        case MaterialType::Glass: return SmoothDielectric{m.ior, m.transmittance};
    }
    return Lambertian{Color(0.0f)};
}

}  // namespace

Bsdf::Bsdf(const BsdfLobe& lobe, const Vec3& shading_normal, const Vec3& geometric_normal)
    : lobe_(lobe), frame_(shading_normal), n_geo_(geometric_normal) {}

Bsdf::Bsdf(const Material& material, const SurfaceInteraction& si)
    : lobe_(lobe_of(material, si.uv)), frame_(si.n_shading), n_geo_(si.n_geo) {
    const bool transmits = facts_of(material.type).transmits;
    if (!transmits && !si.front_face()) {
        frame_ = Frame(-si.n_shading);
        n_geo_ = -si.n_geo;
    }
    // An interpolated normal can tilt so far that the viewer is below its hemisphere (near the
    // silhouette of a coarse mesh); every lobe would then be black. Shade with the true surface.
    if (si.shading_fallback && !transmits) {
        n_interpolated_ = frame_.n;
        may_fall_back_ = true;
        if (glm::dot(si.wo, frame_.n) <= 0.0f) {
            frame_ = Frame(n_geo_);
            fell_back_ = true;
        }
    }
}

Bsdf Bsdf::seen_from(const Vec3& wo) const {
    const bool fall_back = may_fall_back_ && glm::dot(wo, n_interpolated_) <= 0.0f;
    if (fall_back == fell_back_) return *this;
    Bsdf b = *this;
    b.frame_ = Frame(fall_back ? n_geo_ : n_interpolated_);
    b.fell_back_ = fall_back;
    return b;
}

float Bsdf::pdf_seen_from(const Vec3& wo, const Vec3& wi) const {
    const bool fall_back = may_fall_back_ && glm::dot(wo, n_interpolated_) <= 0.0f;
    return fall_back == fell_back_ ? pdf(wo, wi) : seen_from(wo).pdf(wo, wi);
}

bool Bsdf::is_delta() const {
    return std::holds_alternative<PerfectMirror>(lobe_) ||
           std::holds_alternative<SmoothDielectric>(lobe_);
}

bool Bsdf::same_geometric_side(const Vec3& wo, const Vec3& wi) const {
    return glm::dot(wo, n_geo_) * glm::dot(wi, n_geo_) > 0.0f;
}

Color Bsdf::eval(const Vec3& wo, const Vec3& wi) const {
    if (!same_geometric_side(wo, wi)) return Color(0.0f);  // every non-delta lobe reflects
    const Vec3 lo = frame_.to_local(wo), li = frame_.to_local(wi);
    return std::visit([&](const auto& lobe) { return lessons::eval(lobe, lo, li); }, lobe_);
}

float Bsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    if (!same_geometric_side(wo, wi)) return 0.0f;
    const Vec3 lo = frame_.to_local(wo), li = frame_.to_local(wi);
    return std::visit([&](const auto& lobe) { return lessons::pdf(lobe, lo, li); }, lobe_);
}

std::optional<BsdfSample> Bsdf::sample(const Vec3& wo, const Vec2& u, Transport transport) const {
    const Vec3 lo = frame_.to_local(wo);
    std::optional<BsdfSample> s = std::visit(
        [&](const auto& lobe) {
            if constexpr (std::is_same_v<std::decay_t<decltype(lobe)>, SmoothDielectric>)
                return lessons::sample(lobe, lo, u, transport);
            else
                return lessons::sample(lobe, lo, u);
        },
        lobe_);
    if (!s) return std::nullopt;
    s->wi = glm::normalize(frame_.to_world(s->wi));
    // A reflected direction must stay on wo's geometric side, a refracted one must cross.
    const bool refracted = frame_.to_local(s->wi).z * lo.z < 0.0f;
    if (same_geometric_side(wo, s->wi) == refracted) return std::nullopt;
    if (!is_finite(s->f) || !std::isfinite(s->pdf)) return std::nullopt;
    return s;
}

}  // namespace lessons
