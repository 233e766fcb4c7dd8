// Every shipped scene through every lesson of the registry (chapters/lessons.txt), with its
// default flags and with each variant the registry names: no NaN and no infinite sample, ever.
// Each run is the lesson's own executable, so a new lesson is tested by its one registry line.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "lesson_registry.h"

namespace fs = std::filesystem;

namespace {

std::string read_file(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

TEST(AllScenes, EveryLessonRendersEverySceneWithoutNaNOrInf) {
    const fs::path dir =
        fs::temp_directory_path() / ("lessons_all_scenes_" + std::to_string(getpid()));
    fs::create_directories(dir);
    int scenes = 0, runs = 0;
    for (const auto& entry :
         fs::recursive_directory_iterator(std::string(LESSONS_SOURCE_DIR) + "/scenes")) {
        if (entry.path().extension() != ".toml") continue;
        ++scenes;
        for (const lessons::test::RegisteredLesson& lesson : lessons::test::registered_lessons()) {
            std::vector<std::string> flag_sets = {""};
            flag_sets.insert(flag_sets.end(), lesson.variants.begin(), lesson.variants.end());
            for (const std::string& flags : flag_sets) {
                const std::string what =
                    lesson.name + " " + flags + " on " + entry.path().filename().string();
                const fs::path report = dir / ("run" + std::to_string(++runs) + ".json");
                const fs::path log = dir / "run.log";
                // One thread each: ctest runs tests side by side on every core.
                const std::string command =
                    "\"" + std::string(LESSONS_BIN_DIR) + "/" + lesson.name + "\" --scene \"" +
                    entry.path().string() + "\" --width 40 --height 30 --spp 4 --threads 1 --quiet " +
                    flags + " --out \"" + (dir / "img").string() + "\" --report \"" +
                    report.string() + "\" > \"" + log.string() + "\" 2>&1";
                const int status = std::system(command.c_str());
                const bool ran = WIFEXITED(status) && WEXITSTATUS(status) == 0;
                EXPECT_TRUE(ran) << what << ":\n" << read_file(log);
                if (!ran) continue;
                const std::string r = read_file(report);
                for (const char* field : {"\"nan_samples\": 0,", "\"inf_samples\": 0,",
                                          "\"nan_pixels\": 0,", "\"inf_pixels\": 0,"})
                    EXPECT_NE(r.find(field), std::string::npos) << field << ": " << what;
            }
        }
    }
    fs::remove_all(dir);
    EXPECT_GE(scenes, 7);
}
