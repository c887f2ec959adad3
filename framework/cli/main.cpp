// The `fixpoint` command line: the command table (cli.hpp says which family file holds what).
#include "cli.hpp"

#include <fixpoint/host/core/ranks.hpp>
#include <fixpoint/simd.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/version.hpp>

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <csignal>
#include <cstdio>
#include <new>

using namespace fp;
using namespace fp::cli;
using namespace fp::host;

namespace {

std::string simd_targets() {
    std::string l;
    for (const auto& t : simd::supported_targets()) l += (l.empty() ? "" : ", ") + t;
    return l;
}

// The command's exit code, every error one line (cli.hpp): bad input 2, internal failures 1,
// a Ctrl-C 130.
int run_reported(const Command& c) {
    try {
        return c.run();
    } catch (const ranks::Refused& f) {
        if (ranks::rank() == 0) std::fprintf(stderr, "%s\n", f.verdict.message.c_str());
        return f.verdict.code;
    } catch (const Cancelled&) {
        return report(130, "fixpoint: interrupted; no image written");
    } catch (const InputError& e) {
        return report(2, e.what());
    } catch (const InternalError& e) {
        return report(1, std::string("fixpoint: internal error: ") + e.what());
    } catch (const std::bad_alloc&) {
        return report(1, "fixpoint: out of memory");
    } catch (const std::exception& e) {
        return report(1, "fixpoint: internal error: " + excerpt(e.what(), 400));
    } catch (...) {
        // A plugin may throw anything; it must not abort the process without a word.
        return report(1, "fixpoint: internal error: an exception that is not a std::exception (thrown by "
                         "a plugin?)");
    }
}

} // namespace

int main(int argc, char** argv) {
    // A file-size limit (ulimit -f) must make a write fail with EFBIG, reported and cleaned up
    // like a full disk, not kill the process with its temporary file left behind.
    std::signal(SIGXFSZ, SIG_IGN);
    auto logger = spdlog::stderr_logger_st("fixpoint");
    logger->set_pattern("%v");
    spdlog::set_default_logger(logger);
    // Under mpirun: one process per rank (host/core/ranks.hpp); rank 0 speaks for the job.
    try {
        ranks::init(&argc, &argv);
    } catch (const InputError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    }
    struct Finalize {
        ~Finalize() { ranks::finalize(); }
    } finalize_at_exit;
    if (ranks::rank() != 0) spdlog::set_level(spdlog::level::off);

    CLI::App app{"fixpoint " FIXPOINT_VERSION
                 " - renders fractal and symmetric patterns from YAML pipelines"};
    app.set_version_flag("--version", FIXPOINT_VERSION);
    app.require_subcommand(1);
    Options o;
    app.add_option("--plugin-dir", o.plugin_dirs, "Also load plugins from this folder (repeatable)");
    std::string simd;
    app.add_option("--simd", simd,
                   "Instruction set of the vectorised kernels (default: the best this CPU has; the image "
                   "does not depend on it): one of " +
                       simd_targets())
        ->envname("FIXPOINT_SIMD");

    std::vector<Command> table;
    add_render_commands(app, o, table); // render, validate, animate, watch
    add_serve_commands(app, o, table);  // serve, explore
    add_tool_commands(app, o, table);   // eval, to-subdivision, recipe, addresses, symmetry
    add_plugin_commands(app, o, table); // plugins, describe, conformance

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "fixpoint: %s (see fixpoint --help)\n", e.what());
        return 2;
    }
    if (!simd.empty() && !simd::force_target(simd)) {
        std::fprintf(stderr, "fixpoint: --simd: %s is not an instruction set of this CPU (it has: %s)\n",
                     quote(simd).c_str(), simd_targets().c_str());
        return 2;
    }
    for (const Command& c : table) {
        if (!*c.app) continue;
        // Only `render` is split over ranks; any other command runs once, on rank 0.
        if (ranks::rank() != 0 && c.app->get_name() != "render") return 0;
        return run_reported(c);
    }
    return 1;
}
