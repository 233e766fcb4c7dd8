// The references the panes' error charts measure against: the shipped ones (references/) and
// lessons.sh's (out/), found on disk; the studio's own, cached by what the scene was made of; or
// one rendered in the background (lesson 5 at Limits::reference_spp), which every pane of that
// scene, size and albedo takes when done.
#include <toml++/toml.h>

#include <algorithm>
#include <cstdio>

#include "farm/part.h"
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

// What a reference's provenance file (reference.toml beside it: scripts/references.sh) says.
struct Provenance {
    std::string scene_files, lesson, commit;
    int width = 0, height = 0, spp = 0;
};
std::optional<Provenance> read_provenance(const fs::path& file) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return std::nullopt;
    try {
        const toml::table t = toml::parse_file(file.string());
        Provenance p;
        p.scene_files = t["scene_files"].value_or(std::string());
        p.lesson = t["lesson"].value_or(std::string());
        p.commit = t["commit"].value_or(std::string());
        p.width = t["width"].value_or(0);
        p.height = t["height"].value_or(0);
        p.spp = t["spp"].value_or(0);
        return p;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

// The reference image and its noise (the mean of its variance image, when there is one), if it
// is of the pane's size.
std::optional<FoundReference> read_images(const fs::path& exr, const fs::path& variance,
                                          const PaneState& pane, const std::string& source) {
    const int width = pane.inputs.scene.width, height = pane.inputs.scene.height;
    std::error_code ec;
    try {
        auto image = std::make_shared<Image>(read_exr(exr.string()));
        if (image->width != width || image->height != height) return std::nullopt;
        FoundReference found{image, source, 0.0};
        if (fs::is_regular_file(variance, ec)) {
            const Image v = read_exr(variance.string());
            if (v.width == width && v.height == height) found.noise = mean_variance(v);
        }
        return found;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

// The reference in `dir` (reference.exr, reference_variance.exr) if it is of the pane's size and
// scene: by its provenance where it has one (reference.toml: the hash of the files the scene was
// made of, against the files the pane loaded; file times mean nothing in a fresh clone), else by
// its time (not older than any of those files).
std::optional<FoundReference> read_reference_file(const fs::path& dir, const PaneState& pane) {
    const fs::path exr = dir / "reference.exr";
    std::error_code ec;
    if (!fs::is_regular_file(exr, ec)) return std::nullopt;
    std::string source = exr.string();
    if (const std::optional<Provenance> p = read_provenance(dir / "reference.toml")) {
        if (p->width != pane.inputs.scene.width || p->height != pane.inputs.scene.height)
            return std::nullopt;
        try {
            if (scene_files_hash(pane.inputs.scene, pane.options.limits) != p->scene_files)
                return std::nullopt;
        } catch (const std::exception&) {
            return std::nullopt;
        }
        source += " (" + p->lesson + ", " + std::to_string(p->spp) + " spp, rendered at commit " +
                  p->commit.substr(0, 7) + "; its provenance: reference.toml beside it)";
    } else if (fs::last_write_time(exr, ec) < newest_input(pane.inputs.scene.input_files)) {
        return std::nullopt;  // rendered from another version of the scene's files
    }
    return read_images(exr, dir / "reference_variance.exr", pane, source);
}

// The studio's own reference, cached under `stem` (cache_stem), if not older than the scene's
// files.
std::optional<FoundReference> read_cached_reference(const std::string& stem,
                                                    const PaneState& pane) {
    const fs::path exr = stem + ".exr";
    std::error_code ec;
    if (!fs::is_regular_file(exr, ec) ||
        fs::last_write_time(exr, ec) < newest_input(pane.inputs.scene.input_files))
        return std::nullopt;
    return read_images(exr, stem + "_variance.exr", pane, "the studio's cache: " + exr.string());
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

std::pair<int, int> provenance_size(const std::vector<std::string>& references,
                                    const std::string& scene_path) {
    for (const std::string& dir : references)
        if (const std::optional<Provenance> p =
                read_provenance(fs::path(dir) / fs::path(scene_path).stem() / "reference.toml"))
            return {p->width, p->height};
    return {0, 0};
}

std::optional<FoundReference> find_reference(const std::vector<std::string>& references,
                                             const std::string& cache, const SceneEntry& scene,
                                             const PaneState& pane, int reference_spp) {
    const int w = pane.inputs.scene.width, h = pane.inputs.scene.height;
    const std::vector<std::string>& inputs = pane.inputs.scene.input_files;
    // A shipped or lessons.sh's reference for this scene and size, else the studio's own. (They
    // are of the scenes as they are: none has --albedo.)
    const float albedo = pane.options.albedo;
    if (albedo < 0.0f)
        for (const std::string& dir : references)
            if (auto found = read_reference_file(fs::path(dir) / fs::path(scene.path).stem(), pane))
                return found;
    const std::string stem = cache_stem(cache, scene, inputs, w, h, albedo, reference_spp);
    return read_cached_reference(stem, pane);
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
