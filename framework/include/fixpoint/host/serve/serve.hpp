// `fixpoint serve`: the live preview page, an HTTP server inside the CLI (cpp-httplib).
// The HTTP interface the page uses is docs/serve-api.md; the security rules are there too.
#pragma once

#include <fixpoint/host/core/registry.hpp>

#include <atomic>
#include <functional>
#include <string>
#include <vector>

namespace fp::host {

struct ServeOptions {
    /// The config the page opens; may be empty. Relative to `root` when one is given, else a
    /// path from the working folder (the root is then that folder, or the config's own when it
    /// lies outside: `info` says so).
    std::string config;
    std::string host = "127.0.0.1"; ///< --host; anything but loopback needs the token
    int port = 8420;                ///< --port; 0: any free port (printed)
    std::string root;               ///< --root: the only folder the page reads and writes ("": see config)
    unsigned threads = 0;           ///< render threads (0: all cores)
    /// --allow-python: configs may hold a python-scheme, whose Python runs when a config is
    /// checked; without it serve refuses them (a page could run any code otherwise).
    bool allow_python = false;
    std::vector<std::string> plugin_dirs;
    /// Called once the server listens, with the address to open (the token included when one
    /// is needed); the CLI prints it as "fixpoint serve: open URL".
    std::function<void(const std::string&)> on_listen;
    /// Called with a line for the user before listening (which folder is served, when it is
    /// not the working one by default); may be empty.
    std::function<void(const std::string&)> info;
};

/// Runs the server until `stop` becomes true (SIGINT). Returns the exit code; throws
/// fp::InputError for bad options (a config outside the root, a port in use, ...).
/// While it runs the process works in `root` (its current folder, restored after), so that a
/// config reads what it names (a picture, a script) as `fixpoint render` run there would.
int serve(const Registry& reg, const ServeOptions& o, const std::atomic<bool>& stop);

} // namespace fp::host
