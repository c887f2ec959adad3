// What the command families share (cli.hpp): signals, the registry, warnings, error lines.
#include "cli.hpp"

#include <fixpoint/host/core/ranks.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/text.hpp>

#include <spdlog/spdlog.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>

#include <chrono>
#include <thread>

namespace fs = std::filesystem;
using namespace fp::host;

namespace fp::cli {

namespace {

std::atomic<bool> g_interrupted{false};

// The temporary file a streamed render is writing (StreamedImage), removed by the signal
// handler too: a rank that fails mid-render ends the job with MPI_Abort, and mpirun then
// terminates rank 0 inside a collective, where no destructor runs. (unlink is safe in a
// handler; the path is written before the handler can see it, and cleared after.)
char g_partial_output[4096];
std::atomic<bool> g_has_partial_output{false};

extern "C" void on_sigint(int) {
    g_interrupted.store(true);
    if (g_has_partial_output.load()) ::unlink(g_partial_output);
}

// An error line as the terminal shows it: one line whatever the input it echoes held
// (newlines, terminal escapes, bytes that are not UTF-8 become escapes), and of a readable
// length: a line longer than about 1000 characters keeps its start and its end (where the
// reason is) and says how much was cut (a 4 kB file name quoted twice).
std::string error_line(const std::string& raw) {
    std::string line = excerpt(raw, std::string::npos);
    constexpr std::size_t keep = 480;
    if (line.size() <= 2 * keep + 64) return line;
    // Cut at UTF-8 character boundaries.
    std::size_t head = keep, tail = line.size() - keep;
    while (head > 0 && (static_cast<unsigned char>(line[head]) & 0xc0) == 0x80) --head;
    while (tail < line.size() && (static_cast<unsigned char>(line[tail]) & 0xc0) == 0x80) ++tail;
    return line.substr(0, head) + " [... " + std::to_string(tail - head) + " bytes cut ...] " +
           line.substr(tail);
}

} // namespace

std::atomic<bool>& interrupted() { return g_interrupted; }

void install_sigint() {
    struct sigaction sa {};
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

Registry make_registry(const Options& o) {
    Registry reg;
    for (const auto& d : Registry::default_dirs()) reg.load_dir(d);
    for (const auto& d : o.plugin_dirs) {
        std::error_code ec;
        if (!fs::is_directory(d, ec)) throw InputError("--plugin-dir: '" + d + "' is not a folder");
        reg.load_dir(d);
    }
    // A plugin file that did not load is skipped with one line each (`plugins --check` lists
    // them instead); a config that asks for a plugin it would have provided fails naming it.
    if (!o.check)
        for (const auto& r : reg.refused()) spdlog::warn("warning: plugin file skipped: {}", r.reason);
    return reg;
}

const Pipeline& told(const Pipeline& p) {
    tell(p.warnings);
    return p;
}

void tell(const std::vector<std::string>& warnings) {
    for (const auto& w : warnings) spdlog::warn("warning: {}", w);
}

RenderHooks render_hooks(bool quiet) {
    RenderHooks h;
    h.cancel = &g_interrupted;
    h.progress_bar = !quiet && ::isatty(2);
    h.partial = [](const std::string& tmp) {
        if (tmp.empty()) {
            g_has_partial_output.store(false);
        } else if (tmp.size() < sizeof g_partial_output) {
            std::memcpy(g_partial_output, tmp.c_str(), tmp.size() + 1);
            g_has_partial_output.store(true);
        }
    };
    return h;
}

unsigned threads_of(const Options& o) { return o.threads ? o.threads : hardware_threads(); }

int report(int code, const std::string& raw) {
    const std::string line = error_line(raw);
    if (ranks::size() <= 1) {
        std::fprintf(stderr, "%s\n", line.c_str());
        return code;
    }
    switch (ranks::phase()) {
    case ranks::Phase::checking: {
        // Agreed with the others during the checks: rank 0 prints the first failing rank's line.
        ranks::set_phase(ranks::Phase::free);
        const ranks::Verdict v = ranks::agree(code, line);
        if (ranks::rank() == 0) std::fprintf(stderr, "%s\n", v.message.c_str());
        return v.code;
    }
    case ranks::Phase::rendering:
        if (code == 130) {
            // Stopped by mpirun, which sends every rank SIGTERM on a Ctrl-C and when a rank
            // aborts the job: one line for the job, rank 0's, unless a rank told it that it
            // failed (its line is the job's). The job is ending: no MPI_Abort and its banner.
            if (ranks::rank() == 0 && !ranks::failure_told(300)) std::fprintf(stderr, "%s\n", line.c_str());
            // The others wait a little: mpirun kills the ranks still running as soon as one
            // has ended, which would cut rank 0 before its line.
            if (ranks::rank() != 0) std::this_thread::sleep_for(std::chrono::seconds(2));
            std::fflush(stderr);
            ranks::quit(code);
        }
        // During the render the other ranks may be waiting for this one: the job ends.
        ranks::tell_failure();
        std::fprintf(stderr, "fixpoint: rank %u of %u: %s\n", ranks::rank(), ranks::size(), line.c_str());
        std::fflush(stderr);
        ranks::abort(code);
    case ranks::Phase::free: break;
    }
    if (ranks::rank() == 0) std::fprintf(stderr, "%s\n", line.c_str());
    return code;
}

CLI::Option* add_threads(CLI::App* cmd, unsigned& threads, const std::string& what) {
    return cmd->add_option("--threads", threads, what)->check(CLI::Range(1u, 4096u));
}

CLI::Option* add_sets(CLI::App* cmd, std::vector<std::string>& sets, const std::string& what) {
    return cmd->add_option("--set", sets, what);
}

} // namespace fp::cli
