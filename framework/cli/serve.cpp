// The page and the search: serve (the live preview page, host/serve/serve.hpp) and explore
// (a seeded search for good parameters, host/tools/explore.hpp).
#include "cli.hpp"

#include <spdlog/spdlog.h>

#include <cstdio>

using namespace fp::host;

namespace fp::cli {

namespace {

int cmd_serve(const Options& o) {
    install_sigint(); // Ctrl-C stops the server: serve() polls the flag
    ServeOptions so = o.serve;
    so.plugin_dirs = o.plugin_dirs;
    so.on_listen = [](const std::string& url) {
        std::printf("fixpoint serve: open %s\n", url.c_str());
        std::fflush(stdout);
    };
    if (!o.quiet) so.info = [](const std::string& l) { spdlog::info("{}", l); };
    return serve(make_registry(o), so, interrupted());
}

int cmd_explore(const Options& o) {
    install_sigint();
    ExploreOptions ex = o.explore;
    ex.cancel = &interrupted();
    if (!o.quiet) ex.info = [](const std::string& l) { spdlog::info("{}", l); };
    return run_explore(make_registry(o), ex);
}

} // namespace

void add_serve_commands(CLI::App& app, Options& o, std::vector<Command>& table) {
    ServeOptions& so = o.serve;
    auto* serve_cmd = app.add_subcommand("serve", "Serve the live preview page: edit a config, see it render "
                                                  "(docs/serve-api.md)");
    serve_cmd->add_option("config", so.config,
                          "Pipeline file (YAML) the page opens: a path from here, or from --root when "
                          "one is given");
    serve_cmd->add_option("--port", so.port, "Port (default 8420; 0: any free port)")
        ->check(CLI::Range(0, 65535));
    serve_cmd->add_option("--host", so.host,
                          "Address to listen on (default 127.0.0.1); any other needs the token printed in "
                          "the address");
    serve_cmd->add_option("--root", so.root,
                          "The only folder the page reads and writes (default: the current one, or the "
                          "config's own when it lies outside)");
    add_threads(serve_cmd, so.threads, "Render threads (default: all cores)");
    serve_cmd->add_flag("--allow-python", so.allow_python,
                        "Accept configs with a python-scheme (its Python code runs when the page checks "
                        "the config)");

    table.push_back({serve_cmd, [&o] { return cmd_serve(o); }});

    ExploreOptions& ex = o.explore;
    auto* explore = app.add_subcommand(
        "explore", "Search parameters of a config for good patterns: score quick drafts, keep the best");
    explore->add_option("config", ex.config, "Pipeline file (YAML)")->required();
    explore
        ->add_option("-o,--output", ex.out_dir,
                     "Folder of best-k.yaml, best-k.png, sheet.png, candidates.tsv")
        ->required();
    explore->add_option("--param", ex.params,
                        "A parameter and its range: PATH=A..B, PATH=a+bq..c+dq, 'PATH=a|b|c'");
    explore->add_option("--random", ex.random,
                        "Every ranged parameter of the plugin at this path (repeatable)");
    add_sets(explore, ex.sets, "Override a value first: path.to.param=value (repeatable)");
    explore->add_option(
        "--weights", ex.weights,
        "Weights of the measures (default coverage=1,entropy=1,dimension=2,lyapunov=1,symmetry=0)");
    explore->add_option("--seed", ex.seed, "Seed of the search (default 1)");
    explore
        ->add_option("--candidates", ex.candidates,
                     "Candidates of the random phase and of each generation (default 24)")
        ->check(CLI::Range(1, 100000));
    explore->add_option("--keep", ex.keep, "Best candidates kept, rendered and written (default 6)")
        ->check(CLI::Range(1, 1000));
    explore
        ->add_option("--generations", ex.generations,
                     "Evolutionary generations after the random phase (default 0)")
        ->check(CLI::Range(0, 10000));
    explore->add_option("--draft-size", ex.draft_size, "Larger side of a draft in pixels (default 160)")
        ->check(CLI::Range(8, 4096));
    explore->add_option("--draft-points", ex.draft_points, "Most points of a draft (default 100000)")
        ->check(CLI::Range(1LL, 1000000000LL));
    explore->add_option("--columns", ex.columns, "Columns of the contact sheet (default: about square)")
        ->check(CLI::Range(1, 1000));
    add_threads(explore, ex.threads, "Worker threads (default: all cores); the result does not depend on it");
    explore->add_flag("-q,--quiet", o.quiet, "No summary lines");
    explore->add_flag("--force", ex.force, "Replace existing files in the folder");
    explore->add_flag("--allow-python", ex.allow_python,
                      "Run the Python of a python-scheme in a recipe read from an image (refused by default: "
                      "an image may come from anywhere)");
    explore->footer(explore_help);

    table.push_back({explore, [&o] { return cmd_explore(o); }});
}

} // namespace fp::cli
