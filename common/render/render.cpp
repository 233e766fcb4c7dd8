// The tiled, multi-threaded render loop (see render.h).
#include "render/render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "render/progress.h"
#include "scene/scene.h"

namespace lessons {

namespace {

constexpr int kTileSize = 16;

// The image's tiles, row by row.
struct Tiles {
    int width, height, across, count;
    Tiles(int w, int h)
        : width(w),
          height(h),
          across((w + kTileSize - 1) / kTileSize),
          count(across * ((h + kTileSize - 1) / kTileSize)) {}
    // Calls pixel(x, y, index) for every pixel of tile `tile`; returns the number of pixels.
    template <class PixelFn>
    uint64_t for_each_pixel(int tile, PixelFn&& pixel) const {
        const int x0 = (tile % across) * kTileSize, y0 = (tile / across) * kTileSize;
        const int x1 = std::min(x0 + kTileSize, width), y1 = std::min(y0 + kTileSize, height);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) pixel(x, y, static_cast<size_t>(y) * width + x);
        return static_cast<uint64_t>(x1 - x0) * (y1 - y0);
    }
};

// Where the films lie in the whole image (RenderSettings::image_width).
struct Window {
    int image_width, image_height, x0, y0;
    Window(const RenderSettings& s, const Film& film)
        : image_width(s.image_width > 0 ? s.image_width : film.width()),
          image_height(s.image_width > 0 ? s.image_height : film.height()),
          x0(s.image_width > 0 ? s.crop_x : 0),
          y0(s.image_width > 0 ? s.crop_y : 0) {
        if (x0 < 0 || y0 < 0 || x0 + film.width() > image_width ||
            y0 + film.height() > image_height)
            throw std::logic_error("render: the crop lies outside the image");
    }
    // The index of film pixel (x, y) in the whole image: its random numbers' key.
    size_t image_index(int x, int y) const {
        return static_cast<size_t>(y0 + y) * image_width + (x0 + x);
    }
};

// Runs work(tile) for every tile on the worker threads, which take tiles in turn until none is
// left or settings.stop is set. Rethrows the first exception a worker met, after the join.
struct TileRun {
    uint64_t rays = 0;
    bool stopped = false;
};
template <class WorkFn>
TileRun run_tiles(int tile_count, const RenderSettings& settings, WorkFn&& work) {
    std::atomic<int> next_tile{0};
    std::atomic<uint64_t> rays{0};
    std::atomic<bool> stopped{false};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto worker = [&]() {
        const uint64_t rays_before = rays_traced_by_this_thread();
        try {
            for (int tile = next_tile++; tile < tile_count; tile = next_tile++) {
                if (settings.stop && settings.stop->load(std::memory_order_relaxed)) {
                    stopped = true;
                    break;
                }
                work(tile);
            }
        } catch (...) {
            // Stop every worker and hand the exception to the caller after the join.
            std::lock_guard lock(failure_mutex);
            if (!failure) failure = std::current_exception();
            next_tile = tile_count;
        }
        rays += rays_traced_by_this_thread() - rays_before;
    };
    const int threads = std::min(resolve_thread_count(settings.threads), std::max(1, tile_count));
    std::vector<std::thread> pool;
    for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    return {rays.load(), stopped.load()};
}

// The random numbers of sample s of pixel `pixel`.
Rng sample_rng(const RenderSettings& settings, size_t pixel, int s) {
    switch (settings.sampler) {
        case RenderSettings::Sampler::Kronecker: return Rng::kronecker(settings.seed, pixel, s);
        case RenderSettings::Sampler::Sobol: return Rng::sobol(settings.seed, pixel, s);
        default: return Rng(settings.seed, pixel, static_cast<uint64_t>(s));
    }
}

// The camera ray through film pixel (x, y), placed in it by the sample's first two numbers.
Ray camera_ray(const Camera& camera, const RenderSettings& settings, const Window& window, int x,
               int y, Rng& rng) {
    const Vec2 j = settings.jitter ? rng.uniform2() : Vec2(0.5f);
    return camera.generate_ray(window.x0 + x + j.x, window.y0 + y + j.y, window.image_width,
                               window.image_height);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Pixel by pixel: each tile's pixels take samples [sample_begin, sample_end) in turn.
RenderStats render_pixels(const Camera& camera, std::span<Film> films,
                          const RenderSettings& settings, const Model& model, int sample_begin,
                          int sample_end) {
    const auto start = std::chrono::steady_clock::now();
    const Tiles tiles(films[0].width(), films[0].height());
    const Window window(settings, films[0]);
    const size_t layer_count = films.size() - 1;
    const int samples = std::max(0, sample_end - sample_begin);
    Progress own_progress("render", static_cast<uint64_t>(tiles.width) * tiles.height * samples,
                          settings.progress && !settings.shared_progress);
    Progress& progress = settings.shared_progress ? *settings.shared_progress : own_progress;

    const TileRun run = run_tiles(tiles.count, settings, [&](int tile) {
        std::vector<Color> layers(layer_count);
        std::vector<Splat> none;  // the model does not splat (render() checked)
        const uint64_t pixels = tiles.for_each_pixel(tile, [&](int x, int y, size_t pixel) {
            const size_t index = window.image_index(x, y);
            for (int s = sample_begin; s < sample_end; ++s) {
                Rng rng = sample_rng(settings, index, s);
                const Ray ray = camera_ray(camera, settings, window, x, y, rng);
                std::fill(layers.begin(), layers.end(), Color(0.0f));
                const Color value =
                    model.sample(ray, rng, static_cast<uint32_t>(index), layers, none);
                films[0].add_sample(pixel, value);
                const float scale = films[0].clamp_scale(value);
                for (size_t k = 0; k < layer_count; ++k)
                    films[1 + k].add_sample(pixel, scale * layers[k]);
            }
            if (!none.empty())
                throw std::logic_error("render: a model that does not say it splats splatted");
        });
        progress.advance(pixels * samples);
    });
    if (!settings.shared_progress) progress.finish();
    RenderStats stats;
    stats.seconds = seconds_since(start);
    stats.rays = run.rays;
    stats.stopped = run.stopped;
    return stats;
}

// One pass: the sample of index s of every pixel of the films into `pass` (one image per film),
// each tile's splats into its list.
TileRun render_pass(const Camera& camera, const RenderSettings& settings, const Model& model,
                    const Tiles& tiles, const Window& window, int s,
                    std::vector<std::vector<Color>>& pass,
                    std::vector<std::vector<Splat>>& tile_splats, Progress& progress) {
    const size_t layer_count = pass.size() - 1;
    return run_tiles(tiles.count, settings, [&](int tile) {
        std::vector<Color> layers(layer_count);
        std::vector<Splat>& splats = tile_splats[tile];
        splats.clear();
        const uint64_t pixels = tiles.for_each_pixel(tile, [&](int x, int y, size_t pixel) {
            const size_t index = window.image_index(x, y);
            Rng rng = sample_rng(settings, index, s);
            const Ray ray = camera_ray(camera, settings, window, x, y, rng);
            std::fill(layers.begin(), layers.end(), Color(0.0f));
            pass[0][pixel] = model.sample(ray, rng, static_cast<uint32_t>(index), layers, splats);
            for (size_t k = 0; k < layer_count; ++k) pass[1 + k][pixel] = layers[k];
        });
        if (!model.splats && !splats.empty())
            throw std::logic_error("render: a model that does not say it splats splatted");
        progress.advance(pixels);
    });
}

// A finished pass into the films: the tiles' splats added to the pass's images in tile order,
// then every pixel's value as its sample. Returns the memory the splats held.
size_t add_pass(std::span<Film> films, std::vector<std::vector<Color>>& pass,
                const std::vector<std::vector<Splat>>& tile_splats) {
    size_t bytes = 0;
    for (const std::vector<Splat>& splats : tile_splats) {  // in tile order
        bytes += splats.capacity() * sizeof(Splat);
        for (const Splat& splat : splats) {
            if (splat.film >= films.size() || splat.pixel >= pass[0].size())
                throw std::logic_error("render: a splat outside the image or its layers");
            // A non-finite splat would spoil the whole sample of the pixel it lands on:
            // counted and left out on its own instead.
            if (is_finite(splat.value))
                pass[splat.film][splat.pixel] += splat.value;
            else
                films[splat.film].reject_sample(splat.pixel, splat.value);
        }
    }
    for (size_t pixel = 0; pixel < pass[0].size(); ++pixel) {
        films[0].add_sample(pixel, pass[0][pixel]);
        const float scale = films[0].clamp_scale(pass[0][pixel]);
        for (size_t f = 1; f < films.size(); ++f)
            films[f].add_sample(pixel, scale * pass[f][pixel]);
    }
    return bytes;
}

// Pass by pass: begin_pass(s), then sample s of every pixel, for s in [sample_begin, sample_end).
RenderStats render_passes(const Camera& camera, std::span<Film> films,
                          const RenderSettings& settings, const Model& model, int sample_begin,
                          int sample_end) {
    const auto start = std::chrono::steady_clock::now();
    const Tiles tiles(films[0].width(), films[0].height());
    const Window window(settings, films[0]);
    const size_t pixel_count = static_cast<size_t>(tiles.width) * tiles.height;
    const int samples = std::max(0, sample_end - sample_begin);
    Progress own_progress("render", pixel_count * samples,
                          settings.progress && !settings.shared_progress);
    Progress& progress = settings.shared_progress ? *settings.shared_progress : own_progress;

    std::vector<std::vector<Color>> pass(films.size(), std::vector<Color>(pixel_count));
    std::vector<std::vector<Splat>> tile_splats(tiles.count);
    const uint64_t pass_rays = model.pass_rays();
    RenderStats stats;
    for (int s = sample_begin; s < sample_end; ++s) {
        if (settings.stop && settings.stop->load()) {
            stats.stopped = true;
            break;
        }
        model.begin_pass(s, settings);
        const TileRun run =
            render_pass(camera, settings, model, tiles, window, s, pass, tile_splats, progress);
        stats.rays += run.rays;
        if (run.stopped) {  // a pass with tiles missing would be biased: drop it whole
            stats.stopped = true;
            break;
        }
        stats.splat_bytes = std::max(stats.splat_bytes, add_pass(films, pass, tile_splats));
        ++stats.complete_passes;
    }
    if (!settings.shared_progress) progress.finish();
    stats.rays += model.pass_rays() - pass_rays;  // what the passes' preparation traced
    stats.seconds = seconds_since(start);
    return stats;
}

}  // namespace

int resolve_thread_count(int requested) {
    if (requested > 0) return requested;
    return std::max(1u, std::thread::hardware_concurrency());
}

RenderStats render(const Camera& camera, std::span<Film> films, const RenderSettings& settings,
                   const Model& model, int sample_begin, int sample_end) {
    if (films.size() != 1 + model.layer_names.size())
        throw std::logic_error("render: one film for the image and one per layer of the model");
    if (model.splats && !model.passes)
        throw std::logic_error("render: a model that splats renders in passes");
    if (model.splats && settings.image_width > 0 &&
        (settings.image_width != films[0].width() || settings.image_height != films[0].height()))
        throw std::logic_error(
            "render: splats land anywhere, so a model that splats takes no crop");
    return model.passes ? render_passes(camera, films, settings, model, sample_begin, sample_end)
                        : render_pixels(camera, films, settings, model, sample_begin, sample_end);
}

}  // namespace lessons
