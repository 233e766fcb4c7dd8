// What the page reads of the renders: the status of every pane (JSON, polled), a pane's frame
// (PNG: the image, a layer, the layers so far, or the error against the reference) and its
// download (the CLI's EXR or PNG bytes). Also the JSON pieces the probe shares.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "io/report.h"
#include "io/shipped_files.h"
#include "render/metrics.h"
#include "studio_internal.h"

namespace lessons::studio {

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

namespace {

// What the status says of one render: copied under the studio's lock, written out after it.
struct PaneView {
    std::shared_ptr<const PaneState> pane;  // its fixed parts: command line, scene, model
    std::shared_ptr<const Snapshot> snapshot;
    std::string state, failure, reference_source;
    bool has_reference = false;
    double reference_noise = 0.0;
};

// What a render has reached: its times and rays, and each layer's share of the image's
// luminance (lesson 4's bounces: the series), and the error chart.
std::string snapshot_json(const Snapshot& snap, const std::vector<std::string>& layer_names) {
    const RenderStats& st = snap.result.stats;
    const double n = static_cast<double>(std::max<size_t>(1, snap.result.image.pixels.size()));
    std::string s = ", \"seconds\": " + json_number(st.seconds);
    s += ", \"wall_seconds\": " + json_number(snap.wall_seconds);
    s += ", \"rays\": " + std::to_string(st.rays);
    s += ", \"mrays_per_second\": " +
         json_number(st.seconds > 0 ? st.rays / st.seconds * 1e-6 : 0.0);
    s += ", \"nan_samples\": " + std::to_string(snap.result.nan_samples);
    s += ", \"inf_samples\": " + std::to_string(snap.result.inf_samples);
    s += ", \"mean_luminance\": " + json_number(snap.image_luminance / n);
    s += ", \"layers\": [";
    for (size_t k = 0; k < snap.layer_luminance.size(); ++k) {
        const double sum = snap.layer_luminance[k], total = snap.image_luminance;
        s += std::string(k ? ", " : "") + "{\"name\": " + json_quote(layer_names[k]) +
             ", \"share\": " + json_number(total > 0 ? sum / total : 0.0) +
             ", \"mean\": " + json_number(sum / n) + "}";
    }
    s += "], \"chart\": [";
    for (size_t k = 0; k < snap.chart.size(); ++k)
        s += std::string(k ? ", " : "") + "[" + std::to_string(snap.chart[k].spp) + ", " +
             json_number(snap.chart[k].seconds) + ", " + json_number(snap.chart[k].error.mse) + "]";
    return s + "]";
}

std::string pane_json(const PaneView& v, bool is_reference) {
    const PaneState& p = *v.pane;
    const Snapshot* snap = v.snapshot.get();
    // The lesson's program beside the studio's (build/bin/ or an install's bin/).
    std::string command = (program_dir() / p.args[0]).string();
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
    if (snap) s += snapshot_json(*snap, p.inputs.model->layer_names);
    s += ", \"notes\": " + json_strings(p.inputs.model->notes);
    s += ", \"bias\": " + json_strings(run_bias(p.options, p.inputs));
    if (!is_reference) {
        s += ", \"reference\": " + (v.has_reference ? json_quote(v.reference_source) : "null");
        s += ", \"reference_noise\": " + json_number(v.reference_noise);
    }
    return s + "}";
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

// The per-pixel RMS error against the reference, in the viridis colour map.
std::string error_png(const Image& image, const Image& reference) {
    const std::vector<float> errors = pixel_errors(image, reference);
    const double scale = error_map_scale(errors);
    std::vector<uint8_t> rgb(errors.size() * 3);
    for (size_t i = 0; i < errors.size(); ++i) {
        const auto c = viridis(static_cast<float>(errors[i] / scale));
        std::copy(c.begin(), c.end(), rgb.begin() + 3 * i);
    }
    return encode_png(image.width, image.height, rgb);
}

std::string read_file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
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

std::pair<std::shared_ptr<PaneState>, std::shared_ptr<const Snapshot>> Studio::rendered(
    int pane_index) const {
    const std::shared_ptr<PaneState> p = pane(pane_index);
    std::shared_ptr<const Snapshot> snap;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (p) snap = p->snapshot;
    }
    if (!p || !snap) throw RequestError("pane " + std::to_string(pane_index) + ": no render yet");
    return {p, snap};
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
        return error_png(r.image, *reference);
    }
    const Image image = view_image(r, view);
    return encode_png(image.width, image.height, display_bytes(image, exposure));
}

std::string Studio::download(int pane_index, const std::string& format, float exposure,
                             int* spp) const {
    const std::shared_ptr<const Snapshot> snap = rendered(pane_index).second;
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
