// The parallel runtime: a RenderContext on a oneTBB arena of a fixed number of threads.
#pragma once

#include <fixpoint/host/core/checkpoint.hpp>
#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/render.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

namespace fp::host {

class Runtime : public RenderContext {
public:
    /// `cancel` (may be null) is polled by renderers; a signal handler sets it. `distributed`:
    /// the render is split over the MPI ranks (host/ranks.hpp), as `fixpoint render` under
    /// mpirun does; otherwise this process renders alone. `serial`: every task on the calling
    /// thread, no thread pool (and no change to oneTBB's global parallelism), for renders run
    /// side by side on threads of their own (explore's drafts).
    Runtime(unsigned threads, const std::atomic<bool>* cancel, bool distributed = false, bool serial = false);
    ~Runtime() override;

    unsigned workers() const override { return threads_; }
    void parallel_for(std::size_t n, const std::function<void(std::size_t, unsigned)>& task) override;
    void progress(std::uint64_t units) override { progress_->fetch_add(units, std::memory_order_relaxed); }
    bool cancelled() const override { return cancel_ && cancel_->load(std::memory_order_relaxed); }

    unsigned rank() const override;
    unsigned ranks() const override;
    void combine(void* data, std::size_t bytes, std::size_t record,
                 const std::function<void(const void*, void*, std::size_t)>& fold, bool everywhere) override;

    /// A shard (render --shard K/N): this process renders share `k` (from 0) of `n` alone, as
    /// MPI rank k of n would (rank() and ranks() say so), and combines nothing.
    void set_shard(unsigned k, unsigned n) {
        shard_ = true;
        shard_k_ = k, shard_n_ = n;
    }
    bool shard() const override { return shard_; }

    std::uint64_t memory_budget() const override { return budget_; }
    /// The budget renderers see (check_memory's answer); unset: no limit.
    void set_memory_budget(std::uint64_t bytes) { budget_ = bytes; }

    std::uint64_t done() const { return progress_->load(std::memory_order_relaxed); }
    /// Count the work done in `counter` (polled by the caller from another thread) from now on.
    void count_progress_in(std::atomic<std::uint64_t>* counter) { progress_ = counter ? counter : &done_; }

    // Checkpoints (host/checkpoint.hpp): written to `path` every `every_s` seconds and when the
    // render ends, with `header`; `resume`: the checkpoint the render continues from (null: from
    // the start).
    void set_checkpoints(std::string path, double every_s, CheckpointHeader header,
                         std::unique_ptr<CheckpointSource> resume);
    /// Checkpoints written into `memory` instead of a file (its last payload; `path` empty).
    void keep_checkpoints_in(std::shared_ptr<std::string> memory) { checkpoint_memory_ = std::move(memory); }
    bool checkpointing() const override { return !checkpoint_path_.empty() || checkpoint_memory_ != nullptr; }
    bool checkpoint_due() const override;
    void write_checkpoint(const std::function<void(CheckpointSink&)>& body) override;
    CheckpointSource* resume_from() override { return resume_.get(); }
    /// Checkpoints written so far.
    unsigned checkpoints_written() const { return written_; }

    // The kept histogram (`render --histogram`, host/core/histogram_file.hpp): the rows the
    // renderer hands over go to `writer` (rank 0's; null: none kept).
    void keep_histogram_in(HistogramWriter* writer) { histogram_ = writer; }
    /// ... and (too) into `h`, made of `shape` (the preview's kept histogram).
    void keep_histogram_in(Histogram* h, const HistogramShape& shape, bool order = false);
    /// ... and (too) to `rows` as they come (RenderHooks::histogram_rows).
    void keep_histogram_in(std::function<void(const Histogram&, int, int, int)> rows) {
        rows_ = std::move(rows);
    }
    bool keeps_histogram() const override { return histogram_ != nullptr || kept_ != nullptr || bool(rows_); }
    void keep_histogram(const Histogram& part, int part_row0, int row0, int rows) override;

private:
    struct Impl;
    unsigned threads_;
    const std::atomic<bool>* cancel_;
    bool distributed_;
    bool shard_ = false;
    unsigned shard_k_ = 0, shard_n_ = 1;
    std::atomic<std::uint64_t> done_{0};
    std::atomic<std::uint64_t>* progress_ = &done_;
    std::uint64_t budget_ = UINT64_MAX;
    std::string checkpoint_path_;
    double checkpoint_every_ = 0;
    CheckpointHeader checkpoint_header_;
    std::unique_ptr<CheckpointSource> resume_;
    std::shared_ptr<std::string> checkpoint_memory_;
    std::chrono::steady_clock::time_point checkpoint_due_;
    unsigned written_ = 0;
    HistogramWriter* histogram_ = nullptr;
    Histogram* kept_ = nullptr;
    HistogramShape kept_shape_;
    bool kept_order_ = false; ///< a shard's kept histogram: its last colours' order too
    std::function<void(const Histogram&, int, int, int)> rows_;
    std::unique_ptr<Impl> impl_;
};

/// Threads this machine offers.
unsigned hardware_threads();

/// Memory available for a render, in bytes: the least of the machine's (MemAvailable), the
/// cgroup's (its limit less its use) and the address space left under RLIMIT_AS, less an eighth
/// for headroom.
std::uint64_t available_memory();

/// "1.5 GiB"
std::string format_bytes(std::uint64_t b);

/// A size as `--memory` takes it: a number of bytes with an optional binary unit, K, M, G or T
/// (KiB, MiB, GiB, TiB; "B" and "iB" optional, any case): "8G", "512MiB", "1.5g", "1000000".
/// fp::InputError naming `option` otherwise, or for a size below 1 MiB.
std::uint64_t parse_size(const std::string& text, const std::string& option);

/// A number and the unit after it ("1.5GiB": 1.5 and "GiB"), as --memory and --checkpoint-every
/// read them; false when the text does not start with a number.
bool number_and_unit(const std::string& text, double& value, std::string& unit);

} // namespace fp::host
