// The references the panes' error charts measure against: lessons.sh's, found on disk; the
// studio's own, cached by what the scene was made of; or one rendered in the background (lesson
// 5 at Limits::reference_spp), which every pane of that scene, size and albedo takes when done.
#include <algorithm>
#include <cstdio>

#include "io/input_file.h"
#include "studio_internal.h"

namespace lessons::studio {

namespace {

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

// The reference render's command line: the lesson's, with another seed than any pane's default.
std::vector<std::string> reference_command_line(const std::string& lesson,
                                                const std::string& scene_path, int width,
                                                int height, int spp, float albedo) {
    // Independent samples: the chart's noise line is this render's variance, the error of its
    // mean only for independent samples (docs/studio.md).
    std::vector<std::string> args{lesson,
                                  "--scene",
                                  scene_path,
                                  "--width",
                                  std::to_string(width),
                                  "--height",
                                  std::to_string(height),
                                  "--spp",
                                  std::to_string(spp),
                                  "--seed",
                                  "1000003",
                                  "--sampler",
                                  "independent"};
    if (albedo >= 0.0f) {
        args.push_back("--albedo");
        args.push_back(std::to_string(albedo));
    }
    return args;
}

}  // namespace

double mean_variance(const Image& variance) {
    double sum = 0.0;
    for (const Color& c : variance.pixels) sum += (double(c.x) + c.y + c.z) / 3.0;
    return variance.pixels.empty() ? 0.0 : sum / static_cast<double>(variance.pixels.size());
}

std::string cache_stem(const std::string& cache, const SceneEntry& scene,
                       const std::vector<std::string>& inputs, int width, int height, float albedo,
                       int spp) {
    std::string name = scene.id;
    std::replace(name.begin(), name.end(), '/', '_');
    name += std::string("_") + kReferenceLesson;  // the lesson that rendered it
    if (albedo >= 0.0f) name += "_albedo" + std::to_string(albedo);
    char buf[64];
    std::snprintf(buf, sizeof buf, "_%dx%d_%dspp_%016llx", width, height, spp,
                  static_cast<unsigned long long>(inputs_hash(inputs)));
    return (fs::path(cache) / (name + buf)).string();
}

std::optional<FoundReference> find_reference(const std::string& references,
                                             const std::string& cache, const SceneEntry& scene,
                                             const PaneState& pane, int reference_spp) {
    const int w = pane.inputs.scene.width, h = pane.inputs.scene.height;
    const std::vector<std::string>& inputs = pane.inputs.scene.input_files;
    // lessons.sh's for this scene and size, else the studio's own. (lessons.sh renders the
    // scenes as they are: no reference of theirs has --albedo.)
    const float albedo = pane.options.albedo;
    std::optional<FoundReference> found;
    const fs::path lessons_dir = fs::path(references) / fs::path(scene.path).stem();
    if (albedo < 0.0f)
        found = read_reference_file(lessons_dir / "reference.exr",
                                    lessons_dir / "reference_variance.exr", w, h, inputs,
                                    "scripts/lessons.sh:");
    if (!found) {
        const std::string stem = cache_stem(cache, scene, inputs, w, h, albedo, reference_spp);
        found = read_reference_file(stem + ".exr", stem + "_variance.exr", w, h, inputs,
                                    "the studio's cache:");
    }
    return found;
}

bool same_image(const PaneState& a, const PaneState& b) {
    return a.scene_id == b.scene_id && a.inputs.scene.width == b.inputs.scene.width &&
           a.inputs.scene.height == b.inputs.scene.height && a.options.albedo == b.options.albedo;
}

void cache_reference(const PaneState& job, const RenderResult& result) {
    try {
        fs::create_directories(fs::path(job.reference_path).parent_path());
        write_exr(result.image, job.reference_path + ".exr");
        write_exr(result.variance, job.reference_path + "_variance.exr");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "studio: cannot cache the reference: %s\n", e.what());
    }
}

void stop_unwanted_reference(const std::vector<std::shared_ptr<PaneState>>& panes) {
    const auto& ref = panes.back();
    if (!ref || ref->done) return;
    bool wanted = false;
    for (size_t i = 0; i + 1 < panes.size(); ++i)
        wanted |= panes[i] && !panes[i]->reference && same_image(*panes[i], *ref);
    if (!wanted) {
        ref->stop = true;
        if (!ref->busy) ref->films.reset();
    }
}

void Studio::want_reference(const SceneEntry& scene, int width, int height, float albedo) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto& current = panes_.back();
        if (current && !current->done && !current->stop && current->scene_id == scene.id &&
            current->inputs.scene.width == width && current->inputs.scene.height == height &&
            current->options.albedo == albedo)
            return;  // already rendering it
    }
    // The reference is lesson 5's (unbiased for every scene the suite has: it finds point-light
    // caustics and the lamps' caustics that lesson 4 misses or finds by chance; lesson 6's
    // methods are biased, if consistent).
    const RegisteredLesson* registered = find_lesson(kReferenceLesson);
    if (!registered) return;
    auto state = std::make_shared<PaneState>();
    state->is_reference = true;
    state->scene_id = scene.id;
    state->args = reference_command_line(registered->name, scene.path, width, height,
                                         limits_.reference_spp, albedo);
    state->lesson = registered->make();
    try {
        load_run(*state);
    } catch (const std::exception&) {
        return;  // the pane's own load succeeded, so this cannot fail but for memory
    }
    state->reference_path = cache_stem(cache_, scene, state->inputs.scene.input_files, width,
                                       height, albedo, limits_.reference_spp);
    make_films(*state, 0.0f, limits_.reference_spp, limits_.threads);
    std::lock_guard<std::mutex> lock(mutex_);
    state->generation = next_generation_++;
    if (panes_.back()) panes_.back()->stop = true;
    panes_.back() = state;
}

}  // namespace lessons::studio
