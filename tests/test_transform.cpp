// Transforms (geometry/transform.h) and shapes placed by them in scene files: order, handedness
// and normals against hand-computed points; a placed mesh equal, bit for bit, to the same mesh
// moved by hand; mirrors that keep front sides; and the errors a transform can have.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "geometry/transform.h"
#include "io/input_error.h"
#include "io/scene_file.h"
#include "render/render.h"
#include "test_util.h"

using namespace lessons;

namespace {

const std::string kHead = R"([image]
width = 24
height = 18

[camera]
position = [0, 0.5, -6]
look_at = [0, 0, 0]
fov = 40

[materials.white]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]

[materials.lamp]
type = "diffuse"
emission = [4, 4, 4]

[[lights]]
type = "point"
position = [1, 3, -2]
intensity = [5, 5, 5]
)";

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-12) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

std::string error_of(const std::string& text) {
    try {
        build_scene(parse_scene_string(text, "transform.toml"));
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

// A few pixels of a scene, through a radiance that depends on the geometry only: the hit's
// distance and the facing of its geometric normal.
Image render_geometry(const Scene& scene) {
    RenderSettings settings;
    settings.threads = 1;
    settings.progress = false;
    Film film(scene.width, scene.height);
    const test::FunctionModel geometry([&](const Ray& ray, Rng&) {
        const std::optional<Hit> hit = scene.intersect(ray);
        if (!hit) return Color(0.0f);
        const SurfaceInteraction si = scene.interaction(ray, *hit);
        return Color(si.t, si.front ? 1.0f : 0.0f, glm::dot(si.n_geo, si.wo));
    });
    test::render_film(scene.camera, film, settings, geometry, 0, 2);
    return film.mean();
}

}  // namespace

TEST(Transform, RotationsAreRightHandedAndStepsApplyInOrder) {
    // About +z by 90 degrees: +x turns to +y, +y to -x (counter-clockwise seen from +z's tip).
    const Transform rz = Transform::rotation({0, 0, 1}, 90);
    expect_near(rz.point({1, 0, 0}), {0, 1, 0});
    expect_near(rz.point({0, 1, 0}), {-1, 0, 0});
    // About +x: +y turns to +z; about +y: +z turns to +x.
    expect_near(Transform::rotation({1, 0, 0}, 90).point({0, 1, 0}), {0, 0, 1});
    expect_near(Transform::rotation({0, 2, 0}, 90).point({0, 0, 1}), {1, 0, 0});
    // The box's rotate_y is the same rotation.
    expect_near(Transform::rotation_y(30).point({1, 2, 3}),
                Transform::rotation({0, 1, 0}, 30).point({1, 2, 3}));
    // Order: scale 2 then translate +x maps (1, 0, 0) to (3, 0, 0); the other way round to (4, 0,
    // 0).
    const Transform s = Transform::scaling(glm::dvec3(2.0)), t = Transform::translation({1, 0, 0});
    expect_near(s.then(t).point({1, 0, 0}), {3, 0, 0});
    expect_near(t.then(s).point({1, 0, 0}), {4, 0, 0});
}

TEST(Transform, NormalsFollowTheInverseTranspose) {
    // A plane x + y = 0 (normal (1, 1, 0)), stretched 3x along x: its tangent (1, -1, 0) goes to
    // (3, -1, 0), and the transformed normal must stay perpendicular to it: (1/3, 1, 0)
    // normalised, not the stretched (3, 1, 0).
    const Transform stretch = Transform::scaling({3, 1, 1});
    const glm::dvec3 n = stretch.normal({1, 1, 0});
    EXPECT_NEAR(glm::dot(n, stretch.vector({1, -1, 0})), 0.0, 1e-12);
    expect_near(n, glm::normalize(glm::dvec3(1.0 / 3.0, 1, 0)));
    EXPECT_TRUE(Transform::scaling({-1, 1, 1}).mirrors());
    EXPECT_FALSE(Transform::rotation({1, 2, 3}, 70).mirrors());
    EXPECT_NEAR(Transform::rotation({1, 2, 3}, 70)
                    .then(Transform::scaling(glm::dvec3(2.5)))
                    .uniform_scale(),
                2.5, 1e-12);
    EXPECT_EQ(Transform::scaling({1, 2, 1}).uniform_scale(), 0.0);
}

TEST(Transform, AMatrixAndTheStepsItSpellsPlaceAShapeAlike) {
    const std::string steps = kHead + R"(
[[shapes]]
type = "quad"
material = "white"
corner = [-1, 0, -1]
edge_u = [2, 0, 0]
edge_v = [0, 0, 2]
transform = [ { scale = 2 }, { rotate = { axis = [0, 0, 1], angle = 90 } }, { translate = [1, 2, 3] } ]
)";
    // The same as a matrix: x' = -2 y + 1, y' = 2 x + 2, z' = 2 z + 3.
    const std::string matrix = kHead + R"(
[[shapes]]
type = "quad"
material = "white"
corner = [-1, 0, -1]
edge_u = [2, 0, 0]
edge_v = [0, 0, 2]
matrix = [[0, -2, 0, 1], [2, 0, 0, 2], [0, 0, 2, 3], [0, 0, 0, 1]]
)";
    const Scene a = build_scene(parse_scene_string(steps, "steps.toml"));
    const Scene b = build_scene(parse_scene_string(matrix, "matrix.toml"));
    const Quad &qa = a.quads().at(0), &qb = b.quads().at(0);
    // corner (-1, 0, -1) -> (1, 0, 1); edge_u (2, 0, 0) -> (0, 4, 0); edge_v (0, 0, 2) -> (0, 0,
    // 4).
    EXPECT_NEAR(glm::length(qa.corner - Vec3(1, 0, 1)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(qa.edge_u - Vec3(0, 4, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(qa.edge_v - Vec3(0, 0, 4)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(qa.corner - qb.corner), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(qa.normal - qb.normal), 0.0f, 1e-6f);
}

// A mesh placed by a transform is the same mesh with its vertices moved by hand (written with
// the float values the transform gives), bit for bit in the image.
TEST(Transform, APlacedMeshRendersAsTheSameMeshMovedByHand) {
    const std::vector<glm::dvec3> vertices = {
        {-1, -1, 0}, {1, -1, 0}, {1, 1, 0.5}, {-1, 1, 0.2}, {0, 0, -1}};
    const std::string faces =
        "faces = [[0, 1, 2, 3], [0, 4, 1], [1, 4, 2], [2, 4, 3], [3, 4, 0]]\n";
    const Transform t = Transform::scaling({1.5, 0.75, 1})
                            .then(Transform::rotation({0.3, 1, 0.2}, 33))
                            .then(Transform::translation({0.25, -0.5, 1}));
    auto list = [](const std::vector<glm::dvec3>& vs) {
        std::string s = "vertices = [";
        char buf[160];
        for (const glm::dvec3& v : vs) {
            std::snprintf(buf, sizeof buf, "[%.9g, %.9g, %.9g], ", float(v.x), float(v.y),
                          float(v.z));
            s += buf;
        }
        return s + "]\n";
    };
    std::vector<glm::dvec3> moved;
    for (const glm::dvec3& v : vertices) moved.push_back(t.point(v));
    const std::string placed =
        kHead + "[[shapes]]\ntype = \"mesh\"\nmaterial = \"white\"\n" + list(vertices) + faces +
        "transform = [ { scale = [1.5, 0.75, 1] }, { rotate = { axis = [0.3, 1, 0.2], angle = 33 } "
        "}, { translate = [0.25, -0.5, 1] } ]\n";
    const std::string by_hand =
        kHead + "[[shapes]]\ntype = \"mesh\"\nmaterial = \"white\"\n" + list(moved) + faces;
    const Image a = render_geometry(build_scene(parse_scene_string(placed, "placed.toml")));
    const Image b = render_geometry(build_scene(parse_scene_string(by_hand, "by_hand.toml")));
    int covered = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        ASSERT_EQ(a.pixels[i], b.pixels[i]) << "pixel " << i;
        covered += a.pixels[i].x > 0.0f;
    }
    EXPECT_GT(covered, 20);
}

// A one-sided lamp mirrored by a transform still lights what its mirror image faces: the
// floor below a downward lamp mirrored in x gets the same light.
TEST(Transform, AMirroredOneSidedLampStillFacesWhereItsImageFaces) {
    auto scene_with = [](const std::string& transform) {
        return build_scene(parse_scene_string(kHead + R"(
[[shapes]]
type = "quad"
material = "lamp"
corner = [0.5, 2, -0.5]
edge_u = [0, 0, 1]
edge_v = [1, 0, 0]
)" + transform + "\n",
                                              "lamp.toml"));
    };
    const Scene plain = scene_with(""),
                mirrored = scene_with("transform = [ { scale = [-1, 1, 1] } ]");
    ASSERT_EQ(plain.area_lights().size(), 1u);
    ASSERT_EQ(mirrored.area_lights().size(), 1u);
    // As written the lamp faces +y (cross((0, 0, 1), (1, 0, 0))); so must its mirror image (the
    // mirrored edges alone would give -y).
    EXPECT_NEAR(glm::dot(plain.area_lights()[0].normal, mirrored.area_lights()[0].normal), 1.0f,
                1e-6f);
    EXPECT_NEAR(mirrored.area_lights()[0].center.x, -plain.area_lights()[0].center.x, 1e-6f);
}

TEST(Transform, ErrorsNameTheFieldAndSayWhy) {
    const std::string sphere = kHead + R"(
[[shapes]]
type = "sphere"
material = "white"
center = [0, 0, 0]
radius = 1
)";
    struct Case {
        std::string extra, expected;
    };
    const std::vector<Case> cases = {
        {"transform = [ { scale = [1, 2, 1] } ]", "shapes[0].transform: a sphere takes rotations"},
        {"transform = [ { scale = 0 } ]", "shapes[0].transform[0].scale: must not be zero"},
        {"transform = [ { scale = 2, translate = [1, 0, 0] } ]", "each step of a transform is one"},
        {"transform = [ { rotate = { axis = [0, 0, 0], angle = 3 } } ]",
         "transform[0].rotate.axis: must not be the zero vector"},
        {"transform = [ { rotate = { axis = [0, 1, 0], angel = 3 } } ]", "angle: missing"},
        {"matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1]]",
         "shapes[0].matrix: is not invertible"},
        {"matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]",
         "the last row must be [0, 0, 0, 1]"},
        {"matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "expected 4 rows of 4 numbers"},
        {"transform = [ { translate = [2e9, 0, 0] } ]", "too large for single precision"},
        {"transform = [ { scale = 1 } ]\nmatrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, "
         "0, "
         "0, 1]]",
         "give either transform"},
    };
    for (const Case& c : cases) {
        const std::string m = error_of(sphere + c.extra + "\n");
        EXPECT_NE(m.find(c.expected), std::string::npos) << c.extra << "\n -> " << m;
        EXPECT_NE(m.find("transform.toml:"), std::string::npos) << m;
    }
    // A box's rotate_y and translate are a transform already.
    const std::string box = kHead + R"(
[[shapes]]
type = "box"
material = "white"
min = [0, 0, 0]
max = [1, 1, 1]
rotate_y = 10
transform = [ { scale = 2 } ]
)";
    EXPECT_NE(error_of(box).find("give either rotate_y and translate, or a transform"),
              std::string::npos)
        << error_of(box);
}
