// The scene's build steps on several threads: an index range cut into one contiguous part per
// thread. Each part is given to fn(begin, end, part) on a thread of its own (part 0 on the
// caller's), so a step whose parts write disjoint places, or whose per-part results are merged in
// part order, gives the same result on any number of threads.
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace lessons {

// The number of threads a build step uses: `requested`, or every hardware thread for 0.
inline int build_threads(int requested) {
    if (requested > 0) return requested;
    return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// How many parts parallel_parts cuts n items into: one per thread, but none smaller than
// min_part (below, starting a thread costs more than the part).
inline int part_count(size_t n, int threads, size_t min_part) {
    const size_t by_size = std::max<size_t>(1, n / std::max<size_t>(1, min_part));
    return static_cast<int>(std::min<size_t>(static_cast<size_t>(build_threads(threads)), by_size));
}

// Runs fn(begin, end, part) for the part_count(n, threads, min_part) parts of [0, n), the parts
// in order of their ranges, and returns when all are done. If the system refuses a thread, that
// part runs on the caller's thread. An exception from fn, on any thread, is thrown here once every
// part has finished (the first one thrown, if several).
template <class Fn>
void parallel_parts(size_t n, int threads, size_t min_part, Fn&& fn) {
    const int parts = part_count(n, threads, min_part);
    auto range = [&](int i) { return n * static_cast<size_t>(i) / static_cast<size_t>(parts); };
    std::mutex mutex;
    std::exception_ptr failure;
    auto run = [&](int i) {
        try {
            fn(range(i), range(i + 1), i);
        } catch (...) {
            std::lock_guard<std::mutex> lock(mutex);
            if (!failure) failure = std::current_exception();
        }
    };
    std::vector<std::thread> started;
    try {
        started.reserve(static_cast<size_t>(parts - 1));
    } catch (const std::exception&) {  // then every part on this thread
    }
    for (int i = 1; i < parts; ++i) {
        bool on_its_own = false;
        if (started.size() < started.capacity()) {  // room reserved: no allocation below
            try {
                started.emplace_back(run, i);
                on_its_own = true;
            } catch (const std::exception&) {  // std::system_error, std::bad_alloc
            }
        }
        if (!on_its_own) run(i);
    }
    run(0);
    for (std::thread& t : started) t.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace lessons
