// Progress output on stderr (see progress.h).
#include "render/progress.h"

#include <unistd.h>

#include <cstdio>

namespace lessons {

Progress::Progress(std::string label, uint64_t total_work, bool enabled)
    : label_(std::move(label)),
      total_(total_work > 0 ? total_work : 1),
      enabled_(enabled),
      terminal_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

void Progress::advance(uint64_t work) {
    const uint64_t done = done_.fetch_add(work) + work;
    if (!enabled_) return;
    std::unique_lock lock(print_mutex_, std::try_to_lock);
    if (lock.owns_lock()) print(done, false);
}

void Progress::finish() {
    if (!enabled_) return;
    std::lock_guard lock(print_mutex_);
    print(done_.load(), true);
}

void Progress::print(uint64_t done, bool final_line) {
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double fraction = static_cast<double>(done) / static_cast<double>(total_);
    const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    if (terminal_) {
        if (!final_line && now - last_print_ < std::chrono::milliseconds(100)) return;
        last_print_ = now;
        constexpr int kWidth = 30;
        const int filled = static_cast<int>(fraction * kWidth);
        std::string bar(filled, '#');
        bar.resize(kWidth, '.');
        std::fprintf(stderr, "\r%s [%s] %3d%%  %.1fs elapsed, ETA %.1fs ", label_.c_str(),
                     bar.c_str(), static_cast<int>(100.0 * fraction), elapsed, eta);
        if (final_line) std::fprintf(stderr, "\n");
    } else {
        const int decile = static_cast<int>(10.0 * fraction);
        if (decile == last_decile_ || (final_line && decile < 10 && last_decile_ == decile)) return;
        last_decile_ = decile;
        std::fprintf(stderr, "%s: %d%%, %.1fs elapsed, ETA %.1fs\n", label_.c_str(), 10 * decile,
                     elapsed, eta);
    }
    std::fflush(stderr);
}

}  // namespace lessons
