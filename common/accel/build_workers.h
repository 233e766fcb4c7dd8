// The BVH build's threads (private to common/accel/): parts of the build started on threads
// while some of the allowed ones are idle, and joined at the end (bvh_binary.cpp, bvh_sah.cpp).
#pragma once

#include <atomic>
#include <exception>
#include <list>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>

#include "accel/parallel.h"

namespace lessons::bvh_build {

// Starts threads for parts of the build while some of the allowed ones are idle, and joins them.
class Workers {
public:
    explicit Workers(int threads) : idle_(build_threads(threads) - 1) {}
    // Takes an idle thread, if there is one, for the caller to start with start().
    bool claim() {
        int n = idle_.load(std::memory_order_relaxed);
        while (n > 0)
            if (idle_.compare_exchange_weak(n, n - 1)) return true;
        return false;
    }
    void release() { idle_.fetch_add(1); }
    // Runs work() on a new thread (claimed before), which becomes idle again when it returns.
    // Returns false, with the claim released, if the system refuses a thread (or memory for
    // it): the caller then does the work itself. Threads that have finished are joined here, so
    // that their stacks go back as the build goes on. An exception thrown by work() (memory
    // running out) is kept, and join_all() throws it.
    template <class Work>
    bool start(Work work) {
        std::lock_guard<std::mutex> lock(mutex_);
        try {
            for (auto t = started_.begin(); t != started_.end();) {
                if (t->done->load()) {
                    t->thread.join();
                    t = started_.erase(t);
                } else {
                    ++t;
                }
            }
            started_.emplace_back();  // before the thread: a thread is never left unowned
            Started& entry = started_.back();
            entry.done = std::make_shared<std::atomic<bool>>(false);
            try {
                entry.thread = std::thread([this, work, done = entry.done] {
                    try {
                        work();
                    } catch (...) {
                        std::lock_guard<std::mutex> failed(mutex_);
                        if (!failure_) failure_ = std::current_exception();
                    }
                    release();
                    done->store(true);
                });
            } catch (...) {
                started_.pop_back();
                throw;
            }
            return true;
        } catch (const std::exception&) {  // std::system_error, std::bad_alloc
            release();
            return false;
        }
    }
    // Joins every thread started, including those started by threads started; then throws what
    // any of them threw.
    void join_all() {
        for (;;) {
            std::thread t;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                if (started_.empty()) break;
                t = std::move(started_.back().thread);
                started_.pop_back();
            }
            t.join();
        }
        if (failure_) std::rethrow_exception(failure_);
    }

private:
    struct Started {
        std::thread thread;
        std::shared_ptr<std::atomic<bool>> done;
    };
    std::atomic<int> idle_;
    std::mutex mutex_;
    std::list<Started> started_;
    std::exception_ptr failure_;  // the first exception a started thread threw
};

}  // namespace lessons::bvh_build
