// The parallel runtime: a RenderContext on a oneTBB arena of a fixed number of threads.
#pragma once

#include <fixpoint/render.hpp>

#include <atomic>
#include <cstdint>
#include <memory>

namespace fp::host {

class Runtime : public RenderContext {
public:
    /// `cancel` (may be null) is polled by renderers; a signal handler sets it. `distributed`:
    /// the render is split over the MPI ranks (host/ranks.hpp), as `fixpoint render` under
    /// mpirun does; otherwise this process renders alone.
    Runtime(unsigned threads, const std::atomic<bool>* cancel, bool distributed = false);
    ~Runtime() override;

    unsigned workers() const override { return threads_; }
    void parallel_for(std::size_t n, const std::function<void(std::size_t, unsigned)>& task) override;
    void progress(std::uint64_t units) override { done_.fetch_add(units, std::memory_order_relaxed); }
    bool cancelled() const override { return cancel_ && cancel_->load(std::memory_order_relaxed); }

    unsigned rank() const override;
    unsigned ranks() const override;
    void combine(void* data, std::size_t bytes, std::size_t record,
                 const std::function<void(const void*, void*, std::size_t)>& fold, bool everywhere) override;

    std::uint64_t done() const { return done_.load(std::memory_order_relaxed); }

private:
    struct Impl;
    unsigned threads_;
    const std::atomic<bool>* cancel_;
    bool distributed_;
    std::atomic<std::uint64_t> done_{0};
    std::unique_ptr<Impl> impl_;
};

/// Threads this machine offers.
unsigned hardware_threads();

/// Memory available for a render, in bytes (MemAvailable).
std::uint64_t available_memory();

/// "1.5 GiB"
std::string format_bytes(std::uint64_t b);

} // namespace fp::host
