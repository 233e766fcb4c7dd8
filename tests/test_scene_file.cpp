// Scene files: every error names file, line and field; valid files build the scene they say.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "input_error.h"
#include "mesh_file.h"
#include "scene_file.h"

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
             "[[lights]]\ntype = \"spot\"\nposition = [0,0,0]\n"
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
