// End to end: the lesson executables on the shipped scenes, and on bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/image.h"
#include "io/report.h"
#include "lesson_registry.h"

namespace fs = std::filesystem;

namespace {

const std::string kSource = LESSONS_SOURCE_DIR;
const std::string kBin = LESSONS_BIN_DIR;

struct RunResult {
    int exit_code;
    std::string output;  // stdout and stderr
};

RunResult run(const std::string& args) {
    // One log per call and process: ctest runs tests in parallel.
    static int calls = 0;
    const fs::path log = fs::temp_directory_path() / ("lessons_cli_" + std::to_string(getpid()) +
                                                      "_" + std::to_string(++calls) + ".log");
    const std::string command = args + " > " + log.string() + " 2>&1";
    const int status = std::system(command.c_str());
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    fs::remove(log);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

std::string read_file(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

fs::path fresh_dir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("lessons_cli_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

}  // namespace

class LessonOnScene : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

TEST_P(LessonOnScene, RendersWritesImagesAndAReportWithNoNaN) {
    const auto& [lesson, scene] = GetParam();
    const fs::path dir = fresh_dir("render_" + lesson + scene);
    const std::string exe = kBin + "/" + lesson;
    const RunResult r = run(exe + " --scene " + kSource + "/scenes/" + scene +
                            ".toml --width 64 --height 48 --spp 2 --quiet --out " +
                            (dir / "img").string() + " --report " + (dir / "report.json").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_GT(fs::file_size(dir / "img.exr"), 0u);
    EXPECT_GT(fs::file_size(dir / "img.png"), 0u);
    const std::string report = read_file(dir / "report.json");
    const std::string chapter = "\"chapter\": \"" + lesson + "\"";
    EXPECT_NE(report.find(chapter), std::string::npos) << report;
    for (const char* field :
         {"\"width\": 64", "\"height\": 48", "\"spp\": 2", "\"threads\"", "\"seconds\"", "\"rays\"",
          "\"nan_pixels\": 0", "\"inf_pixels\": 0", "\"scene\""})
        EXPECT_NE(report.find(field), std::string::npos) << field << " in\n" << report;
}

INSTANTIATE_TEST_SUITE_P(
    ShippedScenes, LessonOnScene,
    ::testing::Combine(::testing::ValuesIn(lessons::test::registered_lesson_names()),
                       ::testing::Values("cornell_box", "whitted_1979", "cornell_spheres",
                                         "veach_mis", "quad_light_plane")));

TEST(Cli, BadSceneExitsWithTwoAndOneLineAndWritesNothing) {
    const fs::path dir = fresh_dir("bad");
    std::ofstream(dir / "bad.toml") << "[image]\nwidth = 64\nheight = -1\n";
    const RunResult r = run(kBin + "/01_ray_casting --scene " + (dir / "bad.toml").string() +
                            " --out " + (dir / "img").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("bad.toml:3: image.height: must be between 1 and 16384"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir / "img.exr"));
    EXPECT_FALSE(fs::exists(dir / "img.png"));
}

// A map with a few slightly negative texels renders, and every lesson prints one note naming it
// with how many texels were set to 0 and the lowest value (docs/scene-format.md).
TEST(Cli, AMapsSlightlyNegativeTexelsAreSetToZeroWithOneNote) {
    const fs::path dir = fresh_dir("flawed_map");
    lessons::Image map(8, 4);
    for (lessons::Color& c : map.pixels) c = lessons::Color(0.4f, 0.5f, 0.6f);
    map.at(2, 1).y = -0.004f;
    map.at(6, 3).x = -0.0015f;
    lessons::write_exr(map, (dir / "flawed.exr").string());
    std::ofstream(dir / "s.toml") << "[image]\nwidth = 8\nheight = 6\n[camera]\n"
                                     "position = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n"
                                     "[materials.white]\ntype = \"diffuse\"\n"
                                     "albedo = [0.5, 0.5, 0.5]\n[[shapes]]\ntype = \"sphere\"\n"
                                     "material = \"white\"\ncenter = [0, 0, 0]\nradius = 1\n"
                                     "[background]\nmap = \"flawed.exr\"\n";
    const std::vector<std::string> names = lessons::test::registered_lesson_names();
    ASSERT_GE(names.size(), 6u);
    for (const std::string& lesson : names) {
        const RunResult r = run(kBin + "/" + lesson + " --scene " + (dir / "s.toml").string() +
                                " --spp 1 --out " + (dir / "img").string());
        SCOPED_TRACE(lesson + ":\n" + r.output);
        EXPECT_EQ(r.exit_code, 0);
        int notes = 0;
        std::istringstream lines(r.output);
        for (std::string line; std::getline(lines, line);)
            if (line.find("note: ") != std::string::npos &&
                line.find("flawed.exr") != std::string::npos) {
                ++notes;
                EXPECT_NE(line.find(": 2 texel(s) with channels slightly below 0 (the lowest "
                                    "-0.004;"),
                          std::string::npos);
            }
        EXPECT_EQ(notes, 1);
    }
}

TEST(Cli, WhittedFlagsAreCheckedAndDocumented) {
    EXPECT_EQ(run(kBin + "/02_whitted --fresnel approximate").exit_code, 2);
    EXPECT_EQ(run(kBin + "/02_whitted --max-bounces -1").exit_code, 2);
    // One meaning per flag: --max-depth counts path segments (lessons 4 and 5), not bounces.
    EXPECT_EQ(run(kBin + "/02_whitted --max-depth 3").exit_code, 2);
    const RunResult help = run(kBin + "/02_whitted --help");
    for (const char* flag : {"--max-bounces", "--min-attenuation", "--fresnel", "--ambient"})
        EXPECT_NE(help.output.find(flag), std::string::npos) << flag;
}

TEST(Cli, ReflectionEquationFlagsAreCheckedAndDocumented) {
    EXPECT_EQ(run(kBin + "/03_reflection_equation --estimator stratified").exit_code, 2);
    EXPECT_EQ(run(kBin + "/03_reflection_equation --mis-heuristic max").exit_code, 2);
    const RunResult help = run(kBin + "/03_reflection_equation --help");
    for (const char* word :
         {"--estimator", "uniform", "cosine", "brdf", "light", "mis", "--mis-heuristic"})
        EXPECT_NE(help.output.find(word), std::string::npos) << word;
}

TEST(Cli, PathTracingSaysWhatItCannotRenderAndPointsToLessonFive) {
    const fs::path dir = fresh_dir("lesson4_notes");
    const std::string lesson = kBin + "/04_rendering_equation --width 16 --height 16 --spp 2 ";
    const RunResult whitted =
        run(lesson + "--scene " + kSource + "/scenes/whitted_1979.toml --out " +
            (dir / "w").string() + " --report " + (dir / "w.json").string());
    ASSERT_EQ(whitted.exit_code, 0) << whitted.output;
    const std::string report = read_file(dir / "w.json");
    EXPECT_NE(report.find("\"biased\": true"), std::string::npos) << report;
    EXPECT_NE(report.find("point-light caustics are missing"), std::string::npos) << report;
    EXPECT_NE(report.find("lesson 5"), std::string::npos) << report;
    const RunResult box = run(lesson + "--scene " + kSource + "/scenes/cornell_box.toml --out " +
                              (dir / "c").string() + " --report " + (dir / "c.json").string());
    ASSERT_EQ(box.exit_code, 0) << box.output;
    EXPECT_NE(read_file(dir / "c.json").find("\"biased\": false"), std::string::npos);
    // The bidirectional extension has left lesson 4.
    EXPECT_EQ(run(lesson + "--light-paths").exit_code, 2);
}

TEST(Cli, BidirectionalStrategyImagesAddUpAndItsFlagsAreChecked) {
    const fs::path dir = fresh_dir("lesson5");
    const std::string lesson = kBin + "/05_bidirectional --width 16 --height 16 --spp 2 ";
    const RunResult r =
        run(lesson + "--strategies 2 --scene " + kSource + "/scenes/cornell_spheres.toml --out " +
            (dir / "s").string() + " --report " + (dir / "s.json").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    for (const char* layer : {"s0_t2", "s1_t1", "s0_t3", "s1_t2", "s2_t1", "segments3plus"})
        EXPECT_TRUE(fs::exists(dir / (std::string("s_") + layer + ".exr"))) << layer;
    const std::string report = read_file(dir / "s.json");
    for (const char* field : {"\"splat_bytes\"", "\"biased\": false", "\"layers\""})
        EXPECT_NE(report.find(field), std::string::npos) << field << " in\n" << report;
    // Weighted layers add up to the image: their shares sum to 100%.
    double shares = 0.0;
    for (size_t at = report.find("% of the image"); at != std::string::npos;
         at = report.find("% of the image", at + 1)) {
        const size_t start = report.rfind(' ', at - 1) + 1;
        shares += std::stod(report.substr(start, at - start));
    }
    EXPECT_NEAR(shares, 100.0, 0.1) << report;
    EXPECT_EQ(run(lesson + "--unweighted").exit_code, 2);
    EXPECT_EQ(run(lesson + "--strategies 13").exit_code, 2);
    const RunResult tracing = run(lesson + "--light-tracing --scene " + kSource +
                                  "/scenes/cornell_spheres.toml --out " + (dir / "t").string());
    ASSERT_EQ(tracing.exit_code, 0) << tracing.output;
    EXPECT_NE(tracing.output.find("light tracing cannot show mirrors and glass"), std::string::npos)
        << tracing.output;
    const RunResult help = run(kBin + "/05_bidirectional --help");
    for (const char* flag :
         {"--max-depth", "--roulette-after", "--strategies", "--unweighted", "--light-tracing"})
        EXPECT_NE(help.output.find(flag), std::string::npos) << flag;
}

TEST(Cli, BadFlagsExitWithTwo) {
    EXPECT_EQ(run(kBin + "/01_ray_casting --spp 0").exit_code, 2);
    EXPECT_EQ(run(kBin + "/01_ray_casting --no-such-flag").exit_code, 2);
    EXPECT_EQ(run(kBin + "/01_ray_casting --scene /no/such/scene.toml").exit_code, 2);
    const RunResult help = run(kBin + "/01_ray_casting --help");
    EXPECT_EQ(help.exit_code, 0);
    for (const char* flag : {"--scene", "--out", "--spp", "--width", "--height", "--threads",
                             "--seed", "--report", "--ambient", "--exposure"})
        EXPECT_NE(help.output.find(flag), std::string::npos) << flag;
}

TEST(Cli, SameSeedSameImageAcrossThreadCounts) {
    const fs::path dir = fresh_dir("threads");
    const std::string base = kBin + "/01_ray_casting --scene " + kSource +
                             "/scenes/cornell_box.toml --width 80 --height 60 --spp 3 --quiet ";
    ASSERT_EQ(run(base + "--threads 1 --out " + (dir / "one").string()).exit_code, 0);
    ASSERT_EQ(run(base + "--threads 2 --out " + (dir / "two").string()).exit_code, 0);
    ASSERT_EQ(run(base + "--threads 3 --out " + (dir / "three").string()).exit_code, 0);
    EXPECT_EQ(read_file(dir / "one.exr"), read_file(dir / "two.exr"));
    EXPECT_EQ(read_file(dir / "one.exr"), read_file(dir / "three.exr"));
    // And for a Monte Carlo lesson, whose every sample draws random numbers.
    const std::string mc =
        kBin + "/04_rendering_equation --scene " + kSource +
        "/scenes/cornell_spheres.toml --width 48 --height 48 --spp 4 --quiet --seed 9 ";
    for (int threads : {1, 2, 3})
        ASSERT_EQ(run(mc + "--threads " + std::to_string(threads) + " --out " +
                      (dir / ("mc" + std::to_string(threads))).string())
                      .exit_code,
                  0);
    EXPECT_EQ(read_file(dir / "mc1.exr"), read_file(dir / "mc2.exr"));
    EXPECT_EQ(read_file(dir / "mc1.exr"), read_file(dir / "mc3.exr"));
    // And for lesson 5, whose light tracing splats onto other pixels than its own (an image of
    // more than one tile, so that threads share the work).
    const std::string bidir =
        kBin + "/05_bidirectional --scene " + kSource +
        "/scenes/cornell_spheres.toml --width 40 --height 40 --spp 3 --quiet --seed 9 ";
    for (int threads : {1, 2, 3})
        ASSERT_EQ(run(bidir + "--threads " + std::to_string(threads) + " --out " +
                      (dir / ("bd" + std::to_string(threads))).string())
                      .exit_code,
                  0);
    EXPECT_EQ(read_file(dir / "bd1.exr"), read_file(dir / "bd2.exr"));
    EXPECT_EQ(read_file(dir / "bd1.exr"), read_file(dir / "bd3.exr"));
}

// Lessons 1 to 7 have no media: on a scene with fog filling the room and milk inside a sphere
// each renders the surfaces exactly as without them (the same pixels), reports biased: true and
// names the media it ignored; without media it says nothing of them.
TEST(Cli, EveryLessonWithoutMediaRendersTheSurfacesAndSaysWhatItIgnored) {
    const std::string room = R"([image]
width = 16
height = 12
[camera]
position = [0, 1, -3]
look_at = [0, 1, 0]
fov = 50
[materials.white]
type = "diffuse"
albedo = [0.6, 0.6, 0.6]
[materials.lamp]
type = "diffuse"
emission = [8, 8, 8]
[[shapes]]
type = "quad"
material = "white"
corner = [-2, 0, -4]
edge_u = [0, 0, 6]
edge_v = [4, 0, 0]
[[shapes]]
type = "quad"
material = "lamp"
corner = [-0.5, 2, 0]
edge_u = [1, 0, 0]
edge_v = [0, 0, 1]
[[shapes]]
type = "sphere"
material = "white"
center = [0, 0.5, 0.5]
radius = 0.5
)";
    const std::string media = R"(
[media.fog]
type = "homogeneous"
sigma_s = [0.2, 0.2, 0.2]
g = 0.5
[media.milk]
type = "homogeneous"
sigma_s = [30, 25, 20]
)";
    const fs::path dir = fresh_dir("media_ignored");
    std::ofstream(dir / "plain.toml") << room;
    // The sphere gets the milk inside it (its table is the last), and the fog fills space.
    std::ofstream(dir / "fog.toml") << "medium = \"fog\"\n" << room << "interior = \"milk\"\n"
                                    << media;
    for (const std::string& lesson : lessons::test::registered_lesson_names()) {
        SCOPED_TRACE(lesson);
        lessons::Image images[2];
        std::string reports[2];
        int k = 0;
        for (const char* scene : {"plain", "fog"}) {
            const std::string out = (dir / (lesson + scene)).string();
            const RunResult r = run(kBin + "/" + lesson + " --scene " +
                                    (dir / (std::string(scene) + ".toml")).string() +
                                    " --spp 2 --seed 3 --threads 1 --quiet --out " + out +
                                    " --report " + out + ".json");
            ASSERT_EQ(r.exit_code, 0) << r.output;
            images[k] = lessons::read_exr(out + ".exr");
            reports[k++] = read_file(out + ".json");
        }
        EXPECT_EQ(reports[0].find("media are ignored"), std::string::npos) << reports[0];
        EXPECT_NE(reports[1].find("\"biased\": true"), std::string::npos) << reports[1];
        EXPECT_NE(reports[1].find("the scene's media are ignored"), std::string::npos)
            << reports[1];
        EXPECT_NE(reports[1].find("fog (fills space"), std::string::npos) << reports[1];
        EXPECT_NE(reports[1].find("milk (inside 1 shape(s)"), std::string::npos) << reports[1];
        EXPECT_NE(reports[1].find("\"nan_pixels\": 0"), std::string::npos) << reports[1];
        ASSERT_EQ(images[0].pixels.size(), images[1].pixels.size());
        EXPECT_TRUE(images[0].pixels == images[1].pixels) << "the surfaces changed";
    }
}
