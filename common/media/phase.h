// Phase functions: how a medium scatters light at a point, the volume's counterpart of a BSDF.
//
// p(wo, wi) is a density over the sphere of directions (per steradian), integrating to 1 over wi.
// The conventions are the BSDFs' (materials/bsdf.h): wo and wi both point away from the
// scattering point, wo towards the viewer, wi towards where the light comes from. Light arrives
// travelling along -wi and leaves along wo, so the angle it turns through, theta, has
// cos(theta) = dot(-wi, wo) = -dot(wo, wi): forward scattering (light going on as it came) is
// wi = -wo, cos(theta) = 1. (Writing the phase function of dot(wo, wi) with the textbook formula,
// which is of the turning angle, swaps forward and back: a classic bug, tested.)
//
// Henyey and Greenstein (1941): p = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos(theta))^(3/2)), g in
// (-1, 1) the mean cosine of theta: g > 0 forward (fog, clouds, milk), g < 0 back, 0 isotropic.
// Sampling inverts its cumulative distribution in cos(theta) (no rejection): its density is the
// phase function's to float precision.
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/math.h"

namespace lessons {

// The Henyey-Greenstein density of turning through an angle of cosine cos_theta, per steradian.
inline float henyey_greenstein(float cos_theta, float g) {
    const float denominator = 1.0f + g * g - 2.0f * g * cos_theta;
    return (1.0f - g * g) / (4.0f * kPi * denominator * std::sqrt(denominator));
}

// The cosine of the turning angle, distributed as henyey_greenstein(., g), from a uniform u.
// Its cumulative distribution solved for cos(theta):
// cos = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2) / (2 g), in double: the numerator loses
// about 1e-16 / |g| to cancellation. Below |g| = 1e-7 the density differs from isotropic by less
// than a float resolves, and cos = 2 u - 1.
inline float sample_henyey_greenstein_cos(float u, float g) {
    if (std::abs(g) < 1e-7f) return std::clamp(2.0f * u - 1.0f, -1.0f, 1.0f);
    const double gd = g, s = (1.0 - gd * gd) / (1.0 - gd + 2.0 * gd * u);
    return static_cast<float>(std::clamp((1.0 + gd * gd - s * s) / (2.0 * gd), -1.0, 1.0));
}

struct PhaseSample {
    Vec3 wi;           // towards where the light comes from
    float p = 0.0f;    // p(wo, wi)
    float pdf = 0.0f;  // per steradian: p itself (the sampling follows p), kept apart so that
                       // an estimator reads p * L / pdf as it does f * cos * L / pdf
};

// A Henyey-Greenstein phase function of asymmetry g.
class HenyeyGreenstein {
public:
    explicit HenyeyGreenstein(float g) : g_(g) {}
    float g() const { return g_; }
    // p(wo, wi), both unit and pointing away from the scattering point.
    float eval(const Vec3& wo, const Vec3& wi) const {
        return henyey_greenstein(-glm::dot(wo, wi), g_);
    }
    float pdf(const Vec3& wo, const Vec3& wi) const { return eval(wo, wi); }
    // wi distributed as p(wo, .), from two uniform numbers: the light's old direction of travel,
    // -wi, makes the sampled turning angle with its new one, wo.
    PhaseSample sample(const Vec3& wo, const Vec2& u) const {
        const float cos_theta = sample_henyey_greenstein_cos(u.x, g_);
        const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
        const float phi = 2.0f * kPi * u.y;
        const Vec3 local(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
        const Vec3 travel_before = Frame(wo).to_world(local);
        PhaseSample s;
        s.wi = -travel_before;
        s.p = s.pdf = henyey_greenstein(cos_theta, g_);
        return s;
    }

private:
    float g_;
};

}  // namespace lessons
