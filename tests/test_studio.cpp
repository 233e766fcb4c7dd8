// The studio's core without HTTP (tools/studio/studio.h): requests are validated as the CLI
// validates its flags, scenes come only from the given folders, a render is the CLI's render,
// and a pixel's radiometry is right where it has a closed form (the furnace).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "io/image.h"
#include "studio.h"

using namespace lessons;
using namespace lessons::studio;

namespace {

const std::string kSource = LESSONS_SOURCE_DIR;

std::string scratch(const std::string& name) {
    const std::string dir = std::string(LESSONS_BIN_DIR) + "/../studio_test/" + name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

Limits small_limits() {
    Limits l;
    l.max_side = 128;
    l.max_spp = 256;
    l.threads = 2;
    l.reference_spp = 4;
    return l;
}

std::string message_of(const Studio& studio, const Params& params) {
    try {
        studio.command_line(params);
    } catch (const RequestError& e) {
        return e.what();
    }
    return "";
}

// Waits until pane `i` has rendered `spp` samples per pixel (the status says "spp": N).
bool wait_for_spp(const Studio& studio, int spp, double seconds = 60.0) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        const std::string s = studio.status_json();
        if (s.find("\"state\": \"done\", \"generation\"") != std::string::npos &&
            s.find("\"spp\": " + std::to_string(spp) + ",") != std::string::npos)
            return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
}

std::string file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

double json_field(const std::string& json, const std::string& key, size_t index = 0) {
    size_t at = json.find("\"" + key + "\": ");
    if (at == std::string::npos) return NAN;
    at += key.size() + 4;
    if (json[at] == '[') {
        ++at;
        for (size_t k = 0; k < index; ++k) at = json.find(',', at) + 1;
    }
    return std::stod(json.substr(at));
}

}  // namespace

TEST(Studio, ScenesAreTheTomlFilesOfTheGivenFoldersOnly) {
    Studio studio({{"scenes", kSource + "/scenes"}, {"hard", kSource + "/scenes/hard"}},
                  {scratch("refs")}, scratch("cache"), small_limits(), 1);
    bool box = false, tiny = false;
    for (const SceneEntry& s : studio.scenes()) {
        box |= s.id == "scenes/cornell_box";
        tiny |= s.id == "hard/cornell_tiny";
        EXPECT_EQ(std::filesystem::path(s.path).extension(), ".toml") << s.path;
    }
    EXPECT_TRUE(box);
    EXPECT_TRUE(tiny);
    for (const std::string& bad : std::vector<std::string>{
             "../../etc/passwd", "scenes/../../etc/passwd", "/etc/passwd",
             kSource + "/scenes/cornell_box.toml", "scenes/cornell_box.toml", "hard/meshes/cube"}) {
        const std::string m = message_of(studio, {{"scene", bad}, {"lesson", "01_ray_casting"}});
        EXPECT_NE(m.find("is not one of the studio's scenes"), std::string::npos)
            << bad << ": " << m;
    }
}

TEST(Studio, RequestsAreValidatedAsTheCommandLineIs) {
    Studio studio({{"scenes", kSource + "/scenes"}}, {scratch("refs")}, scratch("cache"),
                  small_limits(), 1);
    const Params ok{{"scene", "scenes/cornell_box"},
                    {"lesson", "03_reflection_equation"},
                    {"--estimator", "light"},
                    {"--width", "32"},
                    {"--height", "24"},
                    {"--seed", "7"},
                    {"--spp", "8"}};
    const std::vector<std::string> args = studio.command_line(ok);
    ASSERT_GE(args.size(), 3u);
    EXPECT_EQ(args[0], "03_reflection_equation");
    EXPECT_EQ(args[1], "--scene");
    EXPECT_EQ(args[2], kSource + "/scenes/cornell_box.toml");
    auto has = [&](const std::string& flag, const std::string& value) {
        for (size_t i = 0; i + 1 < args.size(); ++i)
            if (args[i] == flag && args[i + 1] == value) return true;
        return false;
    };
    EXPECT_TRUE(has("--estimator", "light"));
    EXPECT_TRUE(has("--spp", "8"));

    auto with = [&](const std::string& key, const std::string& value) {
        Params p = ok;
        p[key] = value;
        return message_of(studio, p);
    };
    // The CLI's own messages (CLI11's validators).
    EXPECT_NE(with("--estimator", "guess").find("--estimator"), std::string::npos);
    EXPECT_NE(with("--estimator", "guess").find("guess"), std::string::npos);
    EXPECT_NE(with("--seed", "minus one").find("--seed"), std::string::npos);
    EXPECT_NE(with("--clamp", "-3").find("--clamp"), std::string::npos);
    EXPECT_NE(with("--albedo", "1.5").find("--albedo"), std::string::npos);
    // The studio's limits.
    EXPECT_NE(with("--width", "4096").find("--max-size"), std::string::npos);
    EXPECT_NE(with("--width", "0").find("outside"), std::string::npos);
    EXPECT_NE(with("--spp", "100000").find("--max-spp"), std::string::npos);
    EXPECT_NE(with("--spp", "ten").find("not an integer"), std::string::npos);
    // Flags that name files, and other lessons' flags, are not the page's to set.
    for (const std::string& flag :
         std::vector<std::string>{"--out", "--report", "--reference", "--variance", "--threads",
                                  "--plain", "--scene2", "pane2"})
        EXPECT_NE(with(flag, "x").find("is not allowed"), std::string::npos) << flag;
    EXPECT_NE(with("lesson", "06_nothing").find("unknown"), std::string::npos);
    Params no_scene = ok;
    no_scene.erase("scene");
    EXPECT_NE(message_of(studio, no_scene).find("scene: missing"), std::string::npos);
    // A flag is on or off.
    Params plain{{"scene", "scenes/cornell_box"}, {"lesson", "04_rendering_equation"}};
    plain["--plain"] = "maybe";
    EXPECT_NE(message_of(studio, plain).find("on (1) or off (0)"), std::string::npos);
    plain["--plain"] = "1";
    EXPECT_EQ(message_of(studio, plain), "");
    // Bad input the scene loader finds: the lesson's own check (lesson 5's --unweighted).
    EXPECT_THROW(studio.start(0, {{"scene", "scenes/cornell_box"},
                                  {"lesson", "05_bidirectional"},
                                  {"--unweighted", "1"}}),
                 RequestError);
    EXPECT_THROW(studio.start(3, ok), RequestError);
}

TEST(Studio, LessonsOfferTheirOwnFlags) {
    Studio studio({{"scenes", kSource + "/scenes"}}, {scratch("refs")}, scratch("cache"),
                  small_limits(), 1);
    bool estimator = false, plain = false;
    for (const LessonInfo& l : studio.lessons())
        for (const OptionInfo& o : l.options) {
            if (l.name == "03_reflection_equation" && o.flag == "--estimator") {
                estimator = true;
                EXPECT_EQ(o.choices,
                          (std::vector<std::string>{"uniform", "cosine", "brdf", "light", "mis"}));
                EXPECT_EQ(o.default_value, "mis");
            }
            if (l.name == "04_rendering_equation" && o.flag == "--plain") plain = o.is_flag;
        }
    EXPECT_TRUE(estimator);
    EXPECT_TRUE(plain);
}

// The studio's image after N samples is the CLI's --spp N image, bit for bit (EXR bytes).
TEST(Studio, DownloadEqualsTheCommandLinesImage) {
    const std::string out = scratch("download");
    Studio studio({{"scenes", kSource + "/scenes"}}, {out}, out, small_limits(), 1);
    const Params p{{"scene", "scenes/cornell_spheres"},
                   {"lesson", "04_rendering_equation"},
                   {"--width", "24"},
                   {"--height", "20"},
                   {"--seed", "3"},
                   {"--spp", "37"},
                   {"--bounces", "3"}};
    studio.start(0, p);
    ASSERT_TRUE(wait_for_spp(studio, 37));
    int spp = 0;
    const std::string exr = studio.download(0, "exr", 0.0f, &spp);
    EXPECT_EQ(spp, 37);
    std::string command = std::string(LESSONS_BIN_DIR) + "/04_rendering_equation --scene " +
                          kSource +
                          "/scenes/cornell_spheres.toml --width 24 --height 20 --seed 3 --spp 37 "
                          "--bounces 3 --quiet --out " +
                          out + "/cli";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    EXPECT_TRUE(exr == file_bytes(out + "/cli.exr")) << "the studio's EXR differs from the CLI's";
    // The series view (bounce layers 0..1 added) and the error view need no reference... but
    // the error view does: until one exists it is a clear refusal, not a crash.
    EXPECT_FALSE(studio.frame_png(0, "sum:1", 0.0f).empty());
    EXPECT_THROW(studio.frame_png(0, "layer:9", 0.0f), RequestError);
    EXPECT_THROW(studio.frame_png(0, "nonsense", 0.0f), RequestError);
}

// Inside the furnace (radiance L_e / (1 - rho) everywhere, emission L_e = 1 all around), the
// direct irradiance at any point is pi L_e (a uniform emitter over the whole hemisphere), and
// the probe's f of the diffuse wall is rho / pi.
TEST(Studio, ProbeGivesTheFurnacesIrradianceAndBrdf) {
    const std::string out = scratch("probe");
    Studio studio({{"scenes", kSource + "/scenes"}}, {out}, out, small_limits(), 1);
    studio.start(0, {{"scene", "scenes/furnace"},
                     {"lesson", "04_rendering_equation"},
                     {"--width", "16"},
                     {"--height", "16"},
                     {"--spp", "64"},
                     {"--albedo", "0.5"},
                     // The standard error below is the sample variance's: a measure of the
                     // error for independent samples only (with the stratified default, a
                     // pixel whose 64 paths all end at the first roulette has variance 0).
                     {"--sampler", "independent"}});
    ASSERT_TRUE(wait_for_spp(studio, 64));
    const std::string p = studio.probe_json(0, 8, 8, 0, 4096);
    const double E = json_field(p, "E"), se = json_field(p, "E_standard_error");
    EXPECT_NEAR(E, M_PI, 4.0 * se + 1e-4) << p;
    EXPECT_NEAR(json_field(p, "f"), 0.5 / M_PI, 1e-5) << p;
    // L = L_e / (1 - rho) = 2, within four standard errors.
    EXPECT_NEAR(json_field(p, "L"), 2.0, 4.0 * json_field(p, "L_standard_error") + 1e-4) << p;
    EXPECT_NE(p.find("\"E_units\": \"W/m^2\""), std::string::npos);
    EXPECT_NE(p.find("\"f_units\": \"1/sr\""), std::string::npos);
    EXPECT_THROW(studio.probe_json(0, 16, 3, 0, 16), RequestError);
}

// A scene with a shipped reference (references/SCENE/, with its provenance) has its chart at
// once: the pane takes that reference when it starts and no background render begins. A copy of
// it whose provenance names other scene files (the scene was edited since) is not taken, and the
// studio renders its own in the background.
TEST(Studio, AShippedReferenceStartsTheChartAtOnce) {
    Limits limits = small_limits();
    limits.max_side = 512;
    const Params p{{"scene", "scenes/cornell_spheres"},
                   {"lesson", "01_ray_casting"},
                   {"--width", "256"},
                   {"--height", "256"},
                   {"--spp", "1"}};
    {
        Studio studio({{"scenes", kSource + "/scenes"}}, {kSource + "/references"},
                      scratch("shipped_cache"), limits, 1);
        const SceneEntry* entry = nullptr;
        for (const SceneEntry& e : studio.scenes())
            if (e.id == "scenes/cornell_spheres") entry = &e;
        ASSERT_NE(entry, nullptr);
        EXPECT_EQ(entry->reference_width, 256);  // the page sets this size for the scene
        EXPECT_EQ(entry->reference_height, 256);
        studio.start(0, p);
        const std::string s = studio.status_json();
        EXPECT_NE(s.find("references/cornell_spheres/reference.exr (05_bidirectional, 1024 spp"),
                  std::string::npos)
            << s;
        EXPECT_NE(s.find("], \"reference\": null, \"live_renders\""), std::string::npos)
            << "no background reference render: " << s;
    }
    const std::string stale = scratch("stale_refs");
    std::filesystem::copy(kSource + "/references/cornell_spheres", stale + "/cornell_spheres");
    std::string text = file_bytes(kSource + "/references/cornell_spheres/reference.toml");
    const size_t at = text.find("scene_files = \"");
    ASSERT_NE(at, std::string::npos);
    text.replace(at + 15, 16, "0123456789abcdef");
    std::ofstream(stale + "/cornell_spheres/reference.toml") << text;
    Studio studio({{"scenes", kSource + "/scenes"}}, {stale}, scratch("stale_cache"), limits, 1);
    studio.start(0, p);
    const std::string s = studio.status_json();
    EXPECT_EQ(s.find("stale_refs/cornell_spheres/reference.exr"), std::string::npos) << s;
    EXPECT_EQ(s.find("], \"reference\": null, \"live_renders\""), std::string::npos)
        << "a background reference render: " << s;
}

// Restarting a pane replaces its render: only one runs per pane, whatever the number of starts.
TEST(Studio, RestartsDoNotPileUp) {
    const std::string out = scratch("restarts");
    Limits limits = small_limits();
    limits.max_spp = 1 << 16;
    Studio studio({{"scenes", kSource + "/scenes"}}, {out}, out, limits, 2);
    for (int k = 0; k < 20; ++k)
        studio.start(k % 2, {{"scene", "scenes/cornell_box"},
                             {"lesson", "04_rendering_equation"},
                             {"--width", "64"},
                             {"--height", "64"},
                             {"--seed", std::to_string(k)}});
    // Two panes, and at most the reference besides.
    EXPECT_LE(studio.live_renders(), 3);
    studio.shutdown();
    EXPECT_EQ(studio.live_renders(), 0);
}

// The HTTP server loads starts on several threads: when the earlier of two starts for a pane
// finishes loading last (a bigger scene, say), the later one still wins. (Before, the last to
// finish won, and a page's first start could replace the teacher's next choice.)
TEST(Studio, TheLastStartMadeWinsNotTheLastToFinishLoading) {
    const std::string out = scratch("order");
    Studio studio({{"scenes", kSource + "/scenes"}}, {out}, out, small_limits(), 2);
    const Params earlier = {{"scene", "scenes/cornell_spheres"},
                            {"lesson", "02_whitted"},
                            {"--width", "32"},
                            {"--height", "24"}};
    const Params later = {{"scene", "scenes/cornell_box"},
                          {"lesson", "04_rendering_equation"},
                          {"--width", "48"},
                          {"--height", "36"}};
    const uint64_t first = studio.arrive(), second = studio.arrive();
    ASSERT_LT(first, second);
    EXPECT_EQ(studio.start(0, later, second), second);
    EXPECT_EQ(studio.start(0, earlier, first), second);  // dropped: the pane keeps the later
    const std::string s = studio.status_json();
    const size_t pane0 = s.find("\"panes\"");
    ASSERT_NE(pane0, std::string::npos) << s;
    const size_t generation = s.find("\"generation\": ", pane0);
    ASSERT_NE(generation, std::string::npos) << s;
    EXPECT_EQ(s.substr(generation, s.find(',', generation) - generation),
              "\"generation\": " + std::to_string(second));
    EXPECT_EQ(s.find("cornell_spheres"), std::string::npos) << s;
    EXPECT_NE(s.find("\"scene\": \"scenes/cornell_box\""), std::string::npos) << s;
    // A start made after both replaces it, as always.
    const uint64_t third = studio.start(0, earlier);
    EXPECT_GT(third, second);
    EXPECT_NE(studio.status_json().find("\"scene\": \"scenes/cornell_spheres\""),
              std::string::npos);
    studio.shutdown();
}

// A render larger than the studio's memory budget is refused before anything is allocated.
TEST(Studio, RendersBeyondTheMemoryBudgetAreRefused) {
    const std::string out = scratch("budget");
    Limits limits = small_limits();
    limits.memory_mb = 0.5;
    Studio studio({{"scenes", kSource + "/scenes"}}, {out}, out, limits, 1);
    try {
        studio.start(0, {{"scene", "scenes/cornell_box"}, {"lesson", "04_rendering_equation"},
                         {"--width", "128"}, {"--height", "128"}, {"--bounces", "8"}});
        FAIL() << "expected a refusal";
    } catch (const RequestError& e) {
        EXPECT_NE(std::string(e.what()).find("--max-memory-mb"), std::string::npos) << e.what();
    }
    EXPECT_EQ(studio.live_renders(), 0);
}

// The background reference follows the panes: leaving a scene for one that has a reference
// stops it, coming back starts it again (not "already rendering" a stopped one), and a pane with
// --albedo gets a reference with the same albedo.
TEST(Studio, TheBackgroundReferenceFollowsThePanes) {
    const std::string out = scratch("reference");
    std::filesystem::create_directories(out + "/cornell_box");
    write_exr(Image(16, 16), out + "/cornell_box/reference.exr");
    Limits limits = small_limits();
    limits.reference_spp = 1 << 14;  // long enough to be seen rendering
    Studio studio({{"scenes", kSource + "/scenes"}}, {out}, out, limits, 1);
    const Params furnace{{"scene", "scenes/furnace"}, {"lesson", "01_ray_casting"},
                         {"--width", "16"}, {"--height", "16"}, {"--spp", "4"}};
    Params box = furnace;
    box["scene"] = "scenes/cornell_box";
    auto reference = [&] {
        const std::string s = studio.status_json();
        return s.substr(s.find("\"reference\": {"));
    };
    studio.start(0, furnace);
    EXPECT_NE(reference().find("\"scene\": \"scenes/furnace\""), std::string::npos);
    studio.start(0, box);  // has lessons.sh's reference: the furnace's is not needed any more
    EXPECT_NE(reference().find("\"state\": \"stopped\""), std::string::npos) << reference();
    EXPECT_NE(studio.status_json().find(out + "/cornell_box/reference.exr"), std::string::npos);
    studio.start(0, furnace);
    EXPECT_NE(reference().find("\"state\": \"rendering\""), std::string::npos) << reference();
    Params grey = furnace;
    grey["--albedo"] = "0.5";
    studio.start(0, grey);
    EXPECT_NE(reference().find("--albedo 0.5"), std::string::npos) << reference();
}
