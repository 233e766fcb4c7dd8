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

}  // namespace

int resolve_thread_count(int requested) {
    if (requested > 0) return requested;
    return std::max(1u, std::thread::hardware_concurrency());
}

RenderStats render(const Camera& camera, Film& film, const RenderSettings& settings,
                   const RadianceFn& radiance, int sample_begin, int sample_end) {
    return render_layers(
        camera, std::span<Film>(&film, 1), settings,
        [&](const Ray& ray, Rng& rng, std::span<Color>) { return radiance(ray, rng); },
        sample_begin, sample_end);
}

RenderStats render_layers(const Camera& camera, std::span<Film> films,
                          const RenderSettings& settings, const LayeredRadianceFn& radiance,
                          int sample_begin, int sample_end) {
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
        const uint64_t pixels = tiles.for_each_pixel(tile, [&](int x, int y, size_t pixel) {
            for (int s = sample_begin; s < sample_end; ++s) {
                Rng rng = sample_rng(settings, window.image_index(x, y), s);
                const Ray ray = camera_ray(camera, settings, window, x, y, rng);
                std::fill(layers.begin(), layers.end(), Color(0.0f));
                const Color value = radiance(ray, rng, layers);
                films[0].add_sample(pixel, value);
                const float scale = films[0].clamp_scale(value);
                for (size_t k = 0; k < layer_count; ++k)
                    films[1 + k].add_sample(pixel, scale * layers[k]);
            }
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

RenderStats render_splatting(const Camera& camera, std::span<Film> films,
                             const RenderSettings& settings, const SplattingRadianceFn& radiance,
                             int sample_begin, int sample_end,
                             const std::function<void(int)>& before_pass) {
    const auto start = std::chrono::steady_clock::now();
    const Tiles tiles(films[0].width(), films[0].height());
    if (settings.image_width > 0 &&
        (settings.image_width != tiles.width || settings.image_height != tiles.height))
        throw std::logic_error("render_splatting: splats land anywhere, so it takes no crop");
    const Window window(settings, films[0]);
    const size_t pixel_count = static_cast<size_t>(tiles.width) * tiles.height;
    const size_t layer_count = films.size() - 1;
    const int samples = std::max(0, sample_end - sample_begin);
    Progress own_progress("render", pixel_count * samples,
                          settings.progress && !settings.shared_progress);
    Progress& progress = settings.shared_progress ? *settings.shared_progress : own_progress;

    // One pass: each pixel's own sample per film, and each tile's splats.
    std::vector<std::vector<Color>> pass(films.size(), std::vector<Color>(pixel_count));
    std::vector<std::vector<Splat>> tile_splats(tiles.count);
    RenderStats stats;
    for (int s = sample_begin; s < sample_end; ++s) {
        if (settings.stop && settings.stop->load()) {
            stats.stopped = true;
            break;
        }
        if (before_pass) before_pass(s);
        const TileRun run = run_tiles(tiles.count, settings, [&](int tile) {
            std::vector<Color> layers(layer_count);
            std::vector<Splat>& splats = tile_splats[tile];
            splats.clear();
            const uint64_t pixels = tiles.for_each_pixel(tile, [&](int x, int y, size_t pixel) {
                Rng rng = sample_rng(settings, pixel, s);
                const Ray ray = camera_ray(camera, settings, window, x, y, rng);
                std::fill(layers.begin(), layers.end(), Color(0.0f));
                pass[0][pixel] = radiance(ray, rng, static_cast<uint32_t>(pixel), layers, splats);
                for (size_t k = 0; k < layer_count; ++k) pass[1 + k][pixel] = layers[k];
            });
            progress.advance(pixels);
        });
        stats.rays += run.rays;
        if (run.stopped) {  // a pass with tiles missing would be biased: drop it whole
            stats.stopped = true;
            break;
        }
        size_t bytes = 0;
        for (const std::vector<Splat>& splats : tile_splats) {  // in tile order
            bytes += splats.capacity() * sizeof(Splat);
            for (const Splat& splat : splats) {
                // A non-finite splat would spoil the whole sample of the pixel it lands on:
                // counted and left out on its own instead.
                if (is_finite(splat.value))
                    pass[splat.film][splat.pixel] += splat.value;
                else
                    films[splat.film].reject_sample(splat.pixel, splat.value);
            }
        }
        stats.splat_bytes = std::max(stats.splat_bytes, bytes);
        ++stats.complete_passes;
        for (size_t pixel = 0; pixel < pixel_count; ++pixel) {
            films[0].add_sample(pixel, pass[0][pixel]);
            const float scale = films[0].clamp_scale(pass[0][pixel]);
            for (size_t f = 1; f < films.size(); ++f)
                films[f].add_sample(pixel, scale * pass[f][pixel]);
        }
    }
    if (!settings.shared_progress) progress.finish();
    stats.seconds = seconds_since(start);
    return stats;
}

}  // namespace lessons
