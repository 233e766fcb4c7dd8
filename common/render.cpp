// The tiled, multi-threaded render loop (see render.h).
#include "render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "progress.h"
#include "scene.h"

namespace lessons {

namespace {
constexpr int kTileSize = 16;
}

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
    const int width = films[0].width(), height = films[0].height();
    const size_t layer_count = films.size() - 1;
    const int tiles_x = (width + kTileSize - 1) / kTileSize;
    const int tiles_y = (height + kTileSize - 1) / kTileSize;
    const int tile_count = tiles_x * tiles_y;
    const int samples = std::max(0, sample_end - sample_begin);

    Progress own_progress("render", static_cast<uint64_t>(width) * height * samples,
                          settings.progress && !settings.shared_progress);
    Progress& progress = settings.shared_progress ? *settings.shared_progress : own_progress;
    std::atomic<int> next_tile{0};
    std::atomic<uint64_t> rays{0};

    std::atomic<bool> stopped{false};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto worker = [&]() {
        const uint64_t rays_before = rays_traced_by_this_thread();
        std::vector<Color> layers(layer_count);
        try {
            for (int tile = next_tile++; tile < tile_count; tile = next_tile++) {
                if (settings.stop && settings.stop->load(std::memory_order_relaxed)) {
                    stopped = true;
                    break;
                }
                const int x0 = (tile % tiles_x) * kTileSize, y0 = (tile / tiles_x) * kTileSize;
                const int x1 = std::min(x0 + kTileSize, width),
                          y1 = std::min(y0 + kTileSize, height);
                for (int y = y0; y < y1; ++y) {
                    for (int x = x0; x < x1; ++x) {
                        const size_t pixel = static_cast<size_t>(y) * width + x;
                        for (int s = sample_begin; s < sample_end; ++s) {
                            Rng rng = settings.kronecker
                                          ? Rng::kronecker(settings.seed, pixel, s)
                                          : Rng(settings.seed, pixel, static_cast<uint64_t>(s));
                            const float jx = settings.jitter ? rng.uniform() : 0.5f;
                            const float jy = settings.jitter ? rng.uniform() : 0.5f;
                            const Ray ray = camera.generate_ray(x + jx, y + jy, width, height);
                            std::fill(layers.begin(), layers.end(), Color(0.0f));
                            films[0].add_sample(pixel, radiance(ray, rng, layers));
                            for (size_t k = 0; k < layer_count; ++k)
                                films[1 + k].add_sample(pixel, layers[k]);
                        }
                    }
                }
                progress.advance(static_cast<uint64_t>(x1 - x0) * (y1 - y0) * samples);
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
    if (!settings.shared_progress) progress.finish();

    RenderStats stats;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.rays = rays.load();
    stats.stopped = stopped.load();
    return stats;
}

}  // namespace lessons
