// The shipped files found from the program's own place (io/shipped_files.h): --scene takes a
// shipped scene's name when no such file is here, a path keeps its meaning, and an unknown name
// is an error naming every place looked in. This test program is in build/bin, beside
// build/share/illumination-lessons, whose scenes/ is the source tree's (cmake/install.cmake);
// tests/package/run.sh checks the same from an install.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/input_error.h"
#include "io/shipped_files.h"

using namespace lessons;
namespace fs = std::filesystem;

namespace {

// Each test runs in an empty folder of its own, so that no scenes/ is here; puts back the
// current folder after.
class SceneByName : public ::testing::Test {
protected:
    void SetUp() override {
        previous_ = fs::current_path();
        folder_ =
            fs::temp_directory_path() /
            ("shipped_files_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(folder_);
        fs::create_directories(folder_);
        fs::current_path(folder_);
    }
    void TearDown() override {
        fs::current_path(previous_);
        fs::remove_all(folder_);
    }
    fs::path previous_, folder_;
};

const fs::path kSourceScenes = fs::path(LESSONS_SOURCE_DIR) / "scenes";

bool same_file(const std::string& a, const fs::path& b) {
    return fs::equivalent(a, b);
}

}  // namespace

TEST(ShippedFiles, AreBesideTheProgramInTheBuildTree) {
    const fs::path dir = shipped_files_dir();
    EXPECT_EQ(
        dir,
        (fs::path(LESSONS_BIN_DIR) / ".." / "share" / "illumination-lessons").lexically_normal());
    EXPECT_TRUE(fs::equivalent(dir / "scenes", kSourceScenes));
    EXPECT_TRUE(fs::is_regular_file(dir / "page" / "index.html"));
}

TEST_F(SceneByName, ASceneIsFoundByItsNameWithOrWithoutToml) {
    const fs::path cornell = kSourceScenes / "cornell_box.toml";
    EXPECT_TRUE(same_file(find_scene_file("cornell_box"), cornell));
    EXPECT_TRUE(same_file(find_scene_file("cornell_box.toml"), cornell));
    EXPECT_TRUE(same_file(find_scene_file("scenes/cornell_box.toml"), cornell));
    EXPECT_TRUE(same_file(find_scene_file("hard/cornell_tiny"),
                          kSourceScenes / "hard" / "cornell_tiny.toml"));
    EXPECT_EQ(find_scene_file("cornell_box"),
              (shipped_files_dir() / "scenes" / "cornell_box.toml").string());
}

TEST_F(SceneByName, AFileHereComesBeforeAShippedScene) {
    std::ofstream("cornell_box.toml") << "# not the shipped one\n";
    EXPECT_EQ(find_scene_file("cornell_box.toml"), "cornell_box.toml");
    EXPECT_EQ(find_scene_file("cornell_box"), "cornell_box.toml");
    fs::create_directory("cornell_box");  // what exists keeps today's meaning (and error)
    EXPECT_EQ(find_scene_file("cornell_box"), "cornell_box");
}

TEST_F(SceneByName, APathIsNeverLookedUpElsewhere) {
    EXPECT_EQ(find_scene_file("./cornell_box.toml"), "./cornell_box.toml");
    EXPECT_EQ(find_scene_file("../cornell_box.toml"), "../cornell_box.toml");
    EXPECT_EQ(find_scene_file("/nonexistent/cornell_box.toml"), "/nonexistent/cornell_box.toml");
    EXPECT_EQ(find_scene_file("hard/../cornell_box"), "hard/../cornell_box");
}

TEST_F(SceneByName, AnUnknownNameSaysWhereItLooked) {
    const fs::path scenes = shipped_files_dir() / "scenes";
    try {
        find_scene_file("cornell_boks");
        FAIL() << "an unknown name was found";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "cornell_boks: scene file not found (looked for ./cornell_boks, "
                  "./cornell_boks.toml, " +
                      (scenes / "cornell_boks").string() + ", " +
                      (scenes / "cornell_boks.toml").string() + ")");
    }
}
