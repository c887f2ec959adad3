#include <fixpoint/host/core/progress.hpp>

#include <cstdio>

namespace fp::host {

ProgressBar::ProgressBar(std::uint64_t total, std::function<std::uint64_t()> done, bool enabled,
                         std::string label)
    : total_(total ? total : 1), done_(std::move(done)), enabled_(enabled), label_(std::move(label)),
      start_(std::chrono::steady_clock::now()) {
    if (!enabled_) return;
    thread_ = std::thread([this] {
        while (!stop_.load()) {
            draw();
            for (int i = 0; i < 10 && !stop_.load(); ++i)
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    });
}

ProgressBar::~ProgressBar() {
    if (!enabled_) return;
    stop_ = true;
    thread_.join();
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
}

void ProgressBar::draw() {
    const double f = std::min(1.0, double(done_()) / double(total_));
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    constexpr int width = 30;
    char bar[width + 1];
    const int filled = int(f * width);
    for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
    bar[width] = 0;
    char eta[32] = "--";
    if (f > 0.001) {
        const double left = elapsed * (1 - f) / f;
        std::snprintf(eta, sizeof eta, "%d:%02d", int(left) / 60, int(left) % 60);
    }
    std::fprintf(stderr, "\r%s[%s] %5.1f%%  ETA %s", label_.c_str(), bar, 100 * f, eta);
    std::fflush(stderr);
}

} // namespace fp::host
