// The `fixpoint` command line: the command table (cli.hpp says which family file holds what).
#include "cli.hpp"

#include <fixpoint/host/core/ranks.hpp>
#include <fixpoint/simd.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/version.hpp>

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
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

// The options a command knows (its own and the global ones), as typed: "--threads", "-o".
std::vector<std::string> option_names(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::App* a = &app; a; a = a->get_parent())
        for (const CLI::Option* opt : a->get_options()) {
            for (const auto& l : opt->get_lnames()) names.push_back("--" + l);
            for (const auto& s : opt->get_snames()) names.push_back("-" + s);
        }
    return names;
}

// A parse error in one line, with "did you mean" for what a typo is likeliest to be: the
// command's name, or an option's. Other errors keep CLI11's words.
std::string parse_error_line(const CLI::App& app, int argc, char** argv, const CLI::ParseError& e) {
    const CLI::App* command = nullptr;
    std::vector<std::string> commands;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        commands.push_back(sub->get_name());
    const auto global = option_names(app);
    for (int i = 1; i < argc && !command; ++i) {
        const std::string a = argv[i];
        if (a.rfind('-', 0) == 0) {
            // A global option's value is not the command (--plugin-dir DIR, --simd X).
            if (a.find('=') == std::string::npos &&
                std::find(global.begin(), global.end(), a) != global.end() && a != "--version" &&
                a != "--help" && a != "-h")
                ++i;
            continue;
        }
        if (std::find(commands.begin(), commands.end(), a) != commands.end()) {
            command = app.get_subcommand(a);
            break;
        }
        const auto near = suggest(a, commands);
        std::string all;
        for (const auto& c : commands) all += (all.empty() ? "" : ", ") + c;
        return "fixpoint: " + quote(a) + " is not a command" +
               (near.empty() ? "" : " (did you mean " + quote(near[0]) + "?)") + "; the commands are " + all;
    }
    if (command) {
        const auto known = option_names(*command);
        bool after = false;
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            after = after || a == command->get_name();
            if (!after || a == "-" || a.rfind('-', 0) != 0 || a == "--") continue;
            const std::string name = a.substr(0, a.find('='));
            // (A negative number is a value, not an option.)
            if (name.size() > 1 && (std::isdigit(static_cast<unsigned char>(name[1])) || name[1] == '.'))
                continue;
            if (std::find(known.begin(), known.end(), name) != known.end()) continue;
            const auto near = suggest(name, known);
            return "fixpoint " + command->get_name() + ": unknown option " + quote(name) +
                   (near.empty() ? "" : " (did you mean " + quote(near[0]) + "?)") + " (see fixpoint " +
                   command->get_name() + " --help)";
        }
    }
    return std::string("fixpoint: ") + e.what() + " (see fixpoint --help)";
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
    // The global options may follow the command too (`fixpoint render --plugin-dir D x.yaml`):
    // the commands, made below, inherit this.
    app.fallthrough();
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
        std::fprintf(stderr, "%s\n", parse_error_line(app, argc, argv, e).c_str());
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
