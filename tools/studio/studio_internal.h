// The studio's core, inside (private to tools/studio): one render's state, and what the core's
// files share. The files, by idea:
//   studio.cpp      the scenes and lessons offered, the panes: a start loaded and installed
//   requests.cpp    a page's parameters turned into the lesson's own command line
//   renders.cpp     the worker: a pass at a time, in turn, each published as a snapshot
//   references.cpp  the background reference render, and references found on disk or cached
//   probe.cpp       the radiometry at a clicked pixel
//   answers.cpp     what the page reads: the status (JSON), frames and downloads
#pragma once

#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "all_lessons.h"
#include "io/image.h"
#include "studio.h"

namespace lessons::studio {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// One render: of a pane, or the background reference.
struct PaneState {
    uint64_t generation = 0;
    std::string scene_id;
    std::vector<std::string> args;  // the lesson's command line
    Params params;                  // as the page sent them (a reloaded page shows them again)
    Lesson lesson;
    CommonOptions options;
    RunInputs inputs;
    std::unique_ptr<ProgressiveFilms> films;  // freed when the render is done
    RenderSettings settings;
    std::atomic<bool> stop{false};
    int target = 0;  // samples per pixel to reach
    int batch = 1;   // samples per pixel of the next pass
    bool done = false;
    bool busy = false;    // the worker holds its films for a pass
    std::string failure;  // why the render stopped with an error (shown in the status)
    Clock::time_point started = Clock::now();
    std::shared_ptr<const Snapshot> snapshot;
    // The reference the chart measures against (shared with other panes), its file and spp.
    std::shared_ptr<const Image> reference;
    std::string reference_source;
    double reference_noise = 0.0;  // mean variance of the reference's pixels, when known
    bool is_reference = false;     // the background reference render itself
    std::string reference_path;    // is_reference: where it is written when done
};

// --- Requests (requests.cpp) ---

// The registered lesson of that name; null if none.
const RegisteredLesson* find_lesson(const std::string& name);
// The lesson that renders the studio's own references: unbiased for every scene of the suite.
inline constexpr const char* kReferenceLesson = "05_bidirectional";
// The scene of that id among the studio's; null if none.
const SceneEntry* find_scene(const std::vector<SceneEntry>& scenes, const std::string& id);
// The lesson's own flags, read from its command line parser.
std::vector<OptionInfo> lesson_options(const Lesson& lesson);
// The render's command line (state.args) parsed into state.options and loaded into
// state.inputs by the CLI's own parse_lesson_arguments and prepare_run; throws as they do.
void load_run(PaneState& state);

// --- Renders (renders.cpp) ---

// A loaded render's films and settings: `clamp` as the CLI's --clamp, `target` samples per pixel
// to reach, passes on `threads` threads, stopped by state.stop.
void make_films(PaneState& state, float clamp, int target, int threads);

// --- References (references.cpp) ---

// A reference found on disk: a shipped one (references/<scene>/reference.exr), lessons.sh's
// (out/<scene>/reference.exr) or the studio's cache.
struct FoundReference {
    std::shared_ptr<const Image> image;
    std::string source;
    double noise = 0.0;
};
// The reference for a pane's render, if there is one on disk: the first of the `references`
// folders that has one for its scene and size (<dir>/<scene>/reference.exr), else the studio's
// own under `cache` (rendered at `reference_spp`).
std::optional<FoundReference> find_reference(const std::vector<std::string>& references,
                                             const std::string& cache, const SceneEntry& scene,
                                             const PaneState& pane, int reference_spp);
// The width and height a reference's provenance (reference.toml) records; 0, 0 without one.
std::pair<int, int> provenance_size(const std::vector<std::string>& references,
                                    const std::string& scene_path);
// Where a reference the studio renders is cached (without ".exr").
std::string cache_stem(const std::string& cache, const SceneEntry& scene,
                       const std::vector<std::string>& inputs, int width, int height, float albedo,
                       int spp);
// A finished background reference, kept where the studio looks for its references next time.
void cache_reference(const PaneState& job, const RenderResult& result);
// Mean over the pixels of the variance image's channel mean: the noise of a reference.
double mean_variance(const Image& variance);
// Whether two renders are of the same scene at the same size (so one can be the other's
// reference).
bool same_image(const PaneState& a, const PaneState& b);
// Stops the reference render (panes.back()) if no pane waits for it any more. Under the lock.
void stop_unwanted_reference(const std::vector<std::shared_ptr<PaneState>>& panes);

// --- JSON pieces (answers.cpp) ---

std::string json_number(double v);  // null if not finite
std::string json_strings(const std::vector<std::string>& values);
std::string json_color(const Color& c);

}  // namespace lessons::studio
