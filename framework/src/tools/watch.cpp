// `fixpoint watch` (see fixpoint/host/tools/watch.hpp).
//
// The file is read every poll_ms and compared by its contents (an editor's save may keep the
// size and, within the file system's resolution, the time). A render runs on this thread; a
// second thread reads the file meanwhile and cancels the render when the contents change or
// the user stops, so that a save during a long full render starts the new draft at once.
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/job/draft.hpp>
#include <fixpoint/host/job/render_job.hpp>
#include <fixpoint/host/tools/watch.hpp>
#include <fixpoint/text.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

namespace fs = std::filesystem;

namespace fp::host {

namespace {

// The file's contents (read as render reads a config: refused above max_yaml_bytes); nullopt
// while it cannot be read (an editor between deleting and writing it anew), which is not a
// change. `error`, when given, gets why a file that exists cannot be taken.
std::optional<std::string> contents(const std::string& path, std::string* error = nullptr) {
    try {
        return read_yaml_text(path);
    } catch (const InputError& e) {
        std::error_code ec;
        if (error && fs::exists(path, ec)) *error = e.what();
        return std::nullopt;
    }
}

std::string format_seconds(double s) {
    char b[32];
    std::snprintf(b, sizeof b, "%.2f", s);
    return b;
}

} // namespace

int watch(const Registry& reg, const WatchOptions& o, const std::atomic<bool>& stop) {
    std::error_code ec;
    if (fs::equivalent(o.out, o.config, ec))
        throw InputError("cannot write " + quote(o.out, 200) + ": it is the config being watched");
    // Each pass is a render of the job's to OUT, replaced at each save.
    RenderRequest request;
    request.output = o.out;
    request.source = o.config;
    request.raster_only = "cannot write {}: watch writes images (.png, .exr, .tif), not SVG or PDF";
    request.threads = o.threads;
    request.may_stream = false; // (a version too large to hold is refused; the last good image stays)
    // Checked now, before the config is first read (it may not load yet).
    check_output_request(request, o.out);
    if (std::string why; !contents(o.config, &why))
        throw InputError(why.empty() ? quote(o.config, 200) + ": cannot read it" : why);

    // `rendering`: the contents being rendered, read by the watcher thread to tell a change.
    std::mutex m;
    std::string rendering;
    std::atomic<bool> cancel{false}, done{false};
    std::thread watcher([&] {
        while (!done.load()) {
            if (stop.load()) cancel.store(true);
            if (const auto now = contents(o.config)) {
                std::lock_guard<std::mutex> lock(m);
                if (*now != rendering) cancel.store(true);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(o.poll_ms));
        }
    });
    struct Join {
        std::atomic<bool>& done;
        std::thread& t;
        ~Join() {
            done.store(true);
            t.join();
        }
    } join{done, watcher};

    // One version of the file: its draft, then its full image; false when a change or the
    // user cancelled it (the loop reads the file again).
    const auto render_version = [&](const CNode& root) {
        const Pipeline full = load_pipeline(reg, root);
        std::vector<std::pair<Pipeline, const char*>> passes;
        if (!o.no_draft) {
            CNode small = root;
            for (const auto& s : draft_overrides(full, draft_factor)) apply_override(small, s);
            passes.emplace_back(load_pipeline(reg, std::move(small)), "draft");
        }
        passes.emplace_back(full, "full");
        // Every pass planned (and so checked) before the first writes: a version refused for its
        // full image leaves the last good image, not its draft.
        std::vector<std::pair<RenderPlan, const char*>> plans;
        for (const auto& [p, what] : passes) plans.emplace_back(plan_render(p, request), what);
        RenderHooks hooks;
        hooks.cancel = &cancel;
        for (auto& [plan, what] : plans) {
            const RenderResult r = run_render(plan, hooks);
            o.info(o.out + ": " + what + " " + std::to_string(r.width) + "x" + std::to_string(r.height) +
                   ", " + std::to_string(r.stats.samples) + " " + r.stats.unit + " in " +
                   format_seconds(r.seconds) + " s");
        }
        return true;
    };

    std::optional<std::string> seen; // the contents last dealt with (rendered, or refused)
    o.info("watching " + o.config + " (Ctrl-C to stop)");
    std::string unreadable; // why the file cannot be taken, said once
    while (!stop.load()) {
        std::string why;
        const auto now = contents(o.config, &why);
        if (!why.empty() && why != unreadable) o.error(why);
        unreadable = why;
        if (!now || now == seen) {
            std::this_thread::sleep_for(std::chrono::milliseconds(o.poll_ms));
            continue;
        }
        {
            std::lock_guard<std::mutex> lock(m);
            rendering = *now;
            cancel.store(false);
        }
        seen = now;
        try {
            // Loaded from the text just read (not the file again, which may already be
            // another version), under the file's name for the messages.
            CNode root = parse_config(*now, o.config);
            for (const auto& s : o.sets) apply_override(root, s);
            if (!render_version(root)) seen.reset(); // changed meanwhile: read again
        } catch (const InputError& e) {
            o.error(e.what()); // the last good image stays
        } catch (const Cancelled&) {
            // Some renderers (the tone mapping, superfractal, mfs) end a cancelled render by
            // throwing: a change or Ctrl-C, as when render_version returns false.
            seen.reset();
        }
    }
    return 0;
}

} // namespace fp::host
