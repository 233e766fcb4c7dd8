// Where a shape of a scene file goes: its `transform` (scale, rotate and translate steps) or
// `matrix` (docs/scene-format.md, "Transforms"), and spheres and quads placed as they are read.
#include <toml++/toml.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "io/input_error.h"
#include "io/scene_tables.h"

namespace lessons::scene_file {

namespace {

// One step of a `transform` list: { scale = s | [x, y, z] }, { rotate = { axis, angle } } or
// { translate = [x, y, z] }.
Transform read_transform_step(TableReader& step) {
    std::vector<std::string> present;
    for (const std::string k : {"scale", "rotate", "translate"})
        if (step.has(k)) present.push_back(k);
    if (present.size() != 1)
        step.fail(present.empty() ? "scale" : present[1],
                  "each step of a transform is one of scale, rotate or translate, e.g. "
                  "{ scale = 2 }, { rotate = { axis = [0, 1, 0], angle = 30 } }, "
                  "{ translate = [1, 0, 0] }");
    Transform t;
    if (present[0] == "scale") {
        glm::dvec3 s;
        if (step.require("scale").is_number())
            s = glm::dvec3(step.number("scale"));
        else
            s = step.dvec3("scale");
        for (int i = 0; i < 3; ++i)
            if (s[i] == 0.0)
                step.fail("scale",
                          "must not be zero: a zero scale flattens the shape (and its "
                          "normals cannot follow)");
        t = Transform::scaling(s);
    } else if (present[0] == "rotate") {
        TableReader rotate(step.table("rotate"), step.where("rotate").file, step.field("rotate"));
        const glm::dvec3 axis = rotate.dvec3("axis");
        if (glm::dot(axis, axis) == 0.0) rotate.fail("axis", "must not be the zero vector");
        t = Transform::rotation(axis, rotate.number("angle"));
        rotate.reject_unknown({"axis", "angle"}, "a rotation (angle in degrees)");
    } else {
        t = Transform::translation(step.dvec3("translate"));
    }
    step.reject_unknown(present, "a transform step");
    return t;
}

// matrix = [[4 numbers] x 4], row by row (column vectors: x' = m00 x + m01 y + m02 z + m03);
// the last row must be [0, 0, 0, 1].
Transform read_matrix(TableReader& r) {
    const toml::array& rows = r.array("matrix");
    if (rows.size() != 4) r.fail("matrix", "expected 4 rows of 4 numbers");
    double m[4][4];
    for (size_t i = 0; i < 4; ++i) {
        const toml::array* row = rows.get(i)->as_array();
        if (!row || row->size() != 4) r.fail("matrix", "expected 4 rows of 4 numbers");
        for (size_t j = 0; j < 4; ++j) {
            const toml::node& c = *row->get(j);
            if (!c.is_number() || !std::isfinite(as_number(c)))
                r.fail("matrix", "row " + std::to_string(i) + ": expected finite numbers");
            m[i][j] = as_number(c);
        }
    }
    if (m[3][0] != 0.0 || m[3][1] != 0.0 || m[3][2] != 0.0 || m[3][3] != 1.0)
        r.fail("matrix", "the last row must be [0, 0, 0, 1] (an affine transform)");
    Transform t;
    for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) t.linear[col][row] = m[row][col];
        t.offset[row] = m[row][3];
    }
    // Invertible, relative to the size of its columns (a scale of 1e-6 is fine, a flat one not).
    const double size =
        glm::length(t.linear[0]) * glm::length(t.linear[1]) * glm::length(t.linear[2]);
    if (!(std::fabs(t.determinant()) > 1e-12 * size))
        r.fail("matrix", "is not invertible (its determinant is 0): it flattens the shape");
    return t;
}

// A point after the transform, checked to stay within single precision's reach.
Vec3 placed_point(const ShapeDescription& s, const glm::dvec3& p) {
    const glm::dvec3 q = s.transform.point(p);
    if (!(max_component(glm::abs(q)) <= kMaxCoordinate))
        throw InputError(s.transform_where.file, s.transform_where.line, s.transform_where.field,
                         "moves the shape too far for single precision geometry (|x| must be at "
                         "most 1e9)");
    return Vec3(q);
}

}  // namespace

void read_transform(TableReader& r, ShapeDescription& s) {
    if (r.has("transform") && r.has("matrix"))
        r.fail("matrix", "give either transform (a list of steps) or matrix, not both");
    if (r.has("matrix")) {
        s.transform_where = r.where("matrix");
        s.transform = read_matrix(r);
    } else if (r.has("transform")) {
        s.transform_where = r.where("transform");
        const toml::array& steps = r.array("transform");
        for (size_t i = 0; i < steps.size(); ++i) {
            const toml::table* t = steps.get(i)->as_table();
            const std::string field = r.field("transform") + "[" + std::to_string(i) + "]";
            if (!t)
                r.fail("transform", "step " + std::to_string(i) +
                                        ": expected a table, e.g. "
                                        "{ scale = 2 }");
            TableReader step(*t, s.where.file, field);
            s.transform = s.transform.then(read_transform_step(step));
        }
    }
}

void place_sphere(ShapeDescription& s) {
    if (s.transform.is_identity()) return;
    const double scale = s.transform.uniform_scale();
    if (scale == 0.0)
        throw InputError(s.transform_where.file, s.transform_where.line, s.transform_where.field,
                         "a sphere takes rotations, mirrors, translations and a uniform scale "
                         "only; this transform stretches it unevenly (an ellipsoid): use a mesh");
    s.center = placed_point(s, glm::dvec3(s.center));
    s.radius = static_cast<float>(s.radius * scale);
}

void place_quad(ShapeDescription& s) {
    if (s.transform.is_identity()) return;
    const glm::dvec3 corner(s.corner), u(s.edge_u), v(s.edge_v);
    s.corner = placed_point(s, corner);
    s.edge_u = Vec3(s.transform.vector(u));
    s.edge_v = Vec3(s.transform.vector(v));
    placed_point(s, corner + u + v);
    // A mirror reverses cross(u, v): swapping the edges keeps the front side the mirror image
    // of the front side (a one-sided lamp still lights what its image faces).
    if (s.transform.mirrors()) std::swap(s.edge_u, s.edge_v);
    if (!(Quad(s.corner, s.edge_u, s.edge_v).area() > 0.0f))
        throw InputError(s.transform_where.file, s.transform_where.line, s.transform_where.field,
                         "leaves the quad no area in single precision");
}

}  // namespace lessons::scene_file
