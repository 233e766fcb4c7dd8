// The studio's core, apart from HTTP (server.cpp): the scenes it may show, requests turned into
// the lessons' own command lines (so they are validated exactly as the CLI validates them), the
// panes and their renders, and what the page asks of a render (frames, a pixel's radiometry,
// downloads). docs/studio.md says what the page does with it.
//
// Rendering: one worker thread renders one pass at a time, in turn for every pane with work and
// the background reference, with all the studio's threads. A pass is a batch of samples per pixel
// sized to take about a quarter of a second; after each one the pane's image, layers and
// variance are published as a snapshot that requests read. Restarting a pane stops its pass in
// flight (RenderSettings::stop) and drops it. A pane's films after N samples are those of the
// CLI with --spp N: the same films, summed in the same order (render.h).
//
// The core's files, one idea each, are listed in studio_internal.h (private to tools/studio).
#pragma once

#include <atomic>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "driver/run.h"
#include "render/metrics.h"
#include "render/progressive.h"

namespace lessons::studio {

// A request the studio refuses: HTTP 400 with this message.
class RequestError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct Limits {
    int max_side = 1024;    // --width/--height at most this
    int max_spp = 1 << 16;  // a pane stops at this many samples per pixel
    int threads = 0;        // per pass; 0: one per core
    int reference_spp = 1024;
    double memory_mb = 4096.0;  // the films and snapshots of one render at most this
};

struct SceneEntry {
    std::string id;    // the name the page uses: its folder's label, '/', the file's stem
    std::string path;  // the file
    std::string description;
    // The size of its reference with a provenance file (references.cpp), as the file says:
    // choosing the scene on the page sets this size, so the chart starts at once. 0: none.
    int reference_width = 0, reference_height = 0;
};

using Params = std::map<std::string, std::string>;

// One option of a lesson's command line, as the page offers it.
struct OptionInfo {
    std::string flag;  // "--estimator"
    std::string description;
    bool is_flag = false;
    std::string default_value;
    std::vector<std::string> choices;  // empty: free text (validated on start)
};
struct LessonInfo {
    std::string name, label, description;
    int default_spp = 1;
    std::vector<OptionInfo> options;  // its own flags
};

// The common flags the page may set (the others name files or are the studio's own business).
const std::vector<std::string>& common_flags();

// What a pane's render has published: everything after its last whole pass.
struct Snapshot {
    uint64_t version = 0;  // grows with every publish, over all panes
    int spp = 0;
    int passes = 0;
    RenderResult result;
    std::vector<Checkpoint> chart;  // error after each pass, against the reference
    double wall_seconds = 0.0;      // since the render started, including waiting for its turn
    double image_luminance = 0.0;   // summed over the pixels (for the layers' shares)
    std::vector<double> layer_luminance;
};

struct PaneState;

class Studio {
public:
    // folders: (label, directory) pairs; scenes are the .toml files directly inside each.
    // references: folders of references, <dir>/<scene>/reference.exr, looked for in order: the
    // shipped ones (references/) and lessons.sh's (out/); cache: where the studio keeps the
    // references it renders itself.
    Studio(std::vector<std::pair<std::string, std::string>> folders,
           std::vector<std::string> references, std::string cache, Limits limits, int panes = 2);
    ~Studio();
    Studio(const Studio&) = delete;
    Studio& operator=(const Studio&) = delete;

    const std::vector<SceneEntry>& scenes() const { return scenes_; }
    const std::vector<LessonInfo>& lessons() const { return lessons_; }
    const Limits& limits() const { return limits_; }
    int pane_count() const {
        return static_cast<int>(panes_.size()) - 1;
    }  // the last: the reference

    // The lesson's command line for these parameters (scene, lesson, width, height, seed, spp,
    // and the lesson's and common flags as "--flag" keys); throws RequestError for a parameter
    // that is not allowed or not valid, with the CLI's own message.
    std::vector<std::string> command_line(const Params& params) const;

    // Validates, loads the scene, makes the model, and replaces the pane's render with it.
    // Throws RequestError (bad parameters or scene). Returns the generation of the render the
    // pane now has.
    // Starts take their generation when they arrive, and the HTTP server loads them on several
    // threads at once: a start whose scene finishes loading after a later start's has been
    // installed is dropped (it returns the later one's generation), so the last request made
    // wins, not the last to finish loading.
    uint64_t start(int pane, const Params& params) { return start(pane, params, arrive()); }
    // The two halves of start, for the test that loads two starts in the opposite order:
    // arrive() takes the next generation; start(pane, params, generation) loads and installs.
    uint64_t arrive();
    uint64_t start(int pane, const Params& params, uint64_t generation);
    void stop_pane(int pane);

    // JSON of every pane's state (and the reference's), for the page's polling.
    std::string status_json() const;
    // The pane's current frame as a PNG: view "image", "layer:K" (layer K), "sum:K" (layers
    // 0..K added: the series so far) or "error" (against the reference, viridis).
    std::string frame_png(int pane, const std::string& view, float exposure) const;
    // What is at pixel (x, y) of the pane's image (JSON): the surface and material, L with its
    // standard error, the direct irradiance E there, f towards light `light`, layer shares.
    std::string probe_json(int pane, int x, int y, int light, int samples) const;
    // The pane's image as the CLI writes it: EXR or PNG bytes, and the spp they hold.
    // (The PNG at this exposure, as the CLI's --exposure.)
    std::string download(int pane, const std::string& format, float exposure, int* spp) const;

    // Stops every render and the worker (Ctrl-C).
    void shutdown();

    // Renders still holding films (at most one per pane, plus the reference): for the tests.
    int live_renders() const;

private:
    void worker_loop();
    // Waits for a render with work (in turn) and hands its films to the worker; null on quit.
    std::shared_ptr<PaneState> next_job(std::unique_ptr<ProgressiveFilms>& films);
    // One pass of the job's render; null if it was stopped. Adapts the pass's size.
    std::shared_ptr<Snapshot> render_pass(PaneState& job, ProgressiveFilms& films);
    // Makes the snapshot the job's (under the lock); a finished reference goes to its panes.
    void publish(PaneState& job, const std::shared_ptr<Snapshot>& snapshot, bool finished);
    // What a render shows after a pass: its result and its error chart, one point longer.
    std::shared_ptr<Snapshot> snapshot_of(const PaneState& job,
                                          const ProgressiveFilms& films) const;
    std::shared_ptr<PaneState> pane(int index) const;
    // The pane's render and what it has published; RequestError if it has none yet.
    std::pair<std::shared_ptr<PaneState>, std::shared_ptr<const Snapshot>> rendered(int pane) const;
    // A start's render, loaded and checked, with its films: not yet in a pane.
    std::shared_ptr<PaneState> load(const Params& params) const;
    // Renders the reference for this scene, size and albedo in the background, unless it is the
    // one being rendered.
    void want_reference(const SceneEntry& scene, int width, int height, float albedo);
    // Refuses a render whose films and snapshots would not fit in Limits::memory_mb.
    void check_memory_budget(const RunInputs& inputs) const;

    std::vector<SceneEntry> scenes_;
    std::vector<LessonInfo> lessons_;
    std::vector<std::string> references_;
    std::string cache_;
    Limits limits_;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::vector<std::shared_ptr<PaneState>> panes_;  // [panes] the reference render last
    bool quit_ = false;
    uint64_t next_version_ = 1;
    uint64_t next_generation_ = 1;
    size_t turn_ = 0;
    std::thread worker_;
};

}  // namespace lessons::studio
