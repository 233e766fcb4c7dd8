// Affine transforms (see transform.h).
#include "geometry/transform.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace lessons {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

glm::dvec3 Transform::normal(const glm::dvec3& n) const {
    return glm::normalize(glm::transpose(glm::inverse(linear)) * n);
}

double Transform::determinant() const {
    return glm::determinant(linear);
}

double Transform::uniform_scale() const {
    // A similarity has orthogonal columns of one length s: L^T L = s^2 I.
    const glm::dmat3 g = glm::transpose(linear) * linear;
    const double s2 = (g[0][0] + g[1][1] + g[2][2]) / 3.0;
    if (!(s2 > 0.0)) return 0.0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (std::fabs(g[c][r] - (c == r ? s2 : 0.0)) > 1e-9 * s2) return 0.0;
    return std::sqrt(s2);
}

Transform Transform::scaling(const glm::dvec3& s) {
    Transform t;
    t.linear = glm::dmat3(s.x, 0.0, 0.0, 0.0, s.y, 0.0, 0.0, 0.0, s.z);
    return t;
}

Transform Transform::rotation(const glm::dvec3& axis, double degrees) {
    // Rodrigues: R = cos(t) I + sin(t) [a]x + (1 - cos(t)) a a^T, for the unit axis a.
    const glm::dvec3 a = glm::normalize(axis);
    const double t = degrees * (kPi / 180.0), c = std::cos(t), s = std::sin(t), k = 1.0 - c;
    Transform r;
    // Columns: the images of +x, +y, +z.
    r.linear[0] = {c + k * a.x * a.x, k * a.x * a.y + s * a.z, k * a.x * a.z - s * a.y};
    r.linear[1] = {k * a.y * a.x - s * a.z, c + k * a.y * a.y, k * a.y * a.z + s * a.x};
    r.linear[2] = {k * a.z * a.x + s * a.y, k * a.z * a.y - s * a.x, c + k * a.z * a.z};
    return r;
}

Transform Transform::rotation_y(double degrees) {
    const double t = degrees * (kPi / 180.0), c = std::cos(t), s = std::sin(t);
    Transform r;
    r.linear[0] = {c, 0.0, -s};  // +x goes to (cos t, 0, -sin t)
    r.linear[1] = {0.0, 1.0, 0.0};
    r.linear[2] = {s, 0.0, c};  // +z goes to (sin t, 0, cos t)
    return r;
}

}  // namespace lessons
