// Image textures (materials/material.h, io/texture.h): bilinear lookup at texel centres and
// edges, sRGB decoding on the standard curve, a flat texture rendering exactly as the same
// colour, and the texels a reflectance may not have.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "01_ray_casting/ray_casting.h"
#include "io/image.h"
#include "io/input_error.h"
#include "io/scene_file.h"
#include "io/texture.h"
#include "render/progressive.h"

using namespace lessons;

namespace {

std::string scratch(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / "lessons_texture_tests";
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

ImageTexture two_by_two() {
    ImageTexture t;
    t.width = t.height = 2;
    // Top row first: (0,0) red, (1,0) green; bottom row (0,1) blue, (1,1) white.
    t.texels = {Color(1, 0, 0), Color(0, 1, 0), Color(0, 0, 1), Color(1, 1, 1)};
    return t;
}

void expect_color(const Color& a, const Color& b, float tolerance = 1e-6f) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

std::string scene_with_albedo(const std::string& albedo) {
    return R"([image]
width = 20
height = 16
[camera]
position = [0, 0, -4]
look_at = [0, 0, 0]
fov = 40
[materials.wall]
type = "diffuse"
albedo = )" +
           albedo + R"(
[[shapes]]
type = "quad"
material = "wall"
corner = [-1, -1, 0]
edge_u = [0, 2, 0]
edge_v = [2, 0, 0]
[[lights]]
type = "point"
position = [0.3, 0.5, -2]
intensity = [3, 3, 3]
)";
}

}  // namespace

TEST(Texture, BilinearAtTexelCentresAndEdges) {
    const ImageTexture t = two_by_two();
    // Texel (i, j) is centred at u = (i + 0.5) / 2, v = 1 - (j + 0.5) / 2 (row 0 is the top).
    for (bool repeat : {false, true}) {
        expect_color(t.lookup({0.25f, 0.75f}, repeat), Color(1, 0, 0));
        expect_color(t.lookup({0.75f, 0.75f}, repeat), Color(0, 1, 0));
        expect_color(t.lookup({0.25f, 0.25f}, repeat), Color(0, 0, 1));
        expect_color(t.lookup({0.75f, 0.25f}, repeat), Color(1, 1, 1));
        // The middle: the mean of all four.
        expect_color(t.lookup({0.5f, 0.5f}, repeat), Color(0.5f, 0.5f, 0.5f));
    }
    // At the left edge, between the two left centres: clamped, the left column alone...
    expect_color(t.lookup({0.0f, 0.75f}, false), Color(1, 0, 0));
    // ...repeated, halfway to the right column's texel across the seam.
    expect_color(t.lookup({0.0f, 0.75f}, true), Color(0.5f, 0.5f, 0));
    // Repeat tiles: u + 3 is u.
    expect_color(t.lookup({3.25f, -1.25f}, true), t.lookup({0.25f, 0.75f}, true));
}

TEST(Texture, EightBitFilesAreDecodedByTheSrgbCurve) {
    const std::string path = scratch("ramp.png");
    // Four texels of 0, 10, 128 and 255 in every channel.
    std::vector<uint8_t> rgb;
    for (int v : {0, 10, 128, 255})
        for (int c = 0; c < 3; ++c) rgb.push_back(static_cast<uint8_t>(v));
    write_png_bytes(path, 4, 1, rgb);
    const auto t = read_texture(path, 1 << 20);
    ASSERT_EQ(t->width, 4);
    // The sRGB curve (IEC 61966-2-1): c / 12.92 below 0.04045, else ((c + 0.055) / 1.055)^2.4.
    EXPECT_EQ(t->texels[0].x, 0.0f);
    EXPECT_NEAR(t->texels[1].x, (10.0 / 255.0) / 12.92, 1e-7);
    EXPECT_NEAR(t->texels[2].x, std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4), 1e-6);
    EXPECT_NEAR(t->texels[2].x, 0.21586, 1e-5);
    EXPECT_EQ(t->texels[3].x, 1.0f);
}

TEST(Texture, AFlatTextureRendersExactlyAsTheSameColour) {
    const std::string path = scratch("flat.png");
    write_png_bytes(path, 3, 2, std::vector<uint8_t>(18, 150));
    const float d = srgb_decode(150.0f / 255.0f);
    char colour[80];
    std::snprintf(colour, sizeof colour, "[%.9g, %.9g, %.9g]", d, d, d);
    const Scene textured = build_scene(
        parse_scene_string(scene_with_albedo("{ texture = \"" + path + "\" }"), "tex.toml"));
    const Scene plain = build_scene(parse_scene_string(scene_with_albedo(colour), "plain.toml"));
    RenderSettings settings;
    settings.threads = 1;
    settings.progress = false;
    const RenderResult a = render_scene(textured, RayCastingModel(textured, {}), 2, settings);
    const RenderResult b = render_scene(plain, RayCastingModel(plain, {}), 2, settings);
    int lit = 0;
    for (size_t i = 0; i < a.image.pixels.size(); ++i) {
        ASSERT_EQ(a.image.pixels[i], b.image.pixels[i]) << "pixel " << i;
        lit += a.image.pixels[i].x > 0.0f;
    }
    EXPECT_GT(lit, 100);
}

TEST(Texture, ExrTexturesAreLinearAndTheirTexelsChecked) {
    const std::string good = scratch("linear.exr"), bright = scratch("bright.exr"),
                      nan = scratch("nan.exr");
    Image image(2, 1);
    image.pixels = {Color(0.25f, 0.5f, 0.75f), Color(0.1f)};
    write_exr(image, good);
    const auto t = read_texture(good, 1 << 20);
    expect_color(t->texels[0], Color(0.25f, 0.5f, 0.75f));  // no sRGB curve for EXR
    expect_color(t->mean, Color(0.175f, 0.3f, 0.425f));
    image.pixels[1] = Color(1.5f, 0.2f, 0.2f);
    write_exr(image, bright);
    image.pixels[1] = Color(NAN, 0.2f, 0.2f);
    write_exr(image, nan);
    for (const std::string& bad : {bright, nan}) {
        try {
            read_texture(bad, 1 << 20);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("texel (1, 0)"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("in [0, 1]"), std::string::npos) << e.what();
        }
    }
    // In a scene, the error names the scene's line and field too.
    try {
        build_scene(parse_scene_string(scene_with_albedo("{ texture = \"" + bright + "\" }"),
                                       "bright.toml"));
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("bright.toml:10: materials.wall.albedo: "),
                  std::string::npos)
            << e.what();
    }
}

// A Radiance .hdr texture is linear, as an EXR (no sRGB curve), its texels within RGBE's
// precision of the values written (one unit of the 8-bit mantissa), and checked as an EXR's.
TEST(Texture, HdrTexturesAreLinearAndTheirTexelsChecked) {
    const std::string good = scratch("linear.hdr"), bright = scratch("bright.hdr");
    float texels[6] = {0.25f, 0.5f, 0.75f, 0.1f, 0.1f, 0.1f};
    ASSERT_TRUE(stbi_write_hdr(good.c_str(), 2, 1, 3, texels));
    const auto t = read_texture(good, 1 << 20);
    ASSERT_EQ(t->width, 2);
    // 0.75 and 0.1 have exponents 0 and -3: units of 2^-8 and 2^-11 (0.25 and 0.5 are exact).
    expect_color(t->texels[0], Color(0.25f, 0.5f, 0.75f), 0x1p-8f);
    expect_color(t->texels[1], Color(0.1f), 0x1p-11f);
    EXPECT_EQ(t->texels[0].x, 0.25f);  // not 0.05, its sRGB decoding
    texels[3] = 1.5f;
    ASSERT_TRUE(stbi_write_hdr(bright.c_str(), 2, 1, 3, texels));
    try {
        read_texture(bright, 1 << 20);
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("texel (1, 0)"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("in [0, 1]"), std::string::npos) << e.what();
    }
    // In a scene, a damaged one names the scene's line and field and the file.
    std::string bytes;
    {
        std::ifstream in(good, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const std::string cut = scratch("cut.hdr");
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 3);
    try {
        build_scene(
            parse_scene_string(scene_with_albedo("{ texture = \"" + cut + "\" }"), "cut.toml"));
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("cut.toml:10: materials.wall.albedo: "), std::string::npos) << what;
        EXPECT_NE(what.find(cut + ": "), std::string::npos) << what;
        EXPECT_NE(what.find("(truncated?)"), std::string::npos) << what;
    }
}

// An OBJ's map_Kd is read from the OBJ's folder and maps onto the albedo (replacing Kd); two
// materials naming one image share it.
TEST(Texture, ObjMapKdBecomesTheAlbedoTexture) {
    const std::string dir = scratch("obj");
    std::filesystem::create_directories(dir);
    write_png_bytes(dir + "/wood.png", 2, 2, std::vector<uint8_t>(12, 200));
    std::FILE* mtl = std::fopen((dir + "/wood.mtl").c_str(), "w");
    std::fprintf(mtl,
                 "newmtl wood\nKd 0.8 0.8 0.8\nmap_Kd wood.png\n"
                 "newmtl wood2\nKd 0.5 0.5 0.5\nmap_Kd wood.png\n");
    std::fclose(mtl);
    std::FILE* obj = std::fopen((dir + "/plank.obj").c_str(), "w");
    std::fprintf(obj,
                 "mtllib wood.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\n"
                 "vt 0 1\nusemtl wood\nf 1/1 2/2 3/3\nusemtl wood2\nf 2/2 4/1 3/3\n");
    std::fclose(obj);
    const std::string text = scene_with_albedo("[0.5, 0.5, 0.5]") +
                             "[[shapes]]\ntype = \"mesh\"\nfile = \"" + dir + "/plank.obj\"\n";
    const Scene scene = build_scene(parse_scene_string(text, "obj.toml"));
    std::vector<const Material*> textured;
    for (const Material& m : scene.materials())
        if (m.albedo.image) textured.push_back(&m);
    ASSERT_EQ(textured.size(), 2u);
    EXPECT_EQ(textured[0]->albedo.image, textured[1]->albedo.image);  // read once
    expect_color(textured[0]->albedo.eval({0.3f, 0.3f}), Color(srgb_decode(200.0f / 255.0f)));
}
