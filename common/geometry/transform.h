// Affine transforms of geometry, in double precision: p -> L p + t. Scene files place shapes
// with them (docs/scene-format.md, "Transforms"); geometry is transformed once, at load, and
// rounded to single precision once.
//
// Conventions: right-handed coordinates; column vectors (a matrix row is written as it acts:
// x' = m00 x + m01 y + m02 z + m03); a rotation by a positive angle about an axis turns
// counter-clockwise seen from the axis's tip (the right-hand rule: about +z, +x turns to +y).
// A list of steps applies in order: [s, r, t] is p -> t(r(s(p))).
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace lessons {

struct Transform {
    glm::dmat3 linear{1.0};  // glm is column-major: linear[c][r] is row r of column c
    glm::dvec3 offset{0.0};

    glm::dvec3 point(const glm::dvec3& p) const { return linear * p + offset; }
    glm::dvec3 vector(const glm::dvec3& v) const { return linear * v; }
    // A surface normal: by the inverse transpose, so it stays perpendicular to the surface's
    // transformed tangents; unit length.
    glm::dvec3 normal(const glm::dvec3& n) const;
    double determinant() const;
    // A negative determinant mirrors: triangle windings and quad edges are swapped so that
    // front sides stay where the mirror image puts them (scene_build.cpp).
    bool mirrors() const { return determinant() < 0.0; }
    bool is_identity() const { return linear == glm::dmat3(1.0) && offset == glm::dvec3(0.0); }
    // The uniform scale factor when this is a similarity (rotation, mirroring, uniform scale and
    // translation only), to within relative 1e-9; else 0.
    double uniform_scale() const;

    // This transform, then `next`.
    Transform then(const Transform& next) const {
        return {next.linear * linear, next.linear * offset + next.offset};
    }
    static Transform scaling(const glm::dvec3& s);
    static Transform rotation(const glm::dvec3& axis, double degrees);  // axis: nonzero
    // About +y by `degrees`, turning +z towards +x: the box's rotate_y, written as it always was
    // (x' = cos t x + sin t z, z' = -sin t x + cos t z).
    static Transform rotation_y(double degrees);
    static Transform translation(const glm::dvec3& t) { return {glm::dmat3(1.0), t}; }
};

}  // namespace lessons
