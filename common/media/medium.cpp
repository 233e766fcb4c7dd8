// Participating media (see medium.h).
#include "media/medium.h"

#include <cmath>

namespace lessons {

namespace {

// The probability of choosing each channel: in proportion to the weights (uniform if they are
// all 0 or not finite).
Color channel_probabilities(const Color& weights) {
    const Color w = glm::max(weights, Color(0.0f));
    const float sum = w.x + w.y + w.z;
    if (!(sum > 0.0f) || !std::isfinite(sum)) return Color(1.0f / 3.0f);
    return w / sum;
}

}  // namespace

Color Medium::albedo() const {
    const Color t = sigma_t();
    Color a(0.0f);
    for (int c = 0; c < 3; ++c)
        if (t[c] > 0.0f) a[c] = sigma_s[c] / t[c];
    return a;
}

Color Medium::transmittance(float distance) const {
    Color T(1.0f);
    const Color s = sigma_t();
    // sigma_t 0 over an infinite distance is no extinction at all (not 0 x inf = NaN).
    for (int c = 0; c < 3; ++c)
        if (s[c] > 0.0f) T[c] = std::exp(-s[c] * distance);
    return T;
}

float free_flight_pdf(const Medium& medium, float t, bool collided, const Color& channel_weights) {
    const Color P = channel_probabilities(channel_weights);
    const Color T = medium.transmittance(t);
    const Color s = medium.sigma_t();
    // Collided: sum_c P_c sigma_t,c T_c(t); passed: sum_c P_c T_c(t).
    return collided ? glm::dot(P, s * T) : glm::dot(P, T);
}

FreeFlight sample_free_flight(const Medium& medium, float t_max, float u_channel, float u_distance,
                              const Color& channel_weights) {
    const Color P = channel_probabilities(channel_weights);
    // The channel: the first whose running sum of probabilities exceeds u_channel; if rounding
    // leaves u_channel past them all, the last channel that can be chosen.
    int c = u_channel < P.x ? 0 : u_channel < P.x + P.y ? 1 : 2;
    while (c > 0 && !(P[c] > 0.0f)) --c;
    const float sigma = medium.sigma_t()[c];
    FreeFlight f;
    // Inverting 1 - exp(-sigma t) = u: t = -log(1 - u) / sigma (infinite where sigma is 0).
    const float t = sigma > 0.0f ? -std::log1p(-u_distance) / sigma : kInfinity;
    f.collided = t < t_max;
    f.t = f.collided ? t : t_max;
    f.transmittance = medium.transmittance(f.t);
    f.pdf = free_flight_pdf(medium, f.t, f.collided, channel_weights);
    return f;
}

}  // namespace lessons
