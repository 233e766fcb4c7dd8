// The studio's core (studio.h): the scenes and lessons it offers, and the panes. A start is
// loaded as the CLI loads a run (the request's command line: requests.cpp), checked against the
// memory budget, given its reference if one is on disk (references.cpp), and installed in its
// pane for the worker (renders.cpp), unless a later start for that pane was installed first.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <tuple>

#include "io/input_error.h"
#include "studio_internal.h"

namespace lessons::studio {

namespace {

// The scene file's `description = "..."` line, for the page's list.
std::string scene_description(const std::string& path) {
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("description", 0) != 0) continue;
        const size_t a = line.find('"'), b = line.rfind('"');
        if (a != std::string::npos && b > a) return line.substr(a + 1, b - a - 1);
    }
    return "";
}

}  // namespace

Studio::Studio(std::vector<std::pair<std::string, std::string>> folders,
               std::vector<std::string> references, std::string cache, Limits limits, int panes)
    : references_(std::move(references)), cache_(std::move(cache)), limits_(limits) {
    for (const auto& [label, dir] : folders) {
        std::vector<SceneEntry> found;
        std::error_code ec;
        for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
            if (e.path().extension() != ".toml" || !e.is_regular_file(ec)) continue;
            SceneEntry entry{label + "/" + e.path().stem().string(), e.path().string(),
                             scene_description(e.path().string())};
            std::tie(entry.reference_width, entry.reference_height) =
                provenance_size(references_, entry.path);
            found.push_back(entry);
        }
        std::sort(found.begin(), found.end(),
                  [](const SceneEntry& a, const SceneEntry& b) { return a.id < b.id; });
        scenes_.insert(scenes_.end(), found.begin(), found.end());
    }
    for (const RegisteredLesson& l : all_lessons()) {
        const Lesson lesson = l.make();
        lessons_.push_back(
            {l.name, l.label, lesson.description, lesson.default_spp, lesson_options(lesson)});
    }
    panes_.resize(panes + 1);
    worker_ = std::thread([this] { worker_loop(); });
}

Studio::~Studio() {
    shutdown();
}

void Studio::shutdown() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        quit_ = true;
        for (auto& p : panes_)
            if (p) p->stop = true;
    }
    wake_.notify_all();
    if (worker_.joinable()) worker_.join();
}

std::shared_ptr<PaneState> Studio::pane(int index) const {
    if (index < 0 || index >= pane_count())
        throw RequestError("pane: " + std::to_string(index) + " is not 0 .. " +
                           std::to_string(pane_count() - 1));
    std::lock_guard<std::mutex> lock(mutex_);
    return panes_[index];
}

uint64_t Studio::arrive() {
    std::lock_guard<std::mutex> lock(mutex_);
    return next_generation_++;
}

std::shared_ptr<PaneState> Studio::load(const Params& params) const {
    auto state = std::make_shared<PaneState>();
    state->args = command_line(params);
    state->scene_id = params.at("scene");
    state->params = params;
    state->lesson = find_lesson(params.at("lesson"))->make();
    try {
        load_run(*state);
    } catch (const InputError& e) {
        throw RequestError(e.what());
    } catch (const std::bad_alloc&) {
        throw RequestError("scene: out of memory while loading it");
    }
    check_memory_budget(state->inputs);
    make_films(*state, state->options.clamp, state->options.spp, limits_.threads);
    return state;
}

uint64_t Studio::start(int pane_index, const Params& params, uint64_t generation) {
    if (pane_index < 0 || pane_index >= pane_count())
        throw RequestError("pane: " + std::to_string(pane_index) + " is not 0 .. " +
                           std::to_string(pane_count() - 1));
    const std::shared_ptr<PaneState> state = load(params);
    const SceneEntry& scene = *find_scene(scenes_, state->scene_id);
    const std::optional<FoundReference> found =
        find_reference(references_, cache_, scene, *state, limits_.reference_spp);
    if (found) {
        state->reference = found->image;
        state->reference_source = found->source;
        state->reference_noise = found->noise;
    }
    state->generation = generation;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        // A later start for this pane loaded faster and is installed: it wins.
        if (panes_[pane_index] && panes_[pane_index]->generation > generation)
            return panes_[pane_index]->generation;
        if (panes_[pane_index]) panes_[pane_index]->stop = true;
        panes_[pane_index] = state;
        stop_unwanted_reference(panes_);
    }
    if (!found)
        want_reference(scene, state->inputs.scene.width, state->inputs.scene.height,
                       state->options.albedo);
    wake_.notify_all();
    return generation;
}

void Studio::stop_pane(int pane_index) {
    std::shared_ptr<PaneState> p = pane(pane_index);
    std::lock_guard<std::mutex> lock(mutex_);
    if (p) {
        p->stop = true;
        if (!p->busy) p->films.reset();
    }
}

void Studio::check_memory_budget(const RunInputs& in) const {
    // Per pixel and film (the image and each layer): the film's sums (FilmPixel),
    // and the snapshot's mean and variance images, twice (the one shown, the one being made).
    const double films = 1.0 + static_cast<double>(in.model->layer_names.size());
    const double bytes =
        films * in.scene.width * in.scene.height * (sizeof(FilmPixel) + 2.0 * 24.0);
    if (bytes > limits_.memory_mb * 1048576.0) {
        char msg[240];
        std::snprintf(msg, sizeof msg,
                      "this render needs about %.0f MiB (%g films of %dx%d), more than the "
                      "studio's --max-memory-mb %.0f: a smaller image, or fewer layers",
                      bytes / 1048576.0, films, in.scene.width, in.scene.height, limits_.memory_mb);
        throw RequestError(msg);
    }
}

int Studio::live_renders() const {
    std::lock_guard<std::mutex> lock(mutex_);
    int n = 0;
    for (const auto& p : panes_)
        if (p && (p->films || p->busy) && !p->done && !p->stop) ++n;
    return n;
}

}  // namespace lessons::studio
