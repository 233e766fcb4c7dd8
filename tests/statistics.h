// Statistical tests for samplers and estimators (docs/accuracy.md): the chi-square goodness-of-fit
// test of a sampling routine against its density, and the z-test of a mean.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/math.h"

namespace lessons::test {

// Regularised upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a): by its series
// for x < a + 1, by its continued fraction (modified Lentz) otherwise.
inline double gamma_q(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double log_prefactor = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 10000 && std::fabs(term) > std::fabs(sum) * 1e-15; ++n) {
            term *= x / (a + n);
            sum += term;
        }
        return 1.0 - sum * std::exp(log_prefactor);
    }
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::fabs(delta - 1.0) < 1e-15) break;
    }
    return std::exp(log_prefactor) * h;
}

// p-value of a chi-square statistic with `dof` degrees of freedom.
inline double chi2_p_value(double chi2, int dof) {
    return gamma_q(0.5 * dof, 0.5 * chi2);
}

// Significance per test, Sidak-corrected so that `tests` tests together keep level `alpha`.
inline double sidak(double alpha, int tests) {
    return 1.0 - std::pow(1.0 - alpha, 1.0 / tests);
}

// Adaptive Simpson integration of f over [a, b].
inline double adaptive_simpson(const std::function<double(double)>& f, double a, double b,
                               double eps, int depth = 8) {
    std::function<double(double, double, double, double, double, double, double, int)> recurse =
        [&](double a, double b, double fa, double fm, double fb, double whole, double eps,
            int depth) -> double {
        const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
        const double flm = f(lm), frm = f(rm);
        const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
        const double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
        if (depth <= 0 || std::fabs(left + right - whole) <= 15.0 * eps)
            return left + right + (left + right - whole) / 15.0;
        return recurse(a, m, fa, flm, fm, left, 0.5 * eps, depth - 1) +
               recurse(m, b, fm, frm, fb, right, 0.5 * eps, depth - 1);
    };
    const double fa = f(a), fb = f(b), fm = f(0.5 * (a + b));
    return recurse(a, b, fa, fm, fb, (b - a) / 6.0 * (fa + 4.0 * fm + fb), eps, depth);
}

// The result of a chi-square test, with a readable account for failure messages.
struct Chi2Result {
    bool passed = false;
    double p_value = 0.0;
    double pdf_integral = 0.0;  // the density integrated over the sphere (must be <= 1)
    std::string report;
};

// Chi-square test of a direction sampler against its density (Nori's chi2test, docs/accuracy.md):
// `samples` directions are binned over a (cos theta, phi) grid of the whole sphere; expected
// counts come from the density integrated over each cell (solid angle = d cos(theta) d phi);
// cells expecting fewer than 5 samples are pooled. It fails at once if a sample lands where
// the density is 0, or if the density integrates to more than 1.
// `sample` returns false when the sampler produced no direction (that probability mass is the
// difference between 1 and the density's integral).
inline Chi2Result chi2_test_directions(const std::function<bool(Vec3&)>& sample,
                                       const std::function<double(const Vec3&)>& pdf, int samples,
                                       double significance, int cos_cells = 20,
                                       int phi_cells = 40) {
    auto dir = [](double cos_theta, double phi) {
        const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
        return Vec3(static_cast<float>(s * std::cos(phi)), static_cast<float>(s * std::sin(phi)),
                    static_cast<float>(cos_theta));
    };
    Chi2Result result;
    std::ostringstream log;
    std::vector<double> observed(static_cast<size_t>(cos_cells) * phi_cells, 0.0);
    for (int i = 0; i < samples; ++i) {
        Vec3 w;
        if (!sample(w)) continue;
        if (!(pdf(w) > 0.0)) {
            log << "sample (" << w.x << ", " << w.y << ", " << w.z << ") has density 0";
            result.report = log.str();
            return result;
        }
        const double c = std::clamp(static_cast<double>(w.z), -1.0, 1.0);
        double phi = std::atan2(static_cast<double>(w.y), static_cast<double>(w.x));
        if (phi < 0.0) phi += 2.0 * kPi;
        const int ci = std::min(cos_cells - 1, static_cast<int>((c + 1.0) / 2.0 * cos_cells));
        const int pi = std::min(phi_cells - 1, static_cast<int>(phi / (2.0 * kPi) * phi_cells));
        observed[static_cast<size_t>(ci) * phi_cells + pi] += 1.0;
    }
    std::vector<double> expected(observed.size());
    double integral = 0.0;
    for (int ci = 0; ci < cos_cells; ++ci) {
        const double c0 = -1.0 + 2.0 * ci / cos_cells, c1 = -1.0 + 2.0 * (ci + 1) / cos_cells;
        for (int pi = 0; pi < phi_cells; ++pi) {
            const double p0 = 2.0 * kPi * pi / phi_cells, p1 = 2.0 * kPi * (pi + 1) / phi_cells;
            const double cell = adaptive_simpson(
                [&](double c) {
                    return adaptive_simpson([&](double p) { return pdf(dir(c, p)); }, p0, p1, 1e-9,
                                            12);
                },
                c0, c1, 1e-8, 12);
            expected[static_cast<size_t>(ci) * phi_cells + pi] = cell * samples;
            integral += cell;
        }
    }
    result.pdf_integral = integral;
    if (integral > 1.0 + 1e-3) {
        log << "the density integrates to " << integral << " > 1";
        result.report = log.str();
        return result;
    }
    // Pool cells with small expected counts (sorted ascending) until the pool expects >= 5.
    std::vector<size_t> order(observed.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    double chi2 = 0.0, pool_expected = 0.0, pool_observed = 0.0;
    int dof = -1, pooled = 0;
    for (size_t i : order) {
        if (expected[i] == 0.0) {
            if (observed[i] > 0.0) {
                log << "cell " << i << " has " << observed[i] << " samples but expects none";
                result.report = log.str();
                return result;
            }
            continue;
        }
        if (expected[i] < 5.0 || pool_expected > 0.0) {
            pool_expected += expected[i];
            pool_observed += observed[i];
            ++pooled;
            if (pool_expected >= 5.0) {
                chi2 += (pool_observed - pool_expected) * (pool_observed - pool_expected) /
                        pool_expected;
                ++dof;
                pool_expected = pool_observed = 0.0;
            }
            continue;
        }
        chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        ++dof;
    }
    if (pool_expected > 0.0) {
        chi2 += (pool_observed - pool_expected) * (pool_observed - pool_expected) / pool_expected;
        ++dof;
    }
    result.p_value = dof > 0 ? chi2_p_value(chi2, dof) : 1.0;
    result.passed = result.p_value >= significance;
    log << "chi2 = " << chi2 << ", dof = " << dof << ", p = " << result.p_value
        << ", significance = " << significance << ", density integral = " << integral
        << ", pooled cells = " << pooled;
    result.report = log.str();
    return result;
}

// Mean and standard error of a sequence of values.
struct MeanAndError {
    double mean = 0.0, standard_error = 0.0;
};
inline MeanAndError mean_and_error(const std::vector<double>& v) {
    double sum = 0.0, sum2 = 0.0;
    for (double x : v) {
        sum += x;
        sum2 += x * x;
    }
    const double n = static_cast<double>(v.size());
    const double mean = sum / n;
    const double variance = std::max(0.0, (sum2 - n * mean * mean) / (n - 1.0));
    return {mean, std::sqrt(variance / n)};
}

// Two-sided z quantile for significance alpha (e.g. 2.576 for 0.01), by bisection on erfc.
inline double z_quantile(double alpha) {
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (std::erfc(mid / std::sqrt(2.0)) > alpha ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// The two-sided p-value of Student's t with `dof` degrees of freedom, P(|T| >= t), in closed
// form for whole degrees (Abramowitz and Stegun 26.7.3 and 26.7.4). With theta =
// atan(t / sqrt(dof)) and c = cos theta, P(|T| < t) is
//   odd dof:  (2 / pi) (theta + sin theta (c + 2/3 c^3 + 2 4 / (3 5) c^5 + ...)),
//   even dof: sin theta (1 + 1/2 c^2 + 1 3 / (2 4) c^4 + ...),
// each sum up to the term in c^(dof - 2) (for dof = 1, empty).
inline double student_t_p_value(double t, int dof) {
    const double theta = std::atan(std::fabs(t) / std::sqrt(static_cast<double>(dof)));
    const double c2 = std::cos(theta) * std::cos(theta);
    double term = dof % 2 ? std::cos(theta) : 1.0, sum = dof % 2 && dof < 3 ? 0.0 : term;
    for (int k = dof % 2 ? 3 : 2; k <= dof - 2; k += 2) {
        term *= c2 * (k - 1) / k;
        sum += term;
    }
    const double inside =
        dof % 2 ? 2.0 / kPi * (theta + std::sin(theta) * sum) : std::sin(theta) * sum;
    return 1.0 - inside;
}

// Its two-sided quantile for significance alpha, by bisection (7 degrees: 3.4995 at 0.01).
inline double student_t_quantile(double alpha, int dof) {
    double lo = 0.0, hi = 1e4;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (student_t_p_value(mid, dof) > alpha ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace lessons::test
