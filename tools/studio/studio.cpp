// The studio's core (see studio.h).
#include "studio.h"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "all_lessons.h"
#include "io/image.h"
#include "io/input_error.h"
#include "io/input_file.h"
#include "io/report.h"
#include "io/scene_file.h"
#include "lights/lights.h"
#include "materials/bsdf.h"
#include "sampling/rng.h"

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

namespace {

std::string json_number(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

std::string json_strings(const std::vector<std::string>& values) {
    std::string s = "[";
    for (size_t i = 0; i < values.size(); ++i) {
        if (i) s += ", ";
        s += json_quote(values[i]);
    }
    return s + "]";
}

std::string json_color(const Color& c) {
    return "[" + json_number(c.x) + ", " + json_number(c.y) + ", " + json_number(c.z) + "]";
}

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

// What a cached reference depends on: the size and time of every file the loaded scene was made
// of (Scene::input_files: the scene file, meshes, MTL files, textures, maps, glTF buffers and
// images), and the scene file's bytes.
uint64_t inputs_hash(const std::vector<std::string>& inputs) {
    uint64_t h = inputs.empty() ? kFnvStart : file_hash(inputs.front());
    for (const std::string& f : inputs) {
        std::error_code ec;
        const auto size = fs::file_size(f, ec);
        const auto time = fs::last_write_time(f, ec).time_since_epoch().count();
        for (const uint64_t v : {static_cast<uint64_t>(size), static_cast<uint64_t>(time)}) {
            h ^= v;
            h *= 1099511628211ull;
        }
    }
    return h;
}

// The newest modification among a scene's files: a reference older than it is stale.
fs::file_time_type newest_input(const std::vector<std::string>& inputs) {
    fs::file_time_type newest = fs::file_time_type::min();
    for (const std::string& f : inputs) {
        std::error_code ec;
        const fs::file_time_type t = fs::last_write_time(f, ec);
        if (!ec && t > newest) newest = t;
    }
    return newest;
}

std::vector<OptionInfo> lesson_options(const Lesson& lesson) {
    CLI::App app;
    if (lesson.add_options) lesson.add_options(app);
    std::vector<OptionInfo> options;
    for (const CLI::Option* opt : app.get_options()) {
        const std::string name = opt->get_name();
        if (name.rfind("--", 0) != 0 || name == "--help") continue;
        OptionInfo info;
        info.flag = name;
        info.description = opt->get_description();
        info.is_flag = opt->get_expected_max() == 0;  // takes no value
        info.default_value = opt->get_default_str();
        // CLI11 appends a validator's description to the type name: "TEXT:{a,b,c}" for a set.
        const std::string type = opt->get_type_name();
        const size_t open = type.find('{'), close = type.find('}');
        if (open != std::string::npos && close != std::string::npos && close > open) {
            std::stringstream ss(type.substr(open + 1, close - open - 1));
            for (std::string c; std::getline(ss, c, ',');) info.choices.push_back(c);
        }
        options.push_back(info);
    }
    return options;
}

const RegisteredLesson* find_lesson(const std::string& name) {
    for (const RegisteredLesson& l : all_lessons())
        if (l.name == name) return &l;
    return nullptr;
}

bool truthy(const std::string& v) {
    return v == "1" || v == "true" || v == "on" || v == "yes";
}
bool falsy(const std::string& v) {
    return v.empty() || v == "0" || v == "false" || v == "off";
}

int int_param(const Params& params, const std::string& key, int fallback) {
    const auto it = params.find(key);
    if (it == params.end() || it->second.empty()) return fallback;
    try {
        size_t used = 0;
        const int v = std::stoi(it->second, &used);
        if (used != it->second.size()) throw std::invalid_argument("trailing");
        return v;
    } catch (const std::exception&) {
        throw RequestError(key + ": '" + it->second + "' is not an integer");
    }
}

double mean_variance(const Image& variance) {
    double sum = 0.0;
    for (const Color& c : variance.pixels) sum += (double(c.x) + c.y + c.z) / 3.0;
    return variance.pixels.empty() ? 0.0 : sum / static_cast<double>(variance.pixels.size());
}

// A reference found on disk: lessons.sh's (OUT/<scene>/reference.exr) or the studio's cache.
struct FoundReference {
    std::shared_ptr<const Image> image;
    std::string source;
    double noise = 0.0;
};
std::optional<FoundReference> read_reference_file(const fs::path& exr, const fs::path& variance,
                                                  int width, int height,
                                                  const std::vector<std::string>& inputs,
                                                  const std::string& source) {
    std::error_code ec;
    if (!fs::is_regular_file(exr, ec)) return std::nullopt;
    // Older than the scene file or a file it names: rendered from another version of them.
    if (fs::last_write_time(exr, ec) < newest_input(inputs)) return std::nullopt;
    try {
        auto image = std::make_shared<Image>(read_exr(exr.string()));
        if (image->width != width || image->height != height) return std::nullopt;
        FoundReference found{image, source + " " + exr.string(), 0.0};
        if (fs::is_regular_file(variance, ec)) {
            const Image v = read_exr(variance.string());
            if (v.width == width && v.height == height) found.noise = mean_variance(v);
        }
        return found;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

std::string cache_stem(const std::string& cache, const SceneEntry& scene,
                       const std::vector<std::string>& inputs, int width, int height, float albedo,
                       int spp) {
    std::string name = scene.id;
    std::replace(name.begin(), name.end(), '/', '_');
    if (albedo >= 0.0f) name += "_albedo" + std::to_string(albedo);
    char buf[64];
    std::snprintf(buf, sizeof buf, "_%dx%d_%dspp_%016llx", width, height, spp,
                  static_cast<unsigned long long>(inputs_hash(inputs)));
    return (fs::path(cache) / (name + buf)).string();
}

// The image a frame shows: the render, one layer, or the layers up to K added.
Image view_image(const RenderResult& r, const std::string& view) {
    if (view.empty() || view == "image") return r.image;
    const bool sum = view.rfind("sum:", 0) == 0;
    if (!sum && view.rfind("layer:", 0) != 0) throw RequestError("view: unknown '" + view + "'");
    int k = -1;
    try {
        k = std::stoi(view.substr(sum ? 4 : 6));
    } catch (const std::exception&) {
    }
    if (k < 0 || k >= static_cast<int>(r.layers.size()))
        throw RequestError("view: this render has no layer " + view.substr(sum ? 4 : 6) +
                           " (it has " + std::to_string(r.layers.size()) + ")");
    if (!sum) return r.layers[k];
    Image image(r.image.width, r.image.height);
    for (int j = 0; j <= k; ++j)
        for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] += r.layers[j].pixels[i];
    return image;
}

std::string read_file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Whether two renders are of the same scene at the same size (so one can be the other's
// reference).
bool same_image(const PaneState& a, const PaneState& b) {
    return a.scene_id == b.scene_id && a.inputs.scene.width == b.inputs.scene.width &&
           a.inputs.scene.height == b.inputs.scene.height && a.options.albedo == b.options.albedo;
}

// A finished background reference, kept where the studio looks for its references next time.
void cache_reference(const PaneState& job, const RenderResult& result) {
    try {
        fs::create_directories(fs::path(job.reference_path).parent_path());
        write_exr(result.image, job.reference_path + ".exr");
        write_exr(result.variance, job.reference_path + "_variance.exr");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "studio: cannot cache the reference: %s\n", e.what());
    }
}

// The direct irradiance at a surface point, E = integral of L_i cos(theta_i) over the hemisphere
// about `n` (the viewer's side): `samples` samples of the lessons' light sampler (a light by
// power, a point on it, a shadow ray), their mean and its standard error, W/m^2.
struct Irradiance {
    Color mean, standard_error;
};
Irradiance direct_irradiance(const Scene& scene, const SurfaceInteraction& si, const Vec3& n,
                             int samples, uint64_t pixel) {
    const LightSampler sampler(scene);
    Rng rng(12345, pixel, 0);
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int k = 0; k < samples; ++k) {
        const float u = rng.uniform();
        const Vec2 uv{rng.uniform(), rng.uniform()};
        Color e(0.0f);
        if (const std::optional<LightSample> ls = sampler.sample(si.surface_point(), u, uv)) {
            const float cos_i = glm::dot(ls->wi, n);
            if (cos_i > 0.0f && ls->pdf > 0.0f && !scene.occluded(ls->shadow_ray, ls->emitter))
                e = ls->radiance * (cos_i / ls->pdf);
        }
        const glm::dvec3 d(e);
        sum += d;
        sum2 += d * d;
    }
    const glm::dvec3 mean = sum / double(samples);
    const glm::dvec3 var = samples > 1
                               ? (sum2 / double(samples) - mean * mean) / double(samples - 1)
                               : glm::dvec3(0.0);
    return {Color(mean), Color(glm::sqrt(glm::max(var, glm::dvec3(0.0))))};
}

}  // namespace

const std::vector<std::string>& common_flags() {
    static const std::vector<std::string> flags{"--width",  "--height",  "--spp",
                                                "--seed",   "--sampler", "--clamp",
                                                "--albedo", "--naive",   "--exposure"};
    return flags;
}

Studio::Studio(std::vector<std::pair<std::string, std::string>> folders, std::string references,
               std::string cache, Limits limits, int panes)
    : references_(std::move(references)), cache_(std::move(cache)), limits_(limits) {
    for (const auto& [label, dir] : folders) {
        std::vector<SceneEntry> found;
        std::error_code ec;
        for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
            if (e.path().extension() != ".toml" || !e.is_regular_file(ec)) continue;
            found.push_back({label + "/" + e.path().stem().string(), e.path().string(),
                             scene_description(e.path().string())});
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

std::vector<std::string> Studio::command_line(const Params& params) const {
    const auto lesson_it = params.find("lesson");
    if (lesson_it == params.end()) throw RequestError("lesson: missing");
    const RegisteredLesson* registered = find_lesson(lesson_it->second);
    const LessonInfo* info = nullptr;
    for (const LessonInfo& l : lessons_)
        if (l.name == lesson_it->second) info = &l;
    if (!registered || !info) {
        std::vector<std::string> names;
        for (const LessonInfo& l : lessons_) names.push_back(l.name);
        throw RequestError("lesson: unknown '" + lesson_it->second + "'" +
                           did_you_mean(lesson_it->second, names) + known_names(names));
    }
    const auto scene_it = params.find("scene");
    if (scene_it == params.end()) throw RequestError("scene: missing");
    const SceneEntry* scene = nullptr;
    for (const SceneEntry& s : scenes_)
        if (s.id == scene_it->second) scene = &s;
    if (!scene)
        throw RequestError("scene: '" + scene_it->second +
                           "' is not one of the studio's scenes (only the .toml files in the "
                           "folders given with --scenes are)");

    std::vector<std::string> args{info->name, "--scene", scene->path};
    bool has_spp = false;
    for (const auto& [key, value] : params) {
        if (key == "lesson" || key == "scene" || key == "pane") continue;
        const bool common =
            std::find(common_flags().begin(), common_flags().end(), key) != common_flags().end();
        const OptionInfo* own = nullptr;
        for (const OptionInfo& o : info->options)
            if (o.flag == key) own = &o;
        if (!common && !own)
            throw RequestError("parameter '" + key + "' is not allowed for " + info->name +
                               " (the studio takes scene, lesson, the lesson's own flags and " +
                               "--width, --height, --spp, --seed, --sampler, --clamp, --albedo, " +
                               "--naive, --exposure)");
        if (own && own->is_flag) {
            if (truthy(value))
                args.push_back(key);
            else if (!falsy(value))
                throw RequestError(key + ": a flag is on (1) or off (0), not '" + value + "'");
            continue;
        }
        if (value.empty()) continue;  // the default
        if (key == "--width" || key == "--height") {
            const int side = int_param(params, key, 0);
            if (side < 1 || side > limits_.max_side)
                throw RequestError(key + ": " + value + " is outside 1 .. " +
                                   std::to_string(limits_.max_side) + " (the studio's --max-size)");
        }
        if (key == "--spp") {
            const int spp = int_param(params, key, 0);
            if (spp < 1 || spp > limits_.max_spp)
                throw RequestError("--spp: " + value + " is outside 1 .. " +
                                   std::to_string(limits_.max_spp) + " (the studio's --max-spp)");
            has_spp = true;
        }
        args.push_back(key);
        args.push_back(value);
    }
    if (!has_spp) {
        args.push_back("--spp");
        args.push_back(std::to_string(limits_.max_spp));
    }
    // The same parser as the CLI's: any value it refuses is refused here, with its message.
    const Lesson lesson = registered->make();
    CLI::App app;
    CommonOptions o;
    try {
        parse_lesson_arguments(args, lesson, app, o);
    } catch (const InputError& e) {
        throw RequestError(e.what());
    } catch (const CLI::CallForHelp&) {
        throw RequestError("--help is not a render");
    }
    return args;
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

uint64_t Studio::start(int pane_index, const Params& params, uint64_t generation) {
    if (pane_index < 0 || pane_index >= pane_count())
        throw RequestError("pane: " + std::to_string(pane_index) + " is not 0 .. " +
                           std::to_string(pane_count() - 1));
    auto state = std::make_shared<PaneState>();
    state->args = command_line(params);
    state->scene_id = params.at("scene");
    state->params = params;
    state->lesson = find_lesson(params.at("lesson"))->make();
    CLI::App app;
    try {
        parse_lesson_arguments(state->args, state->lesson, app, state->options);
        prepare_run(state->options, state->lesson, state->inputs);
    } catch (const InputError& e) {
        throw RequestError(e.what());
    } catch (const std::bad_alloc&) {
        throw RequestError("scene: out of memory while loading it");
    }
    check_memory_budget(state->inputs);
    state->films = std::make_unique<ProgressiveFilms>(state->inputs.scene, *state->inputs.model,
                                                      state->options.clamp);
    state->settings = render_settings(state->options);
    state->settings.threads = limits_.threads;
    state->settings.stop = &state->stop;
    state->target = state->options.spp;

    const SceneEntry* scene = nullptr;
    for (const SceneEntry& s : scenes_)
        if (s.id == state->scene_id) scene = &s;
    const int w = state->inputs.scene.width, h = state->inputs.scene.height;
    const std::vector<std::string>& inputs = state->inputs.scene.input_files;
    // The reference: lessons.sh's for this scene and size, the studio's own, or one to render.
    // (lessons.sh renders the scenes as they are: no reference of theirs has --albedo.)
    const float albedo = state->options.albedo;
    std::optional<FoundReference> found;
    const fs::path lessons_dir = fs::path(references_) / fs::path(scene->path).stem();
    if (albedo < 0.0f)
        found = read_reference_file(lessons_dir / "reference.exr",
                                    lessons_dir / "reference_variance.exr", w, h, inputs,
                                    "scripts/lessons.sh:");
    if (!found) {
        const std::string stem =
            cache_stem(cache_, *scene, inputs, w, h, albedo, limits_.reference_spp);
        found = read_reference_file(stem + ".exr", stem + "_variance.exr", w, h, inputs,
                                    "the studio's cache:");
    }
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
        // A reference render that no pane waits for any more is stopped.
        const auto& ref = panes_.back();
        if (ref && !ref->done) {
            bool wanted = false;
            for (size_t i = 0; i + 1 < panes_.size(); ++i)
                wanted |= panes_[i] && !panes_[i]->reference && same_image(*panes_[i], *ref);
            if (!wanted) {
                ref->stop = true;
                if (!ref->busy) ref->films.reset();
            }
        }
    }
    if (!found) want_reference(scene->id, scene->path, w, h, albedo);
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

void Studio::want_reference(const std::string& scene_id, const std::string& scene_path, int width,
                            int height, float albedo) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto& current = panes_.back();
        if (current && !current->done && !current->stop && current->scene_id == scene_id &&
            current->inputs.scene.width == width && current->inputs.scene.height == height &&
            current->options.albedo == albedo)
            return;  // already rendering it
    }
    // The reference is lesson 5's (unbiased for every scene the suite has: it finds point-light
    // caustics and the lamps' caustics that lesson 4 misses or finds by chance), with another
    // seed than any pane's default.
    const RegisteredLesson* registered = &all_lessons().back();
    auto state = std::make_shared<PaneState>();
    state->is_reference = true;
    state->scene_id = scene_id;
    state->args = {registered->name,
                   "--scene",
                   scene_path,
                   "--width",
                   std::to_string(width),
                   "--height",
                   std::to_string(height),
                   "--spp",
                   std::to_string(limits_.reference_spp),
                   "--seed",
                   "1000003",
                   // Independent samples: the chart's noise line is this render's variance,
                   // the error of its mean only for independent samples (docs/studio.md).
                   "--sampler",
                   "independent"};
    if (albedo >= 0.0f) {
        state->args.push_back("--albedo");
        state->args.push_back(std::to_string(albedo));
    }
    state->lesson = registered->make();
    CLI::App app;
    try {
        parse_lesson_arguments(state->args, state->lesson, app, state->options);
        prepare_run(state->options, state->lesson, state->inputs);
    } catch (const std::exception&) {
        return;  // the pane's own load succeeded, so this cannot fail but for memory
    }
    for (const SceneEntry& s : scenes_)
        if (s.id == scene_id)
            state->reference_path =
                cache_stem(cache_, s, state->inputs.scene.input_files, width, height, albedo,
                           limits_.reference_spp);
    state->films =
        std::make_unique<ProgressiveFilms>(state->inputs.scene, *state->inputs.model, 0.0f);
    state->settings = render_settings(state->options);
    state->settings.threads = limits_.threads;
    state->settings.stop = &state->stop;
    state->target = limits_.reference_spp;
    std::lock_guard<std::mutex> lock(mutex_);
    state->generation = next_generation_++;
    if (panes_.back()) panes_.back()->stop = true;
    panes_.back() = state;
}

std::shared_ptr<PaneState> Studio::next_job(std::unique_ptr<ProgressiveFilms>& films) {
    auto has_work = [](const std::shared_ptr<PaneState>& p) {
        return p && !p->done && p->films && !p->stop;
    };
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait(lock, [&] { return quit_ || std::any_of(panes_.begin(), panes_.end(), has_work); });
    if (quit_) return nullptr;
    // In turn: the next pane after the last one served that has work.
    std::shared_ptr<PaneState> job;
    for (size_t k = 1; k <= panes_.size() && !job; ++k) {
        const size_t i = (turn_ + k) % panes_.size();
        if (has_work(panes_[i])) job = panes_[turn_ = i];
    }
    // The worker alone touches the films while it renders into them.
    films = std::move(job->films);
    job->busy = true;
    return job;
}

std::shared_ptr<Snapshot> Studio::snapshot_of(const PaneState& job,
                                              const ProgressiveFilms& films) const {
    auto snapshot = std::make_shared<Snapshot>();
    snapshot->spp = films.samples();
    snapshot->result = films.result();
    snapshot->wall_seconds = std::chrono::duration<double>(Clock::now() - job.started).count();
    std::shared_ptr<const Image> reference;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        reference = job.reference;
        if (job.snapshot) {
            snapshot->chart = job.snapshot->chart;
            snapshot->passes = job.snapshot->passes;
        }
    }
    snapshot->passes += 1;
    for (const Color& c : snapshot->result.image.pixels) snapshot->image_luminance += luminance(c);
    for (const Image& layer : snapshot->result.layers) {
        double sum = 0.0;
        for (const Color& c : layer.pixels) sum += luminance(c);
        snapshot->layer_luminance.push_back(sum);
    }
    if (reference)
        snapshot->chart.push_back({snapshot->spp, snapshot->result.stats.seconds,
                                   compare_images(snapshot->result.image, *reference)});
    return snapshot;
}

void Studio::worker_loop() {
    std::unique_ptr<ProgressiveFilms> films;
    while (std::shared_ptr<PaneState> job = next_job(films)) {
        std::shared_ptr<Snapshot> snapshot;
        std::string failure;
        try {
            snapshot = render_pass(*job, *films);
        } catch (const std::bad_alloc&) {
            failure = "out of memory while rendering (a smaller image, or fewer layers)";
        } catch (const std::exception& e) {
            failure = e.what();
        }
        const bool finished = snapshot && snapshot->spp >= job->target;
        if (finished && job->is_reference) cache_reference(*job, snapshot->result);
        {
            // What becomes of the films is decided once, here: back to the render if it goes
            // on, else freed (below, outside the lock).
            std::lock_guard<std::mutex> lock(mutex_);
            job->busy = false;
            if (!failure.empty()) {
                job->failure = failure;
                job->done = true;
            } else if (snapshot && !job->stop) {
                if (!finished) job->films = std::move(films);
                publish(*job, snapshot, finished);
            }
        }
        films.reset();
    }
}

std::shared_ptr<Snapshot> Studio::render_pass(PaneState& job, ProgressiveFilms& films) {
    const int end = std::min(job.target, films.samples() + job.batch);
    const auto t0 = Clock::now();
    // Stopped (replaced by a new render, or the studio quits): nothing to publish.
    if (!films.render_to(end, job.settings)) return nullptr;
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    // Passes of about a quarter of a second: the page sees frames often, a restart waits for
    // at most one pass.
    if (dt < 0.12 && job.batch < 1024)
        job.batch *= 2;
    else if (dt > 0.5 && job.batch > 1)
        job.batch /= 2;
    return snapshot_of(job, films);
}

void Studio::publish(PaneState& job, const std::shared_ptr<Snapshot>& snapshot, bool finished) {
    snapshot->version = next_version_++;
    job.snapshot = snapshot;
    job.done = finished;
    if (!finished || !job.is_reference) return;
    // Every pane of this scene, size and albedo measures against it from now on.
    auto image = std::make_shared<const Image>(snapshot->result.image);
    const double noise = mean_variance(snapshot->result.variance);
    for (size_t i = 0; i + 1 < panes_.size(); ++i) {
        PaneState* p = panes_[i].get();
        if (p && !p->reference && same_image(*p, job)) {
            p->reference = image;
            p->reference_noise = noise;
            p->reference_source = "rendered by the studio: " + job.reference_path + ".exr";
        }
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

namespace {

// What the status says of one render: copied under the studio's lock, written out after it.
struct PaneView {
    std::shared_ptr<const PaneState> pane;  // its fixed parts: command line, scene, model
    std::shared_ptr<const Snapshot> snapshot;
    std::string state, failure, reference_source;
    bool has_reference = false;
    double reference_noise = 0.0;
};

std::string pane_json(const PaneView& v, bool is_reference) {
    const PaneState& p = *v.pane;
    const Snapshot* snap = v.snapshot.get();
    std::string command = "build/bin/" + p.args[0];
    for (size_t k = 1; k < p.args.size(); ++k) command += " " + p.args[k];
    std::string s = "{\"state\": \"" + v.state + "\"";
    if (!v.failure.empty()) s += ", \"error\": " + json_quote(v.failure);
    s += ", \"generation\": " + std::to_string(p.generation);
    s += ", \"scene\": " + json_quote(p.scene_id);
    s += ", \"lesson\": " + json_quote(p.args[0]);
    s += ", \"command\": " + json_quote(command);
    s += ", \"params\": {";
    for (auto it = p.params.begin(); it != p.params.end(); ++it)
        s += std::string(it == p.params.begin() ? "" : ", ") + json_quote(it->first) + ": " +
             json_quote(it->second);
    s += "}, \"width\": " + std::to_string(p.inputs.scene.width);
    s += ", \"height\": " + std::to_string(p.inputs.scene.height);
    s += ", \"target_spp\": " + std::to_string(p.target);
    s += ", \"version\": " + std::to_string(snap ? snap->version : 0);
    s += ", \"spp\": " + std::to_string(snap ? snap->spp : 0);
    s += ", \"passes\": " + std::to_string(snap ? snap->passes : 0);
    if (snap) {
        const RenderStats& st = snap->result.stats;
        const double n = static_cast<double>(std::max<size_t>(1, snap->result.image.pixels.size()));
        s += ", \"seconds\": " + json_number(st.seconds);
        s += ", \"wall_seconds\": " + json_number(snap->wall_seconds);
        s += ", \"rays\": " + std::to_string(st.rays);
        s += ", \"mrays_per_second\": " +
             json_number(st.seconds > 0 ? st.rays / st.seconds * 1e-6 : 0.0);
        s += ", \"nan_samples\": " + std::to_string(snap->result.nan_samples);
        s += ", \"inf_samples\": " + std::to_string(snap->result.inf_samples);
        s += ", \"mean_luminance\": " + json_number(snap->image_luminance / n);
        // Each layer's share of the image's luminance (lesson 4's bounces: the series).
        s += ", \"layers\": [";
        for (size_t k = 0; k < snap->layer_luminance.size(); ++k) {
            const double sum = snap->layer_luminance[k], total = snap->image_luminance;
            s += std::string(k ? ", " : "") +
                 "{\"name\": " + json_quote(p.inputs.model->layer_names[k]) +
                 ", \"share\": " + json_number(total > 0 ? sum / total : 0.0) +
                 ", \"mean\": " + json_number(sum / n) + "}";
        }
        s += "], \"chart\": [";
        for (size_t k = 0; k < snap->chart.size(); ++k)
            s += std::string(k ? ", " : "") + "[" + std::to_string(snap->chart[k].spp) + ", " +
                 json_number(snap->chart[k].seconds) + ", " +
                 json_number(snap->chart[k].error.mse) + "]";
        s += "]";
    }
    s += ", \"notes\": " + json_strings(p.inputs.model->notes);
    s += ", \"bias\": " + json_strings(run_bias(p.options, p.inputs));
    if (!is_reference) {
        s += ", \"reference\": " + (v.has_reference ? json_quote(v.reference_source) : "null");
        s += ", \"reference_noise\": " + json_number(v.reference_noise);
    }
    return s + "}";
}

}  // namespace

std::string Studio::status_json() const {
    std::vector<PaneView> views(panes_.size());
    int live = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (size_t i = 0; i < panes_.size(); ++i) {
            const std::shared_ptr<PaneState>& p = panes_[i];
            if (!p) continue;
            PaneView& v = views[i];
            v.pane = p;
            v.snapshot = p->snapshot;
            v.state = !p->failure.empty() ? "error"
                      : p->done           ? "done"
                      : p->stop           ? "stopped"
                                          : "rendering";
            v.failure = p->failure;
            v.has_reference = p->reference != nullptr;
            v.reference_source = p->reference_source;
            v.reference_noise = p->reference_noise;
            if ((p->films || p->busy) && !p->done && !p->stop) ++live;
        }
    }
    std::string s = "{\"panes\": [";
    for (size_t i = 0; i + 1 < views.size(); ++i)
        s += std::string(i ? ", " : "") +
             (views[i].pane ? pane_json(views[i], false) : "{\"state\": \"idle\"}");
    s += "], \"reference\": " + (views.back().pane ? pane_json(views.back(), true) : "null");
    return s + ", \"live_renders\": " + std::to_string(live) + "}";
}

std::string Studio::frame_png(int pane_index, const std::string& view, float exposure) const {
    const std::shared_ptr<PaneState> p = pane(pane_index);
    std::shared_ptr<const Snapshot> snap;
    std::shared_ptr<const Image> reference;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (p) snap = p->snapshot, reference = p->reference;
    }
    if (!snap) throw RequestError("pane " + std::to_string(pane_index) + ": no frame yet");
    const RenderResult& r = snap->result;
    if (view == "error") {
        if (!reference) throw RequestError("view error: no reference for this scene and size yet");
        const std::vector<float> errors = pixel_errors(r.image, *reference);
        const double scale = error_map_scale(errors);
        std::vector<uint8_t> rgb(errors.size() * 3);
        for (size_t i = 0; i < errors.size(); ++i) {
            const auto c = viridis(static_cast<float>(errors[i] / scale));
            std::copy(c.begin(), c.end(), rgb.begin() + 3 * i);
        }
        return encode_png(r.image.width, r.image.height, rgb);
    }
    const Image image = view_image(r, view);
    return encode_png(image.width, image.height, display_bytes(image, exposure));
}

std::string Studio::probe_json(int pane_index, int x, int y, int light, int samples) const {
    const std::shared_ptr<PaneState> p = pane(pane_index);
    std::shared_ptr<const Snapshot> snap;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (p) snap = p->snapshot;
    }
    if (!p || !snap) throw RequestError("pane " + std::to_string(pane_index) + ": no render yet");
    const Scene& scene = p->inputs.scene;
    if (x < 0 || y < 0 || x >= scene.width || y >= scene.height)
        throw RequestError("x, y: outside the " + std::to_string(scene.width) + "x" +
                           std::to_string(scene.height) + " image");
    samples = std::clamp(samples, 1, 1 << 16);
    const RenderResult& r = snap->result;
    const Color L = r.image.at(x, y), var = r.variance.at(x, y);
    std::string s = "{\"x\": " + std::to_string(x) + ", \"y\": " + std::to_string(y);
    s += ", \"spp\": " + std::to_string(snap->spp);
    s += ", \"L\": " + json_color(L);
    s += ", \"L_standard_error\": " +
         json_color({std::sqrt(var.x), std::sqrt(var.y), std::sqrt(var.z)});
    s += ", \"L_units\": \"W/(sr m^2)\"";
    // The lights, for the page's choice of a direction for f.
    struct LightPoint {
        std::string what;
        Vec3 position;
    };
    std::vector<LightPoint> lights;
    for (const PointLight& l : scene.point_lights()) lights.push_back({"point light", l.position});
    for (const AreaLight& l : scene.area_lights())
        lights.push_back({"area light (" + scene.material(l.material).name + ")", l.center});
    s += ", \"lights\": [";
    for (size_t k = 0; k < lights.size(); ++k)
        s += std::string(k ? ", " : "") + json_quote(lights[k].what);
    s += "]";
    // The layers' shares of this pixel (lesson 4's bounces, lesson 5's strategies).
    s += ", \"layers\": [";
    for (size_t k = 0; k < r.layers.size(); ++k) {
        const Color v = r.layers[k].at(x, y);
        const float total = luminance(L);
        s += std::string(k ? ", " : "") +
             "{\"name\": " + json_quote(p->inputs.model->layer_names[k]) +
             ", \"value\": " + json_color(v) +
             ", \"share\": " + json_number(total > 0 ? luminance(v) / total : 0.0) + "}";
    }
    s += "]";

    const Ray ray = scene.camera.generate_ray(x + 0.5f, y + 0.5f, scene.width, scene.height);
    const std::optional<Hit> hit = scene.intersect(ray);
    if (!hit)
        return s + ", \"hit\": null, \"background\": " +
               json_color(scene.background_radiance(ray.dir)) + "}";
    const SurfaceInteraction si = scene.interaction(ray, *hit);
    const Material& m = scene.material(si.material);
    static const char* kinds[] = {"sphere", "quad", "triangle"};
    s += ", \"hit\": {\"shape\": \"" + std::string(kinds[static_cast<int>(hit->prim.kind())]) +
         " " + std::to_string(hit->prim.index()) + "\", \"material\": " + json_quote(m.name) +
         ", \"type\": \"" + material_type_name(m.type) + "\", \"distance\": " + json_number(si.t) +
         ", \"position\": " + json_color(si.p) + ", \"front\": " + (si.front ? "true" : "false") +
         "}";

    // E = integral of L_i cos(theta_i) over the hemisphere on the viewer's side, estimated from
    // the lesson's own light sampler (direct light only), with its standard error.
    const Bsdf bsdf(m, si);
    Vec3 n = bsdf.normal();
    if (glm::dot(n, si.wo) < 0.0f) n = -n;
    const Irradiance E =
        direct_irradiance(scene, si, n, samples, static_cast<uint64_t>(y) * scene.width + x);
    s += ", \"E\": " + json_color(E.mean);
    s += ", \"E_standard_error\": " + json_color(E.standard_error);
    s += ", \"E_samples\": " + std::to_string(samples) + ", \"E_units\": \"W/m^2\"";
    // f(wo, wi) towards the chosen light's position (a point light) or centre (an area light).
    if (light >= 0 && light < static_cast<int>(lights.size())) {
        const Vec3 wi = glm::normalize(lights[light].position - si.p);
        s += ", \"f_light\": " + json_quote(lights[light].what) +
             ", \"cos_theta_i\": " + json_number(glm::dot(wi, n));
        if (bsdf.is_delta())
            s += ", \"f\": null, \"f_note\": \"a delta BSDF (" +
                 std::string(material_type_name(m.type)) +
                 "): f is a Dirac distribution, nonzero only along the mirror or refracted "
                 "direction, with no finite value\"";
        else
            s += ", \"f\": " + json_color(bsdf.eval(si.wo, wi));
        s += ", \"f_units\": \"1/sr\"";
    }
    return s + "}";
}

std::string Studio::download(int pane_index, const std::string& format, float exposure,
                             int* spp) const {
    const std::shared_ptr<PaneState> p = pane(pane_index);
    std::shared_ptr<const Snapshot> snap;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (p) snap = p->snapshot;
    }
    if (!p || !snap) throw RequestError("pane " + std::to_string(pane_index) + ": no render yet");
    if (format != "exr" && format != "png")
        throw RequestError("format: '" + format + "' is not exr or png");
    *spp = snap->spp;
    if (format == "png")
        return encode_png(snap->result.image.width, snap->result.image.height,
                          display_bytes(snap->result.image, exposure));
    // The CLI's own writer, so the bytes are the CLI's.
    static std::atomic<uint64_t> counter{0};
    fs::create_directories(cache_);
    const std::string tmp = (fs::path(cache_) / ("download_" + std::to_string(::getpid()) + "_" +
                                                 std::to_string(counter++) + ".exr"))
                                .string();
    write_exr(snap->result.image, tmp);
    std::string bytes = read_file_bytes(tmp);
    std::error_code ec;
    fs::remove(tmp, ec);
    return bytes;
}

}  // namespace lessons::studio
