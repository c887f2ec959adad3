#include "preview.hpp"

#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/host/job/draft.hpp>

#include <fstream>
#include <iterator>
#include <new>
#include <sstream>

namespace fs = std::filesystem;

namespace fp::host::serve_detail {

namespace {
// Jobs whose frames are kept: the running one and the one it replaced (whose frames a page
// may still be fetching); an older id answers "cancelled".
constexpr std::size_t kept_jobs = 2;

} // namespace

Previewer::Previewer() : worker_([this] { run(); }) {}

Previewer::~Previewer() {
    shutdown();
    worker_.join();
}

void Previewer::shutdown() {
    std::lock_guard<std::mutex> lock(mu_);
    stopping_ = true;
    for (auto& j : jobs_) j->cancel.store(true);
    work_cv_.notify_all();
    frame_cv_.notify_all();
}

std::uint64_t Previewer::start(std::vector<RenderPlan> stages) {
    auto job = std::make_shared<Job>();
    job->stages = std::move(stages);
    std::lock_guard<std::mutex> lock(mu_);
    job->id = ++last_id_;
    for (auto& j : jobs_) {
        j->cancel.store(true);
        // A job the worker has not taken yet is cancelled now; a running one when its render
        // has stopped (the worker marks it).
        if (j->state == Job::State::Waiting) j->state = Job::State::Cancelled;
    }
    jobs_.push_back(job);
    while (jobs_.size() > kept_jobs) jobs_.pop_front();
    next_ = job;
    work_cv_.notify_all();
    frame_cv_.notify_all();
    return job->id;
}

std::shared_ptr<const HistogramFile> Previewer::kept() const {
    std::lock_guard<std::mutex> lock(mu_);
    return kept_;
}

Previewer::Answer Previewer::wait(std::uint64_t id, int after, std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    std::unique_lock<std::mutex> lock(mu_);
    while (true) {
        std::shared_ptr<Job> job;
        for (auto& j : jobs_)
            if (j->id == id) job = j;
        Answer a;
        if (!job) {
            // An id given out earlier whose job is no longer kept was replaced.
            a.what = id >= 1 && id <= last_id_ ? Wait::Cancelled : Wait::Unknown;
            return a;
        }
        a.stages = int(job->stages.size());
        const int want = after + 1;
        if (want >= 0 && want < int(job->frames.size())) {
            a.what = Wait::Frame;
            a.stage = want;
            a.frame = job->frames[std::size_t(want)];
            return a;
        }
        if (job->state == Job::State::Cancelled || (stopping_ && job->state != Job::State::Failed)) {
            a.what = Wait::Cancelled;
            return a;
        }
        if (job->state == Job::State::Failed) {
            a.what = Wait::Failed;
            a.error = job->error;
            return a;
        }
        if (job->state == Job::State::Done || want >= a.stages) {
            // Nothing comes after the last stage.
            a.what = Wait::Timeout;
            return a;
        }
        if (frame_cv_.wait_until(lock, until) == std::cv_status::timeout) {
            a.what = Wait::Timeout;
            return a;
        }
    }
}

void Previewer::run() {
    while (true) {
        std::shared_ptr<Job> job;
        {
            std::unique_lock<std::mutex> lock(mu_);
            work_cv_.wait(lock, [&] { return stopping_ || next_; });
            if (stopping_) return;
            job = std::move(next_);
            next_.reset();
            if (job->state != Job::State::Waiting) continue;
            job->state = Job::State::Running;
        }
        render(*job);
    }
}

void Previewer::render(Job& job) {
    auto finish = [&](Job::State s, std::string error = {}) {
        std::lock_guard<std::mutex> lock(mu_);
        job.state = s;
        job.error = std::move(error);
        frame_cv_.notify_all();
    };
    try {
        RenderHooks hooks;
        hooks.cancel = &job.cancel;
        for (RenderPlan& plan : job.stages) {
            if (job.cancel.load()) return finish(Job::State::Cancelled);
            RenderResult r = run_render(plan, hooks);
            auto frame = std::make_shared<Frame>();
            frame->png = std::move(r.bytes);
            frame->width = r.width, frame->height = r.height;
            frame->samples_per_pixel = samples_per_pixel(r.stats, frame->width, frame->height);
            frame->seconds = r.seconds;
            frame->retoned = bool(plan.request.tone);
            std::lock_guard<std::mutex> lock(mu_);
            if (r.kept) kept_ = std::move(r.kept);
            job.frames.push_back(std::move(frame));
            frame_cv_.notify_all();
        }
        finish(Job::State::Done);
    } catch (const InputError& e) {
        finish(Job::State::Failed, e.what());
    } catch (const Cancelled&) {
        finish(Job::State::Cancelled);
    } catch (const std::bad_alloc&) {
        finish(Job::State::Failed, "fixpoint: out of memory");
    } catch (const std::exception& e) {
        finish(Job::State::Failed, std::string("fixpoint: internal error: ") + e.what());
    } catch (...) {
        finish(Job::State::Failed, "fixpoint: internal error: an exception that is not a std::exception "
                                   "(thrown by a plugin?)");
    }
}

} // namespace fp::host::serve_detail
