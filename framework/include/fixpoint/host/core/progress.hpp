// A progress bar with ETA on stderr (no Debian package offers one for C++).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

namespace fp::host {

class ProgressBar {
public:
    /// Polls `done()` every 100 ms from its own thread and redraws; draws nothing unless
    /// `enabled` (stderr is a terminal and --quiet was not given).
    /// `label` is drawn before the bar ("quality 5.2 of 7, "; empty: none).
    ProgressBar(std::uint64_t total, std::function<std::uint64_t()> done, bool enabled,
                std::string label = {});
    ~ProgressBar(); ///< stops and clears the line

private:
    void draw();
    std::uint64_t total_;
    std::function<std::uint64_t()> done_;
    bool enabled_;
    std::string label_;
    std::atomic<bool> stop_{false};
    std::chrono::steady_clock::time_point start_;
    std::thread thread_;
};

} // namespace fp::host
