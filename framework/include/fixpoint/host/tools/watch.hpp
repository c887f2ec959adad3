// `fixpoint watch CONFIG -o OUT`: render again each time the config is saved, a draft first
// (host/draft.hpp), then the full image, each written to OUT as `render` writes it.
#pragma once

#include <fixpoint/host/core/registry.hpp>

#include <atomic>
#include <functional>
#include <string>
#include <vector>

namespace fp::host {

struct WatchOptions {
    std::string config;            ///< the YAML file watched
    std::string out;               ///< -o: the image written (a draft, then the full render)
    std::vector<std::string> sets; ///< --set, applied to every version of the file
    unsigned threads = 0;          ///< 0: the render job's default
    bool no_draft = false;         ///< --no-draft: the full image only
    /// How often the file is read for a change, in milliseconds.
    int poll_ms = 100;
    /// Where the lines go: what was written (info), and a version of the file that fp refuses
    /// (error: the CLI's one line, "file:line:col: ..."); the last good image stays.
    std::function<void(const std::string&)> info, error;
};

/// Watches until `stop` becomes true (SIGINT): returns 0. Throws fp::InputError before
/// watching when OUT cannot be written or names the config.
int watch(const Registry& reg, const WatchOptions& o, const std::atomic<bool>& stop);

} // namespace fp::host
