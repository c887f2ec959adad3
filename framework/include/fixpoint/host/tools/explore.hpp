// `fixpoint explore`: a seeded search over parameters of a config, scored by measures of quick
// drafts (measures.hpp), keeping the best K. See explore.cpp for the design.
#pragma once

#include <fixpoint/host/core/registry.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace fp::host {

struct ExploreOptions {
    std::string config;              ///< the config explored (YAML)
    std::string out_dir;             ///< -o: the folder of best-k.yaml, best-k.png, sheet.png
    std::vector<std::string> sets;   ///< --set: fixed overrides applied first
    std::vector<std::string> params; ///< --param PATH=RANGE
    std::vector<std::string> random; ///< --random PLUGIN-PATH: every ranged parameter of it
    std::string weights;             ///< --weights name=w,...
    std::uint64_t seed = 1;
    int candidates = 24, keep = 6, generations = 0, columns = 0;
    int draft_size = 160;
    long long draft_points = 100000;
    unsigned threads = 0; ///< 0: all cores
    bool force = false;
    bool allow_python = false; ///< --allow-python: a config from an image may run code
    const std::atomic<bool>* cancel = nullptr;
    std::function<void(const std::string&)> info; ///< progress lines (may be empty: silent)
};

/// The search, the renders of the best and every file written. Throws fp::InputError for bad
/// input (one line, "--param ...: ..."), fp::Cancelled when cancelled. Returns 0.
int run_explore(const Registry& reg, const ExploreOptions& o);

/// The text of `fixpoint explore --help` after the options: ranges, measures, scores.
extern const char* const explore_help;

} // namespace fp::host
