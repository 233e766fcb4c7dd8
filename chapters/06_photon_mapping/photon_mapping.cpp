// Lesson 6: the model (see photon_mapping.h): each pass's photons, and each pixel sample by the
// method asked for.
#include "06_photon_mapping/photon_mapping.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "06_photon_mapping/radius.h"
#include "io/input_error.h"

namespace lessons {

const char* photon_method_name(PhotonMethod m) {
    for (const auto& [name, method] : kPhotonMethodNames)
        if (method == m) return name;
    return "?";
}

float pass_radius(float r1, float alpha, int k) {
    return r1 * std::pow(static_cast<float>(k + 1), (alpha - 1.0f) / 2.0f);
}

float default_alpha(PhotonMethod m) {
    switch (m) {
        case PhotonMethod::PhotonMapping:
        case PhotonMethod::VirtualLights: return 1.0f;
        case PhotonMethod::Progressive: return 2.0f / 3.0f;
        case PhotonMethod::Bidirectional:
        case PhotonMethod::VertexMerging: return 0.75f;
    }
    return 1.0f;
}

bool merges_in(const Scene& scene, Merging merging) {
    switch (merging) {
        case Merging::Always: return true;
        case Merging::Never: return false;
        case Merging::Auto: break;
    }
    return scene.contents().delta_materials;
}

namespace {

// The options with the method that runs: vcm that does not merge in this scene runs as bpt.
PhotonOptions method_that_runs(const Scene& scene, PhotonOptions options) {
    if (options.method == PhotonMethod::VertexMerging && !merges_in(scene, options.merging))
        options.method = PhotonMethod::Bidirectional;
    return options;
}

bool uses_photons(PhotonMethod m) {
    return m != PhotonMethod::Bidirectional;
}
bool joins(PhotonMethod m) {
    return m == PhotonMethod::Bidirectional || m == PhotonMethod::VertexMerging;
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

// The technique images of each method, adding up to the image (--techniques).
std::vector<std::string> technique_names(PhotonMethod m) {
    if (joins(m)) return {"connection", "merging", "light_tracing"};
    if (m == PhotonMethod::VirtualLights) return {"direct", "vpl", "compensation"};
    return {"direct", "photons"};
}

}  // namespace

// What the photon methods cannot find in this scene, as notes or as bias.
void PhotonMappingModel::add_what_it_misses(const Scene& scene) {
    const SceneContents contents = scene.contents();
    const bool joined = options_.method == PhotonMethod::VertexMerging;
    const bool virtual_lights = options_.method == PhotonMethod::VirtualLights;
    if (contents.environment)
        (joined ? notes : biased_because)
            .push_back(joined           ? "the sky leaves no photons: its light is found by the "
                                          "joins (camera paths escaping, light samples), as in "
                                          "lesson 5"
                       : virtual_lights ? "the sky starts no light subpaths, so no virtual light "
                                          "carries its light: after a bounce it is missing (only "
                                          "the light sample at the first diffuse vertex sees it)"
                                        : "the sky leaves no photons: its light after a bounce is "
                                          "missing (only the light sample at the first diffuse "
                                          "vertex sees it)");
    if (virtual_lights && contents.delta_materials)
        biased_because.push_back(
            "light that reaches the first diffuse point the camera sees off a mirror or through "
            "glass (a caustic, S+ D S* E) is missing: a virtual light's join and a light sample "
            "are straight segments, which cannot bounce off a mirror or pass through glass");
    if ((contents.point_lights || contents.directional_lights) && contents.delta_materials)
        biased_because.push_back(
            std::string("a point or directional light seen in a mirror or through glass is "
                        "missing: a delta light, a delta BSDF and the pinhole make a path no "
                        "estimator can") +
            (virtual_lights ? "" : " (its caustics, seen any way, are the photons')"));
    if (contents.point_light_in_view && !joined)
        biased_because.push_back(
            std::string("a point light in view is missing: no camera ray hits a point, and ") +
            (virtual_lights ? "instant radiosity" : "photon mapping") +
            " does not join the light to the camera (vcm and bpt do)");
}

// bpt's notes (and vcm's where it does not merge): lesson 5's, which says what it ignores and
// misses here in the same words, for the same image, and the method as asked.
void PhotonMappingModel::add_bpt_notes(const Scene& scene, const PhotonOptions& options) {
    const BidirectionalModel lesson5(scene, options.paths);
    notes = lesson5.notes;
    biased_because = lesson5.biased_because;
    if (asked_ == PhotonMethod::VertexMerging)
        notes.insert(notes.begin(),
                     options.merging == Merging::Never
                         ? "method vcm with --merging never: no merges, so lesson 5's "
                           "bidirectional path tracing, the same image bit for bit"
                         : "method vcm, merging left out: the scene has no mirror or smooth "
                           "glass, so every path has a join and none needs a merge; vcm is "
                           "lesson 5's bidirectional path tracing here, the same image bit "
                           "for bit (--merging always merges anyway, at its cost)");
    else
        notes.insert(notes.begin(),
                     "method bpt: lesson 5's bidirectional path tracing (vertex connection "
                     "without merging): the same image, bit for bit");
}

PhotonMappingModel::PhotonMappingModel(const Scene& scene, const PhotonOptions& options)
    : lights_(scene),
      b_{scene, lights_, scene.camera, scene.width, scene.height},
      options_(method_that_runs(scene, options)),
      asked_(options.method) {
    const PhotonMethod m = options_.method;
    passes = true;      // each pass has its photons
    splats = joins(m);  // bpt and vcm trace light onto the pixels it lands on
    alpha_ = options.alpha > 0.0f ? options.alpha : default_alpha(m);
    r1_ = options.radius > 0.0f ? options.radius : default_photon_radius(scene);
    if (options.technique_layers) layer_names = technique_names(m);
    if (m == PhotonMethod::VirtualLights) {
        clamp_ = options.vpl_clamp >= 0.0f ? options.vpl_clamp : default_vpl_clamp(scene);
        add_vpl_notes(scene);
        return;
    }
    if (m == PhotonMethod::Bidirectional) {
        add_bpt_notes(scene, options);
        return;
    }
    const bool fixed = alpha_ >= 1.0f;
    const std::string radius =
        "radius " + number(r1_) +
        (fixed ? " (fixed)" : " shrinking as (k + 1)^" + number((alpha_ - 1.0f) / 2.0f));
    notes.push_back(m == PhotonMethod::VertexMerging
                        ? "method vcm: lesson 5's strategies and a merge at every diffuse camera "
                          "vertex, all weighted by MIS (power heuristic); " +
                              radius
                        : std::string("method ") + photon_method_name(m) +
                              ": the photons at the first diffuse camera vertex, direct light by "
                              "a light sample there; " +
                              radius);
    notes.push_back(std::string("kernel ") + kernel_name(options.kernel) + "; " +
                    std::to_string(scene.width * scene.height) +
                    " light subpaths per pass leave the photons");
    if (fixed)
        biased_because.push_back("a fixed radius " + number(r1_) +
                                 ": the photons' light is blurred over it however long it renders "
                                 "(--alpha below 1 shrinks it)");
    else
        consistent_bias.push_back(
            "the photons' blur over the radius, at every finite number of passes; it shrinks "
            "with the radius, and with it the bias");
    add_what_it_misses(scene);
    add_path_length_notes(*this, options.paths.max_depth, options.paths.roulette_after);
    if (lights_.empty()) notes.push_back("the scene has no lights: only emission is visible");
}

// Instant radiosity's notes: the method, the cap and what it does to the image, and what virtual
// lights cannot find.
void PhotonMappingModel::add_vpl_notes(const Scene& scene) {
    notes.push_back("method vpl: instant radiosity, " + std::to_string(options_.vpls) +
                    " light subpaths per pass whose vertices are virtual point lights, each "
                    "joined to the first diffuse camera vertex by a shadow ray; direct light by "
                    "a light sample there");
    const std::string cap = "the cap " + number(clamp_) + " on G = cos cos / d^2";
    if (!(clamp_ > 0.0f))
        notes.push_back("no cap on G (--vpl-clamp 0): unbiased, with bright blotches where "
                        "virtual lights lie near the points they light (corners)");
    else if (options_.vpl_compensate)
        notes.push_back(cap + ", compensated (--vpl-compensate): a BSDF sample restores what the "
                              "cap removes, so the image is unbiased");
    else
        biased_because.push_back(cap + ": connections shorter than about " +
                                 number(1.0 / std::sqrt(clamp_)) +
                                 " lose light (darker corners and contact shadows); "
                                 "--vpl-compensate restores it, --vpl-clamp 0 removes the cap");
    add_what_it_misses(scene);
    add_path_length_notes(*this, options_.paths.max_depth, options_.paths.roulette_after);
    if (lights_.empty()) notes.push_back("the scene has no lights: only emission is visible");
}

void PhotonMappingModel::begin_pass(int k, const RenderSettings& settings) const {
    if (!uses_photons(options_.method) || (pass_.index == k && pass_.seed == settings.seed)) return;
    const int longest = longest_path(options_.paths.max_depth);
    PhotonPass& pass = pass_;
    pass.grid = PhotonGrid{};  // the last pass's grid back first; its light subpaths' arrays are
                               // traced into again
    pass.virtual_lights.clear();  // they point into those arrays
    pass.index = -1;           // no pass until this one is whole
    pass.radius = pass_radius(r1_, alpha_, k);
    // vcm joins the light subpaths' vertices and weighs each photon by them; photon mapping
    // needs only the photons.
    const bool merging = options_.method == PhotonMethod::VertexMerging;
    const bool virtual_lights = options_.method == PhotonMethod::VirtualLights;
    trace_photons(b_, settings.seed, k, virtual_lights ? options_.vpls : b_.width * b_.height,
                  longest, options_.paths.roulette_after, settings.threads,
                  merging || virtual_lights, pass.paths);
    rays_ += pass.paths.rays;
    if (merging) {
        const double eta =
            static_cast<double>(std::max(pass.paths.count, 1)) * kPi * pass.radius * pass.radius;
        weigh_photons(b_, pass.paths, eta, settings.threads);
    }
    if (virtual_lights)
        pass.virtual_lights = lessons::virtual_lights(pass.paths);
    else
        pass.grid = PhotonGrid(pass.paths.photons, pass.radius, settings.threads);
    const size_t bytes = pass.bytes();  // the subpaths, the photons and the grid's copy of them
    if (bytes > options_.max_photon_mb * 1048576.0) {
        pass = PhotonPass{};  // nothing of a refused pass is kept, or reused
        throw InputError("command line", 0, "--max-photon-mb",
                         "the photons of pass " + std::to_string(k) + " take " +
                             number(static_cast<double>(bytes) / 1048576.0) +
                             " MiB, over the cap of " + number(options_.max_photon_mb) +
                             " MiB (a smaller image, a shorter --max-depth, or a larger cap)");
    }
    pass.index = k;
    pass.seed = settings.seed;
    most_bytes_ = std::max(most_bytes_, bytes);
    photons_ += pass.paths.photons.size();
    ++passes_;
    if (first_pass_ < 0 || k < first_pass_) first_pass_ = k;
    last_pass_ = std::max(last_pass_, k);
}

Color PhotonMappingModel::sample(const Ray& ray, Rng& rng, uint32_t pixel, std::span<Color> layers,
                                 std::vector<Splat>& splats) const {
    if (uses_photons(options_.method) && pass_.index < 0)
        throw std::logic_error(
            "lesson 6 samples pass by pass, after begin_pass traced the photons");
    if (options_.method == PhotonMethod::VirtualLights)
        return instant_radiosity(b_, pass_.virtual_lights, pass_.paths.count, ray, rng,
                                 {options_.paths, clamp_, options_.vpl_compensate}, layers);
    if (!joins(options_.method)) return photon_mapping(b_, pass_, ray, rng, options_, layers);
    return connect_and_merge(ray, rng, pixel, layers, splats);
}

Color PhotonMappingModel::connect_and_merge(const Ray& ray, Rng& rng, uint32_t pixel,
                                            std::span<Color> layers,
                                            std::vector<Splat>& splats) const {
    const bool merging = options_.method == PhotonMethod::VertexMerging;
    thread_local std::vector<Vertex> camera, own_light;
    std::span<const Vertex> light;
    if (merging) {
        // The pass's light subpath of this pixel's index (its photons are the pass's too).
        const int longest = longest_path(options_.paths.max_depth);
        camera_subpath(b_, ray, rng, longest + 1, options_.paths.roulette_after, camera);
        light = pass_.paths.subpath(pixel);
    } else {
        trace_subpaths(b_, ray, rng, options_.paths, camera, own_light);  // lesson 5's
        light = own_light;
    }
    const double eta = merging ? static_cast<double>(std::max(pass_.paths.count, 1)) * kPi *
                                     pass_.radius * pass_.radius
                               : 0.0;
    // The joins, weighed with the merges among their techniques (bpt: as lesson 5 weighs them).
    const MergeTechnique merge_technique(eta);
    Color L(0.0f);
    for_each_strategy(b_, camera, light, rng, options_.paths, merging ? &merge_technique : nullptr,
                      [&](int, int t, const StrategySample& c, const Color& contribution) {
                          if (t == 1) {  // light tracing, onto the pixel it lands on
                              splats.push_back({*c.pixel, 0, contribution});
                              if (!layers.empty()) splats.push_back({*c.pixel, 3, contribution});
                              return;
                          }
                          L += contribution;
                          if (!layers.empty()) layers[0] += contribution;
                      });
    if (merging) {
        const Color merged = merges(pass_, camera, options_);
        L += merged;
        if (!layers.empty()) layers[1] += merged;
    }
    return L;
}

void PhotonMappingModel::report(Report& report) const {
    report.set("method", photon_method_name(asked_));
    if (asked_ == PhotonMethod::VertexMerging)
        report.set("merging", options_.method == PhotonMethod::VertexMerging);
    if (!uses_photons(options_.method)) return;
    if (options_.method == PhotonMethod::VirtualLights) {
        report.set("vpl_paths", static_cast<uint64_t>(options_.vpls));
        report.set("vpl_clamp", static_cast<double>(clamp_));
        report.set("vpl_compensate", options_.vpl_compensate);
        report.set("photon_bytes", static_cast<uint64_t>(most_bytes_));
        report.set("vpls_per_pass", passes_ > 0 ? static_cast<double>(photons_) / passes_ : 0.0);
        return;
    }
    report.set("kernel", kernel_name(options_.kernel));
    report.set("alpha", static_cast<double>(alpha_));
    report.set("radius_first", static_cast<double>(r1_));
    if (last_pass_ >= 0)
        report.set("radius_reached", static_cast<double>(pass_radius(r1_, alpha_, last_pass_)));
    report.set("photon_bytes", static_cast<uint64_t>(most_bytes_));
    report.set("photons_per_pass", passes_ > 0 ? static_cast<double>(photons_) / passes_ : 0.0);
}

}  // namespace lessons
