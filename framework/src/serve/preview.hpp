// The preview of `fixpoint serve`: one worker thread renders the stages of one job at a time
// (drafts, then the full render) through the render job, which encodes each stage's PNG in
// memory for /api/frame. A new job cancels the running one through the render's cancel flag.
// The full render's histogram is kept, so that a change of tone, filter or density estimation
// is finished from it (fixpoint tone's way) in one stage, with no iterating.
#pragma once

#include <fixpoint/host/job/render_job.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace fp::host::serve_detail {

/// One finished stage: the PNG's bytes, as write_image would write them, and its caption.
struct Frame {
    std::string png;
    int width = 0, height = 0;
    double samples_per_pixel = 0, seconds = 0;
    bool retoned = false; ///< finished from the kept histogram, with no iterating
};

class Previewer {
public:
    Previewer();
    ~Previewer();
    Previewer(const Previewer&) = delete;
    Previewer& operator=(const Previewer&) = delete;

    /// Start a job rendering `stages` in order (the last one the full render), each planned to
    /// encode a PNG; the job running or waiting is cancelled. Returns the job's id (1, 2, ...).
    std::uint64_t start(std::vector<RenderPlan> stages);

    enum class Wait { Frame, Timeout, Cancelled, Failed, Unknown };
    struct Answer {
        Wait what = Wait::Timeout;
        int stage = 0, stages = 0;
        std::shared_ptr<const Frame> frame;
        std::string error; ///< Failed: the error's line
    };
    /// The first stage of job `id` after stage `after` (-1: the first stage), waiting up to
    /// `timeout` for it.
    Answer wait(std::uint64_t id, int after, std::chrono::milliseconds timeout);

    /// Cancel everything and wake every waiting request (the server is stopping).
    void shutdown();

    /// The histogram of the last full render that kept one (RenderRequest::keep_histogram), or
    /// null: a change of the text that touches only finishing parameters re-tones it.
    std::shared_ptr<const HistogramFile> kept() const;

private:
    struct Job {
        std::uint64_t id = 0;
        std::vector<RenderPlan> stages;
        std::vector<std::shared_ptr<const Frame>> frames;
        enum class State { Waiting, Running, Done, Failed, Cancelled } state = State::Waiting;
        std::string error;
        std::atomic<bool> cancel{false};
    };

    void run();
    void render(Job& job);

    mutable std::mutex mu_;
    std::shared_ptr<const HistogramFile> kept_;
    std::condition_variable work_cv_, frame_cv_;
    std::deque<std::shared_ptr<Job>> jobs_; ///< the newest last; only a few kept
    std::shared_ptr<Job> next_;             ///< the job the worker takes next
    std::uint64_t last_id_ = 0;
    bool stopping_ = false;
    std::thread worker_;
};

} // namespace fp::host::serve_detail
