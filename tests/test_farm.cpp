// The farm's core (docs/farm.md): film sums that do not depend on the order or the split of the
// samples, parts saved and read back exactly, and what a set of parts covers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "01_ray_casting/ray_casting.h"
#include "farm/merge_parts.h"
#include "farm/part.h"
#include "io/image.h"
#include "io/input_error.h"
#include "io/scene_file.h"
#include "render/render.h"
#include "test_util.h"

using namespace lessons;

namespace {

bool same_pixel(const FilmPixel& a, const FilmPixel& b) {
    return a.sum[0] == b.sum[0] && a.sum[1] == b.sum[1] && a.sum[2] == b.sum[2] &&
           a.valid == b.valid && a.nan == b.nan && a.inf == b.inf && a.clamped == b.clamped &&
           a.max_luminance == b.max_luminance;
}

// Samples over many orders of magnitude, some negative (a layer may be), some tiny.
std::vector<Color> awkward_samples(int n, uint32_t seed) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<float> exponent(-40.0f, 40.0f), sign(0.0f, 1.0f);
    std::vector<Color> v;
    for (int i = 0; i < n; ++i) {
        Color c;
        for (int k = 0; k < 3; ++k)
            c[k] = (sign(gen) < 0.2f ? -1.0f : 1.0f) * std::exp2(exponent(gen));
        v.push_back(c);
    }
    return v;
}

PartFile header_only(const std::string& name, int x0, int x1, int y0, int y1, int a, int b) {
    PartFile p;
    p.path = name;
    p.header.image_width = 8;
    p.header.image_height = 4;
    p.header.x0 = x0;
    p.header.x1 = x1;
    p.header.y0 = y0;
    p.header.y1 = y1;
    p.header.sample_begin = a;
    p.header.sample_end = b;
    p.header.planned_end = b;
    return p;
}

}  // namespace

TEST(Farm, FilmSumsDoNotDependOnTheOrderOrTheSplitOfTheSamples) {
    const std::vector<Color> samples = awkward_samples(1000, 7);
    Film in_order(1, 1);
    for (const Color& c : samples) in_order.add_sample(0, c);
    std::vector<Color> shuffled = samples;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(3));
    Film reversed(1, 1), merged(1, 1);
    for (const Color& c : shuffled) reversed.add_sample(0, c);
    for (int split : {0, 1, 333, 999}) {
        Film a(1, 1), b(1, 1);
        for (int i = 0; i < 1000; ++i) (i < split ? a : b).add_sample(0, shuffled[i]);
        b.add(a);
        EXPECT_TRUE(same_pixel(b.pixels()[0], in_order.pixels()[0])) << "split at " << split;
        EXPECT_EQ(b.mean().pixels[0], in_order.mean().pixels[0]);
    }
    EXPECT_TRUE(same_pixel(reversed.pixels()[0], in_order.pixels()[0]));
    EXPECT_EQ(reversed.mean().pixels[0], in_order.mean().pixels[0]);
}

TEST(Farm, FilmSumsAreExactWhereADoubleSumIsNot) {
    // 2^40 + 2^-20 - 2^40: a double sum loses the small sample (it is below the double's
    // resolution at 2^40, 2^-12); the fixed-point sum keeps it.
    Film film(1, 1);
    film.add_sample(0, Color(0x1p40f));
    film.add_sample(0, Color(0x1p-20f));
    film.add_sample(0, Color(-0x1p40f));
    double d = 0x1p40;
    d += 0x1p-20;
    d -= 0x1p40;
    EXPECT_EQ(d, 0.0);  // the double sum loses it
    EXPECT_EQ(film.mean().pixels[0].x, static_cast<float>(0x1p-20 / 3.0));
}

TEST(Farm, ASampleTooLargeToSumExactlyIsCountedAsInfinite) {
    Film film(1, 1);
    film.add_sample(0, Color(1.0f));
    film.add_sample(0, Color(0x1p54f, 0.0f, 0.0f));
    film.add_sample(0, Color(0x1p53f));
    EXPECT_EQ(film.inf_samples(), 1u);
    EXPECT_EQ(film.pixels()[0].valid, 2u);
    EXPECT_EQ(film.mean().pixels[0].x, static_cast<float>((0x1p53 + 1.0) / 2.0));
}

TEST(Farm, CropsAndSampleRangesRenderedApartAddUpToTheWholeRender) {
    const Scene scene =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {24, 16});
    const test::FunctionModel radiance([&scene](const Ray& ray, Rng& rng) {
        return ray_cast(scene, ray, {}) * (0.5f + rng.uniform());
    });
    RenderSettings settings;
    settings.progress = false;
    settings.seed = 5;
    Film whole(24, 16);
    test::render_film(scene.camera, whole, settings, radiance, 0, 6);
    Film merged(24, 16);
    for (const auto& [x0, x1, y0, y1] :
         std::vector<std::array<int, 4>>{{0, 10, 0, 16}, {10, 24, 0, 5}, {10, 24, 5, 16}})
        for (const auto& [a, b] : std::vector<std::pair<int, int>>{{0, 2}, {2, 6}}) {
            Film crop(x1 - x0, y1 - y0);
            RenderSettings s = settings;
            s.image_width = 24;
            s.image_height = 16;
            s.crop_x = x0;
            s.crop_y = y0;
            test::render_film(scene.camera, crop, s, radiance, a, b);
            merged.add_window(crop, x0, y0);
        }
    const Image w = whole.mean(), m = merged.mean();
    for (size_t i = 0; i < w.pixels.size(); ++i) ASSERT_EQ(w.pixels[i], m.pixels[i]) << i;
}

TEST(Farm, APartIsReadBackExactly) {
    Film image(5, 3), layer(5, 3);
    const std::vector<Color> samples = awkward_samples(60, 11);
    for (size_t i = 0; i < samples.size(); ++i) {
        image.add_sample(i % 15, samples[i]);
        layer.add_sample(i % 15, 0.5f * samples[i]);
    }
    image.add_sample(2, Color(NAN));
    image.add_sample(3, Color(INFINITY));
    PartHeader h;
    h.lesson = "04_rendering_equation";
    h.scene = "scenes/x.toml";
    h.scene_hash = "0123456789abcdef";
    h.options = "--clamp=\n--plain=true";
    h.seed = 42;
    h.image_width = 20;
    h.image_height = 10;
    h.x0 = 15;
    h.x1 = 20;
    h.y0 = 7;
    h.y1 = 10;
    h.sample_begin = 3;
    h.sample_end = 7;
    h.planned_end = 9;
    h.films = {"image", "bounce1"};
    h.seconds = 1.25;
    h.rays = 123456789012ull;
    h.threads = 2;
    h.exposure = -1.5f;
    h.notes = {"a note", "another"};
    const std::string path =
        (std::filesystem::temp_directory_path() / "lessons_test_part.exr").string();
    write_part(path, h, std::vector<Film>{image, layer});
    const PartFile p = read_part(path);
    std::filesystem::remove(path);
    EXPECT_EQ(p.header.lesson, h.lesson);
    EXPECT_EQ(p.header.options, h.options);
    EXPECT_EQ(p.header.seed, 42u);
    EXPECT_EQ(p.header.pixels_text(), "15:20,7:10");
    EXPECT_EQ(p.header.samples_text(), "3:7");
    EXPECT_TRUE(p.header.partial());
    EXPECT_EQ(p.header.films, h.films);
    EXPECT_EQ(p.header.rays, h.rays);
    EXPECT_EQ(p.header.seconds, 1.25);
    EXPECT_EQ(p.header.exposure, -1.5f);
    EXPECT_EQ(p.header.notes, h.notes);
    EXPECT_TRUE(p.header.bias.empty());
    ASSERT_EQ(p.films.size(), 2u);
    for (size_t i = 0; i < 15; ++i) {
        EXPECT_TRUE(same_pixel(p.films[0].pixels()[i], image.pixels()[i])) << i;
        EXPECT_TRUE(same_pixel(p.films[1].pixels()[i], layer.pixels()[i])) << i;
        EXPECT_EQ(p.films[0].pixels()[i].sum_squares, image.pixels()[i].sum_squares);
    }
}

// A lesson writes parts with ZIP: a part in another codec was not written by a lesson, and is
// refused before it is decoded.
TEST(Farm, APartInAnotherCodecIsRefusedBeforeDecoding) {
    Film image(4, 1);  // one line: one chunk in any codec
    for (int i = 0; i < 4; ++i) image.add_sample(i, Color(0.5f * i));
    PartHeader h;
    h.lesson = "01_ray_casting";
    h.scene = "scenes/x.toml";
    h.scene_hash = "0123456789abcdef";
    h.image_width = 4;
    h.image_height = 1;
    h.x1 = 4;
    h.y1 = 1;
    h.sample_end = h.planned_end = 1;
    h.films = {"image"};
    const std::string path =
        (std::filesystem::temp_directory_path() / "lessons_test_part_codec.exr").string();
    write_part(path, h, std::vector<Film>{image});
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const std::string attribute("compression\0compression\0\1\0\0\0", 28);
    const size_t at = bytes.find(attribute);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(bytes[at + attribute.size()], 3);  // ZIP
    EXPECT_EQ(read_part(path).films.size(), 1u);
    bytes[at + attribute.size()] = 1;  // RLE
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    try {
        read_part(path);
        ADD_FAILURE() << "expected an error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "compression") << e.what();
    }
    std::filesystem::remove(path);
}

TEST(Farm, CoverageNamesTheMissingPiecesAndTheSamplesReached) {
    // An 8x4 image: the left half has samples 0:4 and 4:6, the right half 0:4 only.
    const std::vector<PartFile> parts{header_only("a", 0, 8, 0, 4, 0, 4),
                                      header_only("b", 0, 4, 0, 4, 4, 6)};
    const Coverage c = part_coverage(parts, 0);
    EXPECT_EQ(c.target, 6);
    EXPECT_EQ(c.spp_min, 4);
    EXPECT_EQ(c.spp_max, 6);
    EXPECT_DOUBLE_EQ(c.fraction, (4.0 * 32 + 2.0 * 16) / (6.0 * 32));
    ASSERT_EQ(c.missing.size(), 1u);
    EXPECT_EQ(c.missing[0], "samples 4:6 of pixels 4:8,0:4");
    EXPECT_TRUE(part_coverage({header_only("a", 0, 8, 0, 4, 0, 4)}, 4).complete());
    EXPECT_EQ(part_coverage({header_only("a", 0, 8, 0, 4, 2, 4)}, 4).missing.at(0),
              "samples 0:2 of pixels 0:8,0:4");
}

TEST(Farm, PartsHoldingTheSameSamplesOfAPixelAreRefused) {
    EXPECT_NO_THROW(check_parts_disjoint({header_only("a", 0, 4, 0, 4, 0, 4),
                                          header_only("b", 4, 8, 0, 4, 0, 4),
                                          header_only("c", 0, 8, 0, 4, 4, 8)}));
    try {
        check_parts_disjoint(
            {header_only("a", 0, 5, 0, 4, 0, 4), header_only("b", 4, 8, 0, 4, 3, 8)});
        FAIL() << "overlap not refused";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("holds samples 3:4 of pixels 4:5,0:4"),
                  std::string::npos)
            << e.what();
    }
}

TEST(Farm, PairsOfNumbersAreReadStrictly) {
    long long a = 0, b = 0;
    EXPECT_TRUE(parse_pair("0:8", ':', a, b));
    EXPECT_EQ(a, 0);
    EXPECT_EQ(b, 8);
    EXPECT_TRUE(parse_pair("32x24", 'x', a, b));
    EXPECT_EQ(b, 24);
    for (const char* bad : {"", ":", "1:", ":2", "-1:2", "1:+2", " 1:2", "1:2 ", "1:2:3", "a:b",
                            "99999999999999999999:1", "1;2"})
        EXPECT_FALSE(parse_pair(bad, ':', a, b)) << bad;
}

TEST(Farm, PartsOfOtherBuildsOrCpusAreNamed) {
    std::vector<PartFile> parts{header_only("a", 0, 8, 0, 4, 0, 4),
                                header_only("b", 0, 8, 0, 4, 4, 8)};
    for (PartFile& p : parts) {
        p.header.build = "0123";
        p.header.cpu = "A CPU";
    }
    EXPECT_EQ(mixed_builds(parts), "");
    parts[1].header.cpu = "Another CPU";
    EXPECT_NE(mixed_builds(parts).find("b was made on another CPU (Another CPU)"),
              std::string::npos);
    parts[1].header.build = "4567";
    EXPECT_NE(mixed_builds(parts).find("b was made by another build"), std::string::npos);
}

TEST(Farm, TheTargetIsTheLargestEndAskedForAndPartsPastItAreNamed) {
    std::vector<PartFile> parts{header_only("a", 0, 8, 0, 4, 0, 4)};
    parts[0].header.planned_end = 10;  // interrupted after 4 of 10
    Coverage c = part_coverage(parts, 0);
    EXPECT_EQ(c.target, 10);
    ASSERT_EQ(c.missing.size(), 1u);
    EXPECT_EQ(c.missing[0], "samples 4:10 of pixels 0:8,0:4");
    c = part_coverage(parts, 3);
    ASSERT_EQ(c.beyond.size(), 1u);
    EXPECT_FALSE(c.complete());
    EXPECT_TRUE(part_coverage(parts, 4).complete());
}

namespace {

void write_text(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

// A scene of an OBJ mesh whose MTL names a map_Kd image, beside a quad whose albedo is another
// image, under an environment map: every kind of file a TOML scene loads.
std::string scene_of_every_file_kind(const std::string& dir) {
    std::filesystem::create_directories(dir);
    write_png_bytes(dir + "/wood.png", 2, 2, std::vector<uint8_t>(12, 200));
    write_png_bytes(dir + "/wall.png", 2, 2, std::vector<uint8_t>(12, 100));
    Image sky(4, 2);
    for (size_t i = 0; i < sky.pixels.size(); ++i) sky.pixels[i] = Color(0.1f * float(i + 1));
    write_exr(sky, dir + "/sky.exr");
    write_text(dir + "/wood.mtl",
               "newmtl wood\nKd 0.8 0.8 0.8\nmap_Kd wood.png\n"
               "newmtl plain\nKd 0.5 0.5 0.5\n");
    write_text(dir + "/plank.obj",
               "mtllib wood.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
               "vt 0 0\nvt 1 0\nvt 0 1\nusemtl wood\nf 1/1 2/2 3/3\n"
               "usemtl plain\nf 2/2 4/1 3/3\n");
    write_text(dir + "/scene.toml", R"([image]
width = 8
height = 6
[camera]
position = [0.5, 0.5, -4]
look_at = [0.5, 0.5, 0]
fov = 40
[background]
map = "sky.exr"
[materials.wall]
type = "diffuse"
albedo = { texture = "wall.png" }
[[shapes]]
type = "mesh"
file = "plank.obj"
[[shapes]]
type = "quad"
material = "wall"
corner = [-1, -1, 1]
edge_u = [0, 2, 0]
edge_v = [2, 0, 0]
)");
    return dir + "/scene.toml";
}

std::vector<std::string> file_names(const std::vector<std::string>& paths) {
    std::vector<std::string> names;
    for (const std::string& p : paths)
        names.push_back(std::filesystem::path(p).filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace

// load_scene records every file it reads, the MTL and the images an MTL names included, and the
// farm's scene hash covers each: editing an MTL's colour or its map_Kd image changes the hash.
TEST(Farm, TheSceneHashCoversEveryFileTheSceneWasMadeOf) {
    const std::string dir =
        (std::filesystem::temp_directory_path() / "lessons_farm_scene_files").string();
    std::filesystem::remove_all(dir);
    const std::string path = scene_of_every_file_kind(dir);
    const auto hash = [&] {
        const Scene scene = load_scene(path, {0, 0, {}, 1});
        return std::make_pair(file_names(scene.input_files), scene_files_hash(scene, {}));
    };
    const auto [files, original] = hash();
    EXPECT_EQ(files, (std::vector<std::string>{"plank.obj", "scene.toml", "sky.exr", "wall.png",
                                               "wood.mtl", "wood.png"}));
    EXPECT_EQ(hash().second, original);  // nothing changed, nothing moves

    write_text(dir + "/wood.mtl",
               "newmtl wood\nKd 0.7 0.8 0.8\nmap_Kd wood.png\n"
               "newmtl plain\nKd 0.5 0.5 0.5\n");
    const std::string after_mtl = hash().second;
    EXPECT_NE(after_mtl, original) << "an MTL's colour changed and the hash did not";

    write_png_bytes(dir + "/wood.png", 2, 2, std::vector<uint8_t>(12, 201));
    const std::string after_image = hash().second;
    EXPECT_NE(after_image, after_mtl) << "an MTL's map_Kd image changed and the hash did not";

    write_png_bytes(dir + "/wall.png", 2, 2, std::vector<uint8_t>(12, 101));
    EXPECT_NE(hash().second, after_image) << "a scene texture changed and the hash did not";
    std::filesystem::remove_all(dir);
}

// A glTF file's buffers and images are among the files its scene was made of, whether the glTF
// is the whole scene or placed by a TOML scene.
TEST(Farm, AGltfSceneRecordsItsImages) {
    const std::string gltf = std::string(LESSONS_SOURCE_DIR) + "/tests/gltf/cubes.gltf";
    const Scene whole = load_scene(gltf, {0, 0, {}, 1});
    EXPECT_EQ(file_names(whole.input_files), (std::vector<std::string>{"cubes.gltf", "tiles.png"}));
    const Scene placed = load_scene(
        std::string(LESSONS_SOURCE_DIR) + "/tests/gltf/cubes_placed.toml", {0, 0, {}, 1});
    const std::vector<std::string> names = file_names(placed.input_files);
    for (const char* name : {"cubes_placed.toml", "cubes.gltf", "tiles.png"})
        EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
}
