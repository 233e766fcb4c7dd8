// Lesson 6, section 2: the kernels of density estimation. A photon at distance d from the
// camera-path vertex x counts with weight K(d), a normalised 2D kernel over the disk of radius r
// about x (the photons lie on the surface: a density per unit area),
//   integral over the disk of K(|y - x|) dA(y) = 1,
// so that sum over photons of K(d_p) beta_p estimates flux per unit area (density.h). Its
// expectation is not the irradiance at x but the irradiance convolved with K: the estimate's
// bias. Expanding E about x to second order, the kernel's first moment vanishes and its second,
// per axis, is int K u^2 dA = r^2/4 (constant) or r^2/6 (Epanechnikov), so the bias is
// r^2/8 or r^2/12 times the Laplacian of E, to leading order (docs/06_photon_mapping.md, "The
// kernel's bias").
//
// Kernels, each 0 for d >= r:
//   Constant       K(d) = 1 / (pi r^2)                     (Jensen's photon map; SPPM)
//   Epanechnikov   K(d) = 2 / (pi r^2) (1 - d^2 / r^2)
// The second is Silverman's multivariate Epanechnikov kernel (Silverman, "Density Estimation for
// Statistics and Data Analysis", 1986, section 4.2: K_e(u) = (D + 2) / (2 c_D) (1 - u.u) for
// u.u < 1, c_D the volume of the unit ball in D dimensions), here D = 2, c_2 = pi, u = (y - x) / r
// and the 1/r^2 of the change of variables: among non-negative kernels it has the least
// asymptotic mean integrated squared error, each kernel at its best radius. Its integral:
// 2/(pi r^2) * 2 pi int_0^r (1 - s^2/r^2) s ds = 4/r^2 (r^2/2 - r^2/4) = 1.
#pragma once

#include <utility>

#include "geometry/math.h"

namespace lessons {

enum class Kernel { Constant, Epanechnikov };

// K for a photon at squared distance d2 from the centre of the disk of radius r, per unit area
// (1/m^2); 0 outside the disk.
inline float kernel_weight(Kernel kind, float d2, float r) {
    const float r2 = r * r;
    if (!(d2 < r2)) return 0.0f;
    switch (kind) {
        case Kernel::Constant: return 1.0f / (kPi * r2);
        case Kernel::Epanechnikov: return 2.0f / (kPi * r2) * (1.0f - d2 / r2);
    }
    return 0.0f;
}

// The kernels by name (the --kernel flag's choices, the report's "kernel").
inline constexpr std::pair<const char*, Kernel> kKernelNames[] = {
    {"constant", Kernel::Constant}, {"epanechnikov", Kernel::Epanechnikov}};
inline const char* kernel_name(Kernel kind) {
    for (const auto& [name, kernel] : kKernelNames)
        if (kernel == kind) return name;
    return "?";
}

}  // namespace lessons
