// Progress on stderr: a bar with elapsed time and ETA on a terminal, a plain line every 10%
// otherwise (logs and CI). Safe to update from several threads.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace lessons {

class Progress {
public:
    Progress(std::string label, uint64_t total_work, bool enabled);
    void advance(uint64_t work);  // thread-safe
    void finish();

private:
    void print(uint64_t done, bool final_line);

    std::string label_;
    uint64_t total_;
    bool enabled_, terminal_;
    std::atomic<uint64_t> done_{0};
    std::mutex print_mutex_;
    int last_decile_ = -1;
    std::chrono::steady_clock::time_point start_, last_print_;
};

}  // namespace lessons
