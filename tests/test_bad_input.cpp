// The bad-input corpus (tests/bad_input/) through every lesson: each malformed scene or mesh
// gets one error line naming the file, line and field, exit code 2, and no output file. A file
// says what it expects in its first line: "# expect: TEXT" (an error containing TEXT) or
// "# expect-warning: TEXT" (a warning containing TEXT, and a normal render).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "lesson_registry.h"

namespace fs = std::filesystem;

namespace {

const std::string kSource = LESSONS_SOURCE_DIR;
const std::string kBin = LESSONS_BIN_DIR;
const std::vector<std::string> kLessons = lessons::test::registered_lesson_names();

struct Result {
    int exit_code;
    std::string output;
};

Result run(const std::string& command, const fs::path& log) {
    const int status = std::system((command + " > " + log.string() + " 2>&1").c_str());
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

std::vector<std::string> lines_containing(const std::string& text, const std::string& word) {
    std::vector<std::string> found;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (line.find(word) != std::string::npos) found.push_back(line);
    return found;
}

}  // namespace

TEST(BadInput, EveryCaseInTheCorpusGetsOneClearErrorFromEveryLesson) {
    const fs::path work =
        fs::temp_directory_path() / ("lessons_bad_input_" + std::to_string(getpid()));
    fs::remove_all(work);
    fs::create_directories(work);
    int cases = 0, warned = 0;
    for (const auto& entry : fs::directory_iterator(kSource + "/tests/bad_input")) {
        if (entry.path().extension() != ".toml") continue;
        std::ifstream in(entry.path());
        std::string first;
        std::getline(in, first);
        const bool warning = first.rfind("# expect-warning: ", 0) == 0;
        ASSERT_TRUE(warning || first.rfind("# expect: ", 0) == 0)
            << entry.path() << " has no expectation";
        const std::string expected = first.substr(first.find(':') + 2);
        ++cases;
        warned += warning;
        for (const std::string& lesson : kLessons) {
            const fs::path out = work / (lesson + "_" + entry.path().stem().string());
            const Result r = run(kBin + "/" + lesson + " --scene " + entry.path().string() +
                                     " --spp 1 --quiet --out " + out.string(),
                                 work / "log.txt");
            SCOPED_TRACE(lesson + " on " + entry.path().filename().string() + ":\n" + r.output);
            if (warning) {
                EXPECT_EQ(r.exit_code, 0);
                EXPECT_EQ(lines_containing(r.output, "warning: ").size(), 1u);
                EXPECT_NE(r.output.find(expected), std::string::npos) << "expected: " << expected;
                EXPECT_TRUE(fs::exists(out.string() + ".exr"));
                continue;
            }
            EXPECT_EQ(r.exit_code, 2);
            const std::vector<std::string> errors =
                lines_containing(r.output, lesson + ": error: ");
            ASSERT_EQ(errors.size(), 1u);
            EXPECT_NE(errors[0].find(expected), std::string::npos) << "expected: " << expected;
            EXPECT_NE(errors[0].find(entry.path().stem().string()), std::string::npos)
                << "the message names a file of the case";
            EXPECT_FALSE(fs::exists(out.string() + ".exr"));
            EXPECT_FALSE(fs::exists(out.string() + ".png"));
        }
    }
    EXPECT_GE(cases - warned, 40);
    EXPECT_GE(warned, 1);
    fs::remove_all(work);
}

TEST(Interruption, SigintAndSigtermWriteTheImageSoFarAndAReport) {
    for (int signal_number : {SIGINT, SIGTERM}) {
        const fs::path dir =
            fs::temp_directory_path() /
            ("lessons_interrupt_" + std::to_string(getpid()) + "_" + std::to_string(signal_number));
        fs::remove_all(dir);
        fs::create_directories(dir);
        const std::string scene = kSource + "/scenes/cornell_box.toml";
        const std::string out = (dir / "img").string(), report = (dir / "report.json").string();
        const pid_t child = fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            const std::string exe = kBin + "/04_rendering_equation";
            freopen("/dev/null", "w", stderr);
            execl(exe.c_str(), exe.c_str(), "--scene", scene.c_str(), "--width", "128", "--height",
                  "128", "--spp", "1000000", "--quiet", "--out", out.c_str(), "--report",
                  report.c_str(), static_cast<char*>(nullptr));
            _exit(127);
        }
        usleep(1500 * 1000);
        kill(child, signal_number);
        int status = 0;
        waitpid(child, &status, 0);
        ASSERT_TRUE(WIFEXITED(status));
        EXPECT_EQ(WEXITSTATUS(status), 130);
        EXPECT_GT(fs::file_size(out + ".exr"), 0u);
        EXPECT_GT(fs::file_size(out + ".png"), 0u);
        EXPECT_FALSE(fs::exists(out + ".exr.tmp"));
        std::ifstream in(report);
        std::stringstream text;
        text << in.rdbuf();
        EXPECT_NE(text.str().find("\"interrupted\": true"), std::string::npos) << text.str();
        fs::remove_all(dir);
    }
}

TEST(Interruption, ASecondSignalExitsAtOnce) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        const std::string exe = kBin + "/04_rendering_equation";
        const std::string scene = kSource + "/scenes/cornell_box.toml";
        freopen("/dev/null", "w", stderr);
        // A single huge pass: the first signal alone would wait for the tiles in progress.
        const std::string out = (fs::temp_directory_path() / "lessons_second_signal").string();
        execl(exe.c_str(), exe.c_str(), "--scene", scene.c_str(), "--width", "2048", "--height",
              "2048", "--spp", "1000000", "--quiet", "--out", out.c_str(),
              static_cast<char*>(nullptr));
        _exit(127);
    }
    usleep(1000 * 1000);
    kill(child, SIGINT);
    usleep(100 * 1000);
    kill(child, SIGINT);
    int status = 0;
    for (int waited = 0; waited < 50 && waitpid(child, &status, WNOHANG) == 0; ++waited)
        usleep(100 * 1000);
    if (waitpid(child, &status, WNOHANG) == 0 && !WIFEXITED(status)) {
        kill(child, SIGKILL);
        waitpid(child, &status, 0);
        FAIL() << "still running 5 s after the second signal";
    }
    EXPECT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT);
}

// Files that fight back: a scene or mesh that is a device or a FIFO, or larger than its cap, is
// refused at once (exit 2, a message naming it), and a binary file's bytes never reach the
// terminal raw.
TEST(BadInput, NonRegularAndOversizedFilesAreRefusedAtOnce) {
    const fs::path work = fs::temp_directory_path() / ("lessons_files_" + std::to_string(getpid()));
    fs::remove_all(work);
    fs::create_directories(work);
    const fs::path fifo = work / "scene.fifo";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const std::string exe = kBin + "/04_rendering_equation --spp 1 --quiet --out " +
                            (work / "img").string() + " ";
    struct Case {
        std::string args, expected;
    };
    const std::vector<Case> cases = {
        {"--scene /dev/zero", "/dev/zero: is not a regular file"},
        {"--scene " + fifo.string(), "is not a regular file"},
        {"--scene " + kSource + "/scenes", "is a directory"},
        {"--scene " + kSource + "/scenes/cornell_box.toml --max-scene-mb 0.001",
         "bytes allowed for a scene file (raise --max-scene-mb)"},
        {"--scene " + kSource + "/scenes/hard/lowpoly_sphere.toml --max-file-mb 0.0001",
         "bytes allowed for an OBJ file (raise --max-file-mb)"},
    };
    for (const Case& c : cases) {
        const auto start = std::chrono::steady_clock::now();
        const Result r = run(exe + c.args, work / "log.txt");
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        SCOPED_TRACE(c.args + ":\n" + r.output);
        EXPECT_EQ(r.exit_code, 2);
        EXPECT_NE(r.output.find(c.expected), std::string::npos) << "expected: " << c.expected;
        EXPECT_LT(seconds, 1.0);  // at once: nothing is read
        EXPECT_FALSE(fs::exists(work / "img.exr"));
    }
    fs::remove_all(work);
}

TEST(BadInput, ABinaryMeshsBytesAreEscapedInTheMessage) {
    const fs::path log = fs::temp_directory_path() / ("lessons_binary_" + std::to_string(getpid()));
    const Result r = run(kBin + "/01_ray_casting --quiet --spp 1 --scene " + kSource +
                             "/tests/bad_input/mesh_binary.toml --out " + log.string() + "_img",
                         log);
    EXPECT_EQ(r.exit_code, 2);
    for (const char c : r.output)
        EXPECT_TRUE(c == '\n' || static_cast<unsigned char>(c) >= 0x20)
            << "a raw control byte " << int(static_cast<unsigned char>(c)) << " in: " << r.output;
    EXPECT_NE(r.output.find("\\x01\\x02\\xFF\\x7F"), std::string::npos) << r.output;
    fs::remove(log);
}
