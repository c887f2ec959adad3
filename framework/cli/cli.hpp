// The `fixpoint` command line, in files by command family: main.cpp holds the command table;
// each family (render.cpp: render, validate, animate, watch; plugins.cpp: plugins, describe,
// conformance; tools.cpp: eval, to-subdivision, recipe, addresses, symmetry; serve.cpp: serve,
// explore) declares its subcommands and runs them; common.cpp holds what they share.
//
// Exit codes: 0 success, 2 bad input (config, parameters, command line), 1 internal failure or a
// check's "no" (`symmetry --group G`: G is not kept), 130 interrupted. Every error is one line on
// stderr.
#pragma once

#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/registry.hpp>
#include <fixpoint/host/job/print.hpp>
#include <fixpoint/host/job/render_job.hpp>
#include <fixpoint/host/serve/serve.hpp>
#include <fixpoint/host/tools/animate.hpp>
#include <fixpoint/host/tools/explore.hpp>
#include <fixpoint/host/tools/symmetry.hpp>

#include <CLI/CLI.hpp>

#include <atomic>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace fp::cli {

/// The options of every command, as CLI11 fills them.
struct Options {
    std::vector<std::string> plugin_dirs;
    std::string config, out, image, name, transform, scheme = "{type: picard}", kind;
    std::vector<std::string> sets, files, where, maps;
    std::string vary, example, points;
    std::string memory; ///< --memory SIZE ("": what the machine has available)
    /// --checkpoint FILE, --checkpoint-every TIME ("": 5m), --resume FILE
    std::string checkpoint, checkpoint_every, resume;
    std::string histogram;                                     ///< render --histogram FILE.fph
    std::string shard;                                         ///< render --shard K/N
    double quality = std::numeric_limits<double>::quiet_NaN(); ///< render --quality Q (NaN: none)
    int columns = 0;
    unsigned threads = 0;
    bool quiet = false, force = false, check = false, verbose = false, draft = false, no_draft = false;
    bool markdown = false;     ///< describe --markdown
    bool allow_python = false; ///< --allow-python: a recipe read from an image may run its Python
    bool strict = false;       ///< --strict: refuse a recipe whose image may differ from its own
    std::string steps = "1";
    long long level = -1;
    host::PrintRequest print; ///< --tile, --repeat, --dpi, --print-size
    // symmetry
    std::string group, area, against;
    std::vector<std::string> images;
    std::vector<std::string> ops;
    double tolerance = host::SymmetryOptions{}.tolerance, threshold = host::SymmetryOptions{}.threshold;
    int smooth = host::SymmetryOptions{}.smooth;
    bool json = false;
    // the commands with options of their own
    host::AnimateOptions animate;
    host::ExploreOptions explore;
    host::ServeOptions serve;
};

/// The options several commands share, in one wording each: --threads (1 to 4096; `what` says
/// what they do) and --set.
CLI::Option* add_threads(CLI::App* cmd, unsigned& threads,
                         const std::string& what = "Worker threads (default: all cores)");
CLI::Option* add_sets(CLI::App* cmd, std::vector<std::string>& sets,
                      const std::string& what = "Override a value: path.to.param=value (repeatable)");

/// One subcommand: its CLI11 parser and what runs it (the exit code).
struct Command {
    CLI::App* app;
    std::function<int()> run;
};

// The command families: each adds its subcommands to `app` and their runners to `table`.
void add_render_commands(CLI::App& app, Options& o, std::vector<Command>& table);
void add_plugin_commands(CLI::App& app, Options& o, std::vector<Command>& table);
void add_tool_commands(CLI::App& app, Options& o, std::vector<Command>& table);
void add_serve_commands(CLI::App& app, Options& o, std::vector<Command>& table);

// ---------------------------------------------------------------- shared (common.cpp)

/// Set by Ctrl-C and SIGTERM once install_sigint has run; polled by renders.
std::atomic<bool>& interrupted();
/// Catch Ctrl-C and SIGTERM from now on (a background job of a script starts with SIGINT
/// ignored, and the handler replaces that); the flag is polled by the work.
void install_sigint();

/// The plugins of the default folders and of --plugin-dir (a file that did not load: one
/// warning line each, unless `plugins --check` lists them).
host::Registry make_registry(const Options& o);
/// A pipeline's warnings (a plugin other than the recipe's), one line each; returns it.
const host::Pipeline& told(const host::Pipeline& p);
/// Warnings after a render, one line each.
void tell(const std::vector<std::string>& warnings);
/// The render job's hooks for the command line: Ctrl-C, the progress bar (a terminal, not
/// --quiet), and the streamed file the signal handler removes.
host::RenderHooks render_hooks(bool quiet);
/// The threads asked for, else every core.
unsigned threads_of(const Options& o);

/// An error line and the exit code: as is on one process; under mpirun, as the rank's phase
/// requires (host/core/ranks.hpp).
int report(int code, const std::string& raw);

} // namespace fp::cli
