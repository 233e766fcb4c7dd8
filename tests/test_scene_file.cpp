// Scene files: every error names file, line and field; valid files build the scene they say.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "01_ray_casting/ray_casting.h"
#include "io/image.h"
#include "io/input_error.h"
#include "io/mesh_file.h"
#include "io/scene_file.h"
#include "render/progressive.h"
#include "scene/environment.h"

using namespace lessons;

namespace {

const std::string kValidHead = R"([image]
width = 8
height = 6

[camera]
position = [0, 0, -5]
look_at = [0, 0, 0]
fov = 40

[materials.white]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
)";  // 12 lines

const std::string kSphere = R"(
[[shapes]]
type = "sphere"
material = "white"
center = [0, 0, 0]
radius = 1
)";

struct BadCase {
    std::string name;
    std::string text;
    int line;             // expected line (0: not checked)
    std::string field;    // expected field
    std::string message;  // expected part of the message
};

std::string write_temp(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "lessons_scene_tests";
    std::filesystem::create_directories(dir);
    const auto path = dir / name;
    std::ofstream(path) << text;
    return path.string();
}

std::string error_of(const std::string& text, const std::string& file_name = "bad.toml") {
    try {
        build_scene(parse_scene_string(text, file_name));
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST(SceneFile, EveryErrorNamesFileLineAndField) {
    const std::vector<BadCase> cases = {
        {"syntax", "[image\nwidth = 1\n", 1, "", "TOML syntax error"},
        {"no image", "[camera]\nposition=[0,0,0]\n", 0, "image", "missing"},
        {"width type", "[image]\nwidth = \"big\"\nheight = 2\n", 2, "image.width",
         "expected an integer"},
        {"width zero", "[image]\nwidth = 0\nheight = 2\n", 2, "image.width", "between 1"},
        {"height absurd", "[image]\nwidth = 4\nheight = 100000000\n", 3, "image.height",
         "between 1 and 16384"},
        {"image unknown", "[image]\nwidth = 4\nheight = 4\nwidht = 3\n", 4, "image.widht",
         "did you mean 'width'"},
        {"fov 180", kValidHead + kSphere, 0, "", "(no error)"},  // control: valid
        {"fov range",
         "[image]\nwidth=4\nheight=4\n[camera]\nposition=[0,0,0]\nlook_at=[0,0,1]\nfov=180\n", 7,
         "camera.fov", "must be in (0, 180)"},
        {"position length",
         "[image]\nwidth=4\nheight=4\n[camera]\nposition=[0,0]\nlook_at=[0,0,1]\nfov=40\n", 5,
         "camera.position", "array of 3 numbers"},
        {"degenerate camera",
         "[image]\nwidth=4\nheight=4\n[camera]\nposition=[1,2,3]\nlook_at=[1,2,3]\nfov=40\n", 6,
         "camera.look_at", "equals position"},
        {"up parallel",
         "[image]\nwidth=4\nheight=4\n[camera]\nposition=[0,0,0]\nlook_at=[0,5,0]\nup=[0,1,0]\n"
         "fov=40\n",
         7, "camera.up", "parallel"},
        {"camera typo",
         "[image]\nwidth=4\nheight=4\n[camera]\nposition=[0,0,0]\nlook_at=[0,0,1]\nfov=40\n"
         "fvo=3\n",
         8, "camera.fvo", "did you mean 'fov'"},
        {"nan position",
         "[image]\nwidth=4\nheight=4\n[camera]\nposition=[0,nan,0]\nlook_at=[0,0,1]\nfov=40\n", 5,
         "camera.position", "finite"},
        {"material type", kValidHead + "[materials.m]\ntype = \"difuse\"\n", 14, "materials.m.type",
         "did you mean 'diffuse'"},
        {"albedo above one",
         kValidHead + "[materials.m]\ntype = \"diffuse\"\nalbedo = [1.2, 0, 0]\n", 15,
         "materials.m.albedo", "at most 1"},
        {"negative emission",
         kValidHead + "[materials.m]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n"
                      "emission = [1, -1, 1]\n",
         16, "materials.m.emission", "negative"},
        {"field of another type",
         kValidHead + "[materials.m]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\nior = 1.5\n",
         16, "materials.m.ior", "belongs to glass"},
        {"diffuse without albedo", kValidHead + "[materials.m]\ntype = \"diffuse\"\n", 13,
         "materials.m.albedo", "missing"},
        {"roughness zero", kValidHead + "[materials.m]\ntype = \"glossy\"\nroughness = 0\n", 15,
         "materials.m.roughness", "(0, 1]"},
        {"glossy energy",
         kValidHead +
             "[materials.m]\ntype = \"glossy\"\nalbedo = [0.5, 0.5, 0.5]\nroughness = 0.3\n",
         15, "materials.m.albedo", "albedo + specular must be at most 1"},
        {"ior type", kValidHead + "[materials.m]\ntype = \"glass\"\nior = \"high\"\n", 15,
         "materials.m.ior", "expected a number"},
        {"checker cells",
         kValidHead + "[materials.m]\ntype = \"diffuse\"\nalbedo = { checker = [[1,1,1],[0,0,0]], "
                      "cells = [0, 2] }\n",
         15, "materials.m.albedo.cells", "between 1"},
        {"shape type", kValidHead + "[[shapes]]\ntype = \"sphre\"\nmaterial = \"white\"\n", 14,
         "shapes[0].type", "did you mean 'sphere'"},
        {"radius zero",
         kValidHead + "[[shapes]]\ntype = \"sphere\"\nmaterial = \"white\"\ncenter = [0,0,0]\n"
                      "radius = 0\n",
         17, "shapes[0].radius", "(0, "},
        {"radius inf",
         kValidHead + "[[shapes]]\ntype = \"sphere\"\nmaterial = \"white\"\ncenter = [0,0,0]\n"
                      "radius = inf\n",
         17, "shapes[0].radius", "finite"},
        {"sphere typo",
         kValidHead + "[[shapes]]\ntype = \"sphere\"\nmaterial = \"white\"\ncentre = [0,0,0]\n"
                      "radius = 1\n",
         13, "shapes[0].center", "missing"},
        {"quad parallel edges",
         kValidHead + "[[shapes]]\ntype = \"quad\"\nmaterial = \"white\"\ncorner = [0,0,0]\n"
                      "edge_u = [1,0,0]\nedge_v = [2,0,0]\n",
         18, "shapes[0].edge_v", "parallel"},
        {"box max not above min",
         kValidHead + "[[shapes]]\ntype = \"box\"\nmaterial = \"white\"\nmin = [0, 2, 0]\n"
                      "max = [1, 2, 1]\n",
         17, "shapes[0].max", "must be greater than min on every axis; on y, max = 2 <= min = 2"},
        {"box typo",
         kValidHead + "[[shapes]]\ntype = \"box\"\nmaterial = \"white\"\nmin = [0, 0, 0]\n"
                      "max = [1, 1, 1]\nrotate = 15\n",
         18, "shapes[0].rotate", "unknown field in a box; did you mean 'rotate_y'?"},
        {"box rotate_y nan",
         kValidHead + "[[shapes]]\ntype = \"box\"\nmaterial = \"white\"\nmin = [0, 0, 0]\n"
                      "max = [1, 1, 1]\nrotate_y = nan\n",
         18, "shapes[0].rotate_y", "must be finite"},
        {"box missing max",
         kValidHead + "[[shapes]]\ntype = \"box\"\nmaterial = \"white\"\nmin = [0, 0, 0]\n"
                      "mx = [1, 1, 1]\n",
         13, "shapes[0].max", "missing (required in shapes[0]); found 'mx': a typo?"},
        {"box too large once rotated",
         kValidHead + "[[shapes]]\ntype = \"box\"\nmaterial = \"white\"\nmin = [0, 0, 0]\n"
                      "max = [1e9, 1, 1e9]\nrotate_y = 45\n",
         17, "shapes[0].max", "too large for single precision"},
        {"box too large once moved",
         kValidHead + "[[shapes]]\ntype = \"box\"\nmaterial = \"white\"\nmin = [0, 0, 0]\n"
                      "max = [1, 100, 1]\ntranslate = [0, 1e9, 0]\n",
         18, "shapes[0].translate", "too large for single precision"},
        {"box type typo", kValidHead + "[[shapes]]\ntype = \"bx\"\nmaterial = \"white\"\n", 14,
         "shapes[0].type", "did you mean 'box'"},
        {"undefined material",
         kValidHead + "[[shapes]]\ntype = \"sphere\"\nmaterial = \"whte\"\ncenter = [0,0,0]\n"
                      "radius = 1\n",
         15, "shapes[0].material", "did you mean 'white'"},
        {"missing obj",
         kValidHead + "[[shapes]]\ntype = \"mesh\"\nfile = \"no_such_mesh.obj\"\n"
                      "material = \"white\"\n",
         15, "shapes[0].file", "OBJ file not found"},
        {"face index",
         kValidHead + "[[shapes]]\ntype = \"mesh\"\nmaterial = \"white\"\n"
                      "vertices = [[0,0,0],[1,0,0],[0,1,0]]\nfaces = [[0, 1, 3]]\n",
         17, "shapes[0].faces", "outside 0..2"},
        {"degenerate faces",
         kValidHead + "[[shapes]]\ntype = \"mesh\"\nmaterial = \"white\"\n"
                      "vertices = [[0,0,0],[1,0,0],[2,0,0]]\nfaces = [[0, 1, 2]]\n",
         13, "shapes[0].faces", "zero area"},
        {"empty scene", kValidHead, 0, "shapes", "empty"},
        {"light type",
         kValidHead + kSphere +
             "[[lights]]\ntype = \"spotlight\"\nposition = [0,0,0]\n"
             "intensity = [1,1,1]\n",
         20, "lights[0].type", "unknown light type"},
        {"light intensity missing",
         kValidHead + kSphere + "[[lights]]\ntype = \"point\"\nposition = [0,0,0]\n", 19,
         "lights[0].intensity", "missing"},
        {"top-level typo", kValidHead + kSphere + "[backgound]\nradiance = [1,1,1]\n", 19,
         "backgound", "did you mean 'background'"},
    };
    for (const BadCase& c : cases) {
        const std::string error = error_of(c.text);
        SCOPED_TRACE(c.name + ": " + error);
        if (c.message == "(no error)") {
            EXPECT_EQ(error, "(no error)");
            continue;
        }
        // "file:line: field: message"; line 0 means the line is not checked.
        const std::string where =
            c.line > 0 ? "bad.toml:" + std::to_string(c.line) + ": " : "bad.toml";
        EXPECT_EQ(error.rfind(where, 0), 0u) << "expected to start with " << where;
        if (!c.field.empty()) {
            EXPECT_NE(error.find(": " + c.field + ": "), std::string::npos) << "field " << c.field;
        }
        EXPECT_NE(error.find(c.message), std::string::npos) << "expected " << c.message;
        EXPECT_EQ(error.find('\n'), std::string::npos) << "one line";
    }
}

TEST(SceneFile, MissingSceneFileIsAClearError) {
    try {
        parse_scene_file("/nonexistent/scene.toml");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "/nonexistent/scene.toml: scene file not found");
    }
}

TEST(SceneFile, ShippedScenesBuildWhatTheySay) {
    const Scene cornell = load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml");
    EXPECT_EQ(cornell.width, 512);
    EXPECT_EQ(cornell.triangles().size(), 2u * (3 + 1 + 1 + 5 + 5));
    ASSERT_EQ(cornell.area_lights().size(), 1u);
    EXPECT_FLOAT_EQ(cornell.area_lights()[0].area, 130.0f * 105.0f);
    EXPECT_EQ(cornell.area_lights()[0].normal, Vec3(0, -1, 0));  // shines down
    const Scene rtiow =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box_rtiow.toml");
    EXPECT_EQ(rtiow.quads().size(), 6u + 2u * 6u);  // 5 walls and the lamp, two boxes
    ASSERT_EQ(rtiow.area_lights().size(), 1u);
    EXPECT_FLOAT_EQ(rtiow.area_lights()[0].area, 130.0f * 105.0f);
    EXPECT_TRUE(rtiow.area_lights()[0].two_sided);
    const Scene whitted = load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/whitted_1979.toml");
    EXPECT_EQ(whitted.spheres().size(), 2u);
    EXPECT_EQ(whitted.point_lights().size(), 1u);
    EXPECT_TRUE(whitted.materials()[0].albedo.checker || whitted.materials()[1].albedo.checker ||
                whitted.materials()[2].albedo.checker);
}

TEST(SceneFile, ObjMeshWithMtlMaterialsLoads) {
    write_temp("box.mtl",
               "newmtl shiny\nillum 3\nKs 0.9 0.9 0.9\nnewmtl lamp\nKd 0 0 0\nKe 5 5 5\n"
               "newmtl wall\nKd 0.4 0.5 0.6\n");
    write_temp("box.obj",
               "mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
               "vn 0 0 1\n"
               "usemtl shiny\nf 1//1 2//1 3//1 4//1\nusemtl lamp\nf 1 2 5\nusemtl wall\n"
               "f 1 4 5\nf 1 1 2\n");  // the last face is degenerate
    const std::string scene_path =
        write_temp("obj_scene.toml", kValidHead +
                                         "[materials.wall]\ntype = \"diffuse\"\n"
                                         "albedo = [0.1, 0.2, 0.3]\n"
                                         "[[shapes]]\ntype = \"mesh\"\nfile = \"box.obj\"\n");
    const Scene scene = load_scene(scene_path);
    ASSERT_EQ(scene.triangles().size(), 4u);  // quad -> 2, two triangles, 1 degenerate skipped
    auto material_of = [&](size_t t) { return scene.material(scene.triangles()[t].material); };
    EXPECT_EQ(material_of(0).type, MaterialType::Mirror);
    EXPECT_FLOAT_EQ(material_of(0).reflectance.x, 0.9f);
    EXPECT_TRUE(material_of(2).is_emissive());
    // A scene material named like the MTL material wins over the MTL's values.
    EXPECT_FLOAT_EQ(material_of(3).albedo.value.z, 0.3f);
    EXPECT_EQ(scene.area_lights().size(), 1u);
}

TEST(SceneFile, ObjWithoutMaterialsNeedsOneFromTheScene) {
    write_temp("plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string text = kValidHead + "[[shapes]]\ntype = \"mesh\"\nfile = \"plain.obj\"\n";
    const std::string path = write_temp("plain_scene.toml", text);
    try {
        load_scene(path);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("shapes[0].material"), std::string::npos) << e.what();
    }
}

TEST(SceneFile, ObjWithNonFiniteVertexIsAnErrorNamingTheLine) {
    write_temp("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
    const std::string path = write_temp(
        "nan_scene.toml",
        kValidHead + "[[shapes]]\ntype = \"mesh\"\nfile = \"nan.obj\"\nmaterial = \"white\"\n");
    try {
        load_scene(path);
        FAIL() << "a NaN coordinate was accepted";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("shapes[0].file"), std::string::npos) << msg;
        EXPECT_NE(msg.find("nan.obj:2: v: 'nan' is not a finite coordinate"), std::string::npos)
            << msg;
    }
}

TEST(SceneFile, TyposInRequiredFieldsAndEmptyNamesAreExplained) {
    EXPECT_NE(error_of(kValidHead + "[[shapes]]\ntype = \"sphere\"\nmaterial = \"white\"\n"
                                    "center = [0,0,0]\nradus = 1\n")
                  .find("shapes[0].radius: missing (required in shapes[0]); found 'radus'"),
              std::string::npos);
    EXPECT_NE(error_of(kValidHead + "[[shapes]]\ntype = \"sphere\"\nmaterial = \"\"\n"
                                    "center = [0,0,0]\nradius = 1\n")
                  .find("bad.toml:15: shapes[0].material: must name a material"),
              std::string::npos);
    // A field already read is not taken for a typo of a missing one: a box's min is no 'max'.
    const std::string no_max = error_of(kValidHead +
                                        "[[shapes]]\ntype = \"box\"\nmaterial = \"white\"\n"
                                        "min = [0, 0, 0]\n");
    EXPECT_NE(no_max.find("shapes[0].max: missing (required in shapes[0])"), std::string::npos);
    EXPECT_EQ(no_max.find("found"), std::string::npos) << no_max;
    // An integer beyond a double's exact range is read as the number it is (it used to read
    // as 0), and refused as too large for float geometry; so is a float beyond 1e9.
    for (const char* big : {"9007199254740993", "1e31"}) {
        EXPECT_NE(error_of(kValidHead +
                           "[[shapes]]\ntype = \"sphere\"\nmaterial = \"white\"\n"
                           "center = [0," +
                           big + ",0]\nradius = 1\n")
                      .find("shapes[0].center: element 1 is too large"),
                  std::string::npos)
            << big;
    }
}

TEST(SceneFile, BoxIsSixOutwardQuadsClosingTheRotatedMovedBox) {
    const Scene scene = build_scene(parse_scene_string(
        kValidHead + "[[shapes]]\ntype = \"box\"\nmaterial = \"white\"\nmin = [-1, 0, 2]\n"
                     "max = [2, 3, 4.5]\nrotate_y = 30\ntranslate = [10, -5, 7]\n",
        "box.toml"));
    ASSERT_EQ(scene.quads().size(), 6u);
    EXPECT_TRUE(scene.triangles().empty());

    // The expected box, by the format's definition, in double: p -> R_y(30 deg) p + translate.
    const double t = 30.0 * 3.14159265358979323846 / 180.0, c = std::cos(t), s = std::sin(t);
    auto place = [&](double x, double y, double z) {
        return glm::dvec3(c * x + s * z + 10.0, y - 5.0, -s * x + c * z + 7.0);
    };
    std::vector<glm::dvec3> corners;
    for (double x : {-1.0, 2.0})
        for (double y : {0.0, 3.0})
            for (double z : {2.0, 4.5}) corners.push_back(place(x, y, z));
    const glm::dvec3 center = place(0.5, 1.5, 3.25);
    // The outward normals: the rotated axes, +-x' = +-(cos t, 0, -sin t), +-y, +-z'.
    const std::vector<Vec3> normals = {
        Vec3(float(c), 0, float(-s)), Vec3(float(-c), 0, float(s)), Vec3(0, 1, 0), Vec3(0, -1, 0),
        Vec3(float(s), 0, float(c)),  Vec3(float(-s), 0, float(-c))};

    std::vector<int> corner_uses(corners.size(), 0);
    std::vector<int> normal_uses(normals.size(), 0);
    double area = 0.0;
    for (const Quad& q : scene.quads()) {
        // Front side out of the box: the normal points from the centre towards the face.
        const glm::dvec3 to_face = glm::dvec3(q.center()) - center;
        EXPECT_GT(glm::dot(to_face, glm::dvec3(q.normal)), 0.0);
        for (size_t k = 0; k < normals.size(); ++k)
            if (glm::length(q.normal - normals[k]) < 1e-6f) ++normal_uses[k];
        area += q.area();
        // Each of the quad's four vertices is one of the box's rotated and moved corners.
        for (const Vec3& v :
             {q.corner, q.corner + q.edge_u, q.corner + q.edge_v, q.corner + q.edge_u + q.edge_v}) {
            int found = -1;
            for (size_t k = 0; k < corners.size(); ++k)
                if (glm::length(glm::dvec3(v) - corners[k]) < 1e-5) found = static_cast<int>(k);
            ASSERT_GE(found, 0) << "vertex " << v.x << " " << v.y << " " << v.z;
            ++corner_uses[found];
        }
    }
    // Closed: every corner is shared by three faces, and every direction has its face.
    for (int uses : corner_uses) EXPECT_EQ(uses, 3);
    for (int uses : normal_uses) EXPECT_EQ(uses, 1);
    EXPECT_NEAR(area, 2.0 * (3 * 3 + 3 * 2.5 + 3 * 2.5), 1e-4);

    // Rays from the centre leave through a face's back; rays towards the centre from outside
    // meet a face's front.
    for (int i = 0; i < 200; ++i) {
        const float z = 1.0f - 2.0f * (static_cast<float>(i) + 0.5f) / 200.0f;
        const float phi = 2.399963f * static_cast<float>(i);  // golden angle: spread directions
        const float r = std::sqrt(1.0f - z * z);
        const Vec3 d(r * std::cos(phi), r * std::sin(phi), z);
        const Ray inside{Vec3(center), d, kInfinity};
        const std::optional<Hit> out = scene.intersect(inside);
        ASSERT_TRUE(out.has_value()) << "escaped through a gap, direction " << i;
        EXPECT_FALSE(scene.interaction(inside, *out).front_face());
        const Ray outside{Vec3(center) + 20.0f * d, -d, kInfinity};
        const std::optional<Hit> in = scene.intersect(outside);
        ASSERT_TRUE(in.has_value());
        EXPECT_TRUE(scene.interaction(outside, *in).front_face());
    }
}

// [background] map from a Radiance .hdr file, and real maps' flaws (scene/environment.h).
namespace {

std::string map_scratch(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / "lessons_map_file_tests";
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

std::string scene_with_map(const std::string& map) {
    return R"([image]
width = 24
height = 16
[camera]
position = [0, 0.3, -4]
look_at = [0, 0, 0]
fov = 70
[materials.grey]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[[shapes]]
type = "sphere"
material = "grey"
center = [0, 0, 0]
radius = 1
[background]
map = ")" + map +
           R"("
rotate = 20
strength = 1.5
)";
}

// A map of varied radiance with a small sun.
Image varied_map(int w, int h) {
    Image map(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            map.at(i, j) = Color(0.2f + 0.05f * i, 0.3f + 0.1f * j, 0.7f - 0.02f * (i + j));
    map.at(3, 1) = Color(400.0f, 350.0f, 300.0f);
    return map;
}

std::vector<Vec3> directions(int n) {
    std::vector<Vec3> d;
    for (int k = 0; k < n; ++k) {  // a Fibonacci spiral over the sphere
        const float y = 1.0f - 2.0f * (k + 0.5f) / n, r = std::sqrt(1.0f - y * y);
        const float phi = 2.39996323f * k;
        d.emplace_back(r * std::cos(phi), y, r * std::sin(phi));
    }
    return d;
}

std::vector<std::string> notes_naming(const Scene& scene, const std::string& file) {
    std::vector<std::string> found;
    for (const std::string& n : scene.notes)
        if (n.find(file) != std::string::npos) found.push_back(n);
    return found;
}

}  // namespace

// An .hdr map and an EXR of the texels it holds are the same map: the same radiance and density
// in every direction, and lesson 1 renders the same image from both, bit for bit.
TEST(EnvironmentMapFile, AnHdrMapIsTheExrOfTheSameTexels) {
    const Image map = varied_map(16, 8);
    const std::string hdr = map_scratch("varied.hdr"), exr = map_scratch("varied.exr");
    ASSERT_TRUE(stbi_write_hdr(hdr.c_str(), map.width, map.height, 3,
                               reinterpret_cast<const float*>(map.pixels.data())));
    write_exr(read_hdr(hdr), exr);
    const Scene a = build_scene(parse_scene_string(scene_with_map(hdr), "hdr.toml"));
    const Scene b = build_scene(parse_scene_string(scene_with_map(exr), "exr.toml"));
    ASSERT_TRUE(a.environment_map && b.environment_map);
    for (const Vec3& d : directions(4000)) {
        ASSERT_EQ(a.environment_map->radiance(d), b.environment_map->radiance(d));
        ASSERT_EQ(a.environment_map->pdf(d), b.environment_map->pdf(d));
    }
    EXPECT_EQ(a.environment_map->mean(), b.environment_map->mean());
    EXPECT_TRUE(a.notes == b.notes);
    RenderSettings settings;
    settings.threads = 1;
    settings.progress = false;
    const RenderResult ra = render_scene(a, RayCastingModel(a, {}), 2, settings);
    const RenderResult rb = render_scene(b, RayCastingModel(b, {}), 2, settings);
    for (size_t i = 0; i < ra.image.pixels.size(); ++i)
        ASSERT_EQ(ra.image.pixels[i], rb.image.pixels[i]) << "pixel " << i;
}

// Slightly negative texels (down to -0.01, before the strength) are set to 0, and the scene has
// one note naming the file, how many texels, and the lowest value. Clamped by hand, the same map.
TEST(EnvironmentMapFile, SlightlyNegativeTexelsAreSetToZeroWithOneNote) {
    Image map = varied_map(8, 4);
    map.at(1, 0).x = -0.004f;
    map.at(2, 1).y = -0.001f;
    map.at(2, 1).z = -0.002f;
    map.at(5, 3).z = -0.0005f;
    const std::string flawed = map_scratch("flawed.exr"), clean = map_scratch("clean.exr");
    write_exr(map, flawed);
    for (Color& c : map.pixels) c = glm::max(c, Color(0.0f));
    write_exr(map, clean);
    const Scene a = build_scene(parse_scene_string(scene_with_map(flawed), "flawed.toml"));
    const Scene b = build_scene(parse_scene_string(scene_with_map(clean), "clean.toml"));
    const std::vector<std::string> notes = notes_naming(a, flawed);
    ASSERT_EQ(notes.size(), 1u) << ::testing::PrintToString(a.notes);
    EXPECT_NE(notes[0].find(": 3 texel(s)"), std::string::npos) << notes[0];
    EXPECT_NE(notes[0].find("the lowest -0.004"), std::string::npos) << notes[0];
    EXPECT_NE(notes[0].find("set to 0"), std::string::npos) << notes[0];
    EXPECT_TRUE(notes_naming(b, clean).empty());
    EXPECT_EQ(a.notes.size(), b.notes.size() + 1);
    ASSERT_TRUE(a.environment_map && b.environment_map);
    for (const Vec3& d : directions(4000)) {
        ASSERT_EQ(a.environment_map->radiance(d), b.environment_map->radiance(d));
        ASSERT_EQ(a.environment_map->pdf(d), b.environment_map->pdf(d));
    }
}

// The tolerance's edge, texel by texel: -0.01 is clamped, just below it is refused, as are NaN
// and infinity, each naming the texel (column, row).
TEST(EnvironmentMapFile, TheToleranceIsMinusOneHundredthAndNaNIsNeverClamped) {
    std::vector<Color> texels(8, Color(0.5f));
    texels[5] = Color(0.5f, -kNegativeTexelTolerance, 0.0f);
    const ClampedTexels clamped = clamp_negative_texels(texels, 4);
    EXPECT_EQ(clamped.texels, 1u);
    EXPECT_EQ(clamped.minimum, -0.01f);
    EXPECT_EQ(texels[5], Color(0.5f, 0.0f, 0.0f));
    for (const float bad : {std::nextafter(-0.01f, -1.0f), -0.5f, NAN, -INFINITY, INFINITY}) {
        std::vector<Color> t(8, Color(0.5f));
        t[6].z = bad;
        try {
            clamp_negative_texels(t, 4);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("texel (2, 1)"), std::string::npos) << e.what();
        }
    }
}

// In a scene: a NaN texel and one far below the tolerance are refused, naming the scene's line
// and field, the map and the texel.
TEST(EnvironmentMapFile, NanAndLargeNegativeTexelsAreRefused) {
    struct Case {
        float value;
        const char* expected;
    };
    for (const Case& c : {Case{NAN, "not finite"}, Case{-0.5f, "negative beyond the tolerance"},
                          Case{-0.0101f, "negative beyond the tolerance"}}) {
        Image map = varied_map(8, 4);
        map.at(6, 2).y = c.value;
        const std::string path = map_scratch("bad.exr");
        write_exr(map, path);
        try {
            build_scene(parse_scene_string(scene_with_map(path), "bad.toml"));
            ADD_FAILURE() << c.value << " was accepted";
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("bad.toml:17: background.map: " + path + ": texel (6, 2)"),
                      std::string::npos)
                << what;
            EXPECT_NE(what.find(c.expected), std::string::npos) << what;
        }
    }
}

namespace {

// A unit cube as six quads, each with four vertices of its own (24 in all), as exporters write
// meshes whose faces have their own normals: closed, although no two faces share an index.
std::string cube_of_separate_faces() {
    const int faces[6][4][3] = {
        {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
        {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
        {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}};
    std::string vertices = "vertices = [", indices = "faces = [";
    for (int f = 0; f < 6; ++f) {
        for (int k = 0; k < 4; ++k)
            vertices += "[" + std::to_string(faces[f][k][0]) + ", " +
                        std::to_string(faces[f][k][1]) + ", " + std::to_string(faces[f][k][2]) +
                        "]" + (f == 5 && k == 3 ? "" : ", ");
        indices += "[" + std::to_string(4 * f) + ", " + std::to_string(4 * f + 1) + ", " +
                   std::to_string(4 * f + 2) + ", " + std::to_string(4 * f + 3) + "]" +
                   (f == 5 ? "" : ", ");
    }
    return vertices + "]\n" + indices + "]\n";
}

}  // namespace

TEST(SceneFile, MediaMistakesNameFileLineAndField) {
    // After the head and the sphere, lines 19 and 20; after the head alone, 13 and 14.
    const std::string fog = "[media.fog]\ntype = \"homogeneous\"\n";
    const std::string tetrahedron =
        "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]\n"
        "faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]\n";
    const std::vector<BadCase> cases = {
        {"valid", kValidHead + kSphere + fog + "sigma_s = [1, 1, 1]\n", 0, "", "(no error)"},
        {"type", kValidHead + kSphere + "[media.fog]\ntype = \"homogenous\"\nsigma_s = [1,1,1]\n",
         20, "media.fog.type", "did you mean 'homogeneous'"},
        {"no coefficient", kValidHead + kSphere + fog, 19, "media.fog.sigma_s", "missing"},
        {"negative", kValidHead + kSphere + fog + "sigma_a = [0.1, -1, 0]\n", 21,
         "media.fog.sigma_a", "must not be negative"},
        {"nan", kValidHead + kSphere + fog + "sigma_s = [nan, 0, 0]\n", 21, "media.fog.sigma_s",
         "finite"},
        {"huge", kValidHead + kSphere + fog + "sigma_s = [1e30, 0, 0]\n", 21, "media.fog.sigma_s",
         "at most 1e9 per unit length"},
        {"g is 1", kValidHead + kSphere + fog + "sigma_s = [1, 1, 1]\ng = 1\n", 22, "media.fog.g",
         "must be in [-0.999, 0.999]"},
        {"g rounds to 1", kValidHead + kSphere + fog + "sigma_s = [1, 1, 1]\ng = 0.99999999\n", 22,
         "media.fog.g", "must be in [-0.999, 0.999]"},
        {"g is -1", kValidHead + kSphere + fog + "sigma_s = [1, 1, 1]\ng = -1.0\n", 22,
         "media.fog.g", "must be in [-0.999, 0.999]"},
        {"short colour", kValidHead + kSphere + fog + "sigma_s = [1, 1]\n", 21, "media.fog.sigma_s",
         "expected [r, g, b]"},
        {"medium after a table", kValidHead + kSphere + fog + "sigma_s = [1, 1, 1]\n" +
                                     "[[shapes]]\ntype = \"sphere\"\nmaterial = \"white\"\n"
                                     "center = [0, 0, 0]\nradius = 1\nmedium = \"fog\"\n",
         27, "shapes[1].medium", "belongs to the top level"},
        {"interior of a glTF shape",
         kValidHead + fog + "sigma_s = [1, 1, 1]\n[[shapes]]\ntype = \"gltf\"\nfile = "
                            "\"x.glb\"\ninterior = \"fog\"\n",
         19, "shapes[0].interior", "is not read for a glTF shape"},
        {"interior empty",
         kValidHead + fog + "sigma_s = [1, 1, 1]\n[[shapes]]\ntype = \"sphere\"\nmaterial = "
                            "\"white\"\ncenter = [0, 0, 0]\nradius = 1\ninterior = \"\"\n",
         21, "shapes[0].interior", "must name a medium"},
        {"unknown field", kValidHead + kSphere + fog + "sigma_s = [1, 1, 1]\nsigma_x = 2\n", 22,
         "media.fog.sigma_x", "did you mean"},
        {"not a table", kValidHead + kSphere + "[media]\nfog = 3\n", 20, "media.fog",
         "expected a table"},
        {"unknown outside medium", "medium = \"fgo\"\n" + kValidHead + kSphere + fog +
                                       "sigma_s = [1, 1, 1]\n",
         1, "medium", "unknown medium 'fgo'; did you mean 'fog'"},
        {"no media at all", "medium = \"fog\"\n" + kValidHead + kSphere, 1, "medium",
         "the scene defines no [media.*]"},
        {"interior unknown",
         kValidHead + fog + "sigma_s = [1, 1, 1]\n[[shapes]]\ntype = \"sphere\"\nmaterial = "
                            "\"white\"\ncenter = [0, 0, 0]\nradius = 1\ninterior = \"milk\"\n",
         21, "shapes[0].interior", "unknown medium 'milk'"},
        {"interior of a quad",
         kValidHead + fog + "sigma_s = [1, 1, 1]\n[[shapes]]\ntype = \"quad\"\nmaterial = "
                            "\"white\"\ncorner = [0, 0, 0]\nedge_u = [1, 0, 0]\nedge_v = [0, 1, "
                            "0]\ninterior = \"fog\"\n",
         22, "shapes[0].interior", "not a closed surface"},
        {"closed mesh",
         kValidHead + fog + "sigma_s = [1, 1, 1]\n[[shapes]]\ntype = \"mesh\"\nmaterial = "
                            "\"white\"\ninterior = \"fog\"\n" + tetrahedron,
         0, "", "(no error)"},
        {"closed mesh of repeated positions",  // a cube whose faces each have their own corners
         kValidHead + fog + "sigma_s = [1, 1, 1]\n[[shapes]]\ntype = \"mesh\"\nmaterial = "
                            "\"white\"\ninterior = \"fog\"\n" + cube_of_separate_faces(),
         0, "", "(no error)"},
        {"open mesh",
         kValidHead + fog + "sigma_s = [1, 1, 1]\n[[shapes]]\ntype = \"mesh\"\nmaterial = "
                            "\"white\"\ninterior = \"fog\"\n"
                            "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]\n"
                            "faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2]]\n",
         19, "shapes[0].interior", "the mesh is not closed"},
    };
    for (const BadCase& c : cases) {
        const std::string error = error_of(c.text);
        SCOPED_TRACE(c.name + ": " + error);
        if (c.message == "(no error)") {
            EXPECT_EQ(error, "(no error)");
            continue;
        }
        const std::string where = "bad.toml:" + std::to_string(c.line) + ": ";
        EXPECT_EQ(error.rfind(where, 0), 0u) << "expected to start with " << where;
        EXPECT_NE(error.find(": " + c.field + ": "), std::string::npos) << "field " << c.field;
        EXPECT_NE(error.find(c.message), std::string::npos) << "expected " << c.message;
        EXPECT_EQ(error.find('\n'), std::string::npos) << "one line";
    }
}

TEST(SceneFile, MediaFillSpaceAndTheInsidesOfClosedShapes) {
    const std::string text = "medium = \"fog\"\n" + kValidHead + R"(
[media.fog]
type = "homogeneous"
sigma_a = [0.01, 0.02, 0.03]
sigma_s = [0.1, 0.1, 0.1]
g = 0.3

[media.milk]
type = "homogeneous"
sigma_s = [40, 35, 30]
g = 0.8

[media.unused]
type = "homogeneous"
sigma_a = [1, 1, 1]

[[shapes]]
type = "sphere"
material = "white"
center = [0, 0, 0]
radius = 1
interior = "milk"

[[shapes]]
type = "quad"
material = "white"
corner = [-5, -1, -5]
edge_u = [0, 0, 10]
edge_v = [10, 0, 0]

[[shapes]]
type = "box"
material = "white"
min = [2, -1, 0]
max = [3, 0, 1]
interior = "milk"
)";
    const Scene scene = build_scene(parse_scene_string(text, "media.toml"));
    ASSERT_EQ(scene.media().size(), 3u);
    ASSERT_TRUE(scene.outside_medium().has_value());
    const Medium& fog = scene.media()[*scene.outside_medium()];
    EXPECT_EQ(fog.name, "fog");
    EXPECT_EQ(fog.sigma_a, Color(0.01f, 0.02f, 0.03f));
    EXPECT_EQ(fog.sigma_s, Color(0.1f));
    EXPECT_FLOAT_EQ(fog.g, 0.3f);
    const std::optional<uint32_t> in_sphere = scene.interior_of(PrimRef(ShapeKind::Sphere, 0));
    ASSERT_TRUE(in_sphere.has_value());
    EXPECT_EQ(scene.media()[*in_sphere].name, "milk");
    EXPECT_FALSE(scene.interior_of(PrimRef(ShapeKind::Quad, 0)).has_value());  // the floor
    for (uint32_t face = 1; face <= 6; ++face) {                               // the box's six
        const std::optional<uint32_t> in_box = scene.interior_of(PrimRef(ShapeKind::Quad, face));
        ASSERT_TRUE(in_box.has_value()) << face;
        EXPECT_EQ(*in_box, *in_sphere);
    }
    EXPECT_TRUE(scene.contents().media);
    // The summary names the media in use, not the unused one.
    const std::string summary = scene.media_summary();
    EXPECT_NE(summary.find("fog (fills space"), std::string::npos) << summary;
    EXPECT_NE(summary.find("milk (inside 2 shape(s)"), std::string::npos) << summary;
    EXPECT_EQ(summary.find("unused"), std::string::npos) << summary;

    // A scene that only defines media, or whose medium is a vacuum, has none to speak of.
    const Scene defined_only = build_scene(parse_scene_string(
        kValidHead + kSphere + "[media.fog]\ntype = \"homogeneous\"\nsigma_s = [1, 1, 1]\n",
        "defined.toml"));
    EXPECT_FALSE(defined_only.contents().media);
    const Scene vacuum = build_scene(parse_scene_string(
        "medium = \"air\"\n" + kValidHead + kSphere +
            "[media.air]\ntype = \"homogeneous\"\nsigma_s = [0, 0, 0]\n",
        "vacuum.toml"));
    EXPECT_FALSE(vacuum.contents().media);
    EXPECT_TRUE(vacuum.media_summary().empty());
}
