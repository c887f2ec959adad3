// What the handlers of `fixpoint serve` share: the options resolved at start, the rules every
// request passes (Host header, token, content type, size), the paths inside the root, and the
// config checks of `fixpoint render`.
#pragma once

#include "preview.hpp"

#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/registry.hpp>

#include <nlohmann/json.hpp>

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <mutex>
#include <string>

namespace httplib {
struct Request;
struct Response;
} // namespace httplib

namespace fp::host::serve_detail {

/// A request refused in itself: answered with `status` and {"error": message}.
struct HttpError {
    int status;
    std::string message;
};

/// A JSON value of a request or an answer (nlohmann/json, Debian's nlohmann-json3-dev): ordered,
/// so that answers keep their members in the order the handlers set them.
using Json = nlohmann::ordered_json;

constexpr std::size_t max_json_body = 4u << 20;
constexpr std::size_t max_image_body = 64u << 20;

enum class Body { None, Json, Bytes };

struct Context {
    const Registry* reg = nullptr;
    std::filesystem::path root; ///< canonical; the process works in it while serving
    std::string config;         ///< relative to root; may be empty
    std::string host;
    int port = 0;
    bool loopback = true;
    std::string token; ///< empty on loopback
    unsigned threads = 1;
    /// --threads as given (0: not given), for the render requests: the job picks the default
    /// (one thread for a pipeline whose batches run one at a time, else every core).
    unsigned threads_asked = 0;
    std::filesystem::path scratch; ///< a private temporary folder
    const std::atomic<bool>* stop = nullptr;
    Previewer* preview = nullptr;
    bool allow_python = false; ///< --allow-python: configs may hold python-scheme
    /// One /api/render at a time: each takes every render thread.
    mutable std::mutex render_lock;

    /// The rules every request passes before its body is read (httplib's pre-routing
    /// handler): the Host header, the token, the content type and the Content-Length.
    /// Throws HttpError (403, 415, 413).
    void admit_head(const httplib::Request& req, Body body) const;
    /// admit_head, and the size of the body read: throws HttpError (403, 415, 413).
    void admit(const httplib::Request& req, Body body) const;

    /// `rel` checked as a path inside the root (relative, no '..', no control character, not
    /// out through a symlink): returned as given, for the process works in the root. Throws HttpError 403;
    /// `mark`, when given, prefixes the message (a path from the config).
    std::string inside(const std::string& rel, const std::string& what, const std::string& mark = "") const;
};

/// The body as a JSON object, at most 64 containers deep (HttpError 400 otherwise).
Json parse_body(const httplib::Request& req);
/// A string member; a missing one is HttpError 400 when `required`, else "".
std::string field(const Json& body, const std::string& key, bool required);
/// A boolean member (false when absent).
bool flag(const Json& body, const std::string& key);

void send_json(httplib::Response& res, int status, const Json& v);
/// {"ok": false, "error": TEXT, "line": L, "column": C}: L and C from "file:L:C:" in TEXT.
Json refusal(const std::string& text);

/// What serve refuses in a config that `fixpoint render` would run: a python-scheme (it runs
/// Python code) unless --allow-python, and a file a plugin reads (superfractal's `picture`,
/// python-scheme's `file`) outside the root. Throws fp::InputError at the node's position.
void check_served_config(const Context& c, const CNode& root);
/// The config checked by check_served_config, then loaded and checked as `fixpoint render`
/// checks it before rendering (the memory check included). Throws fp::InputError.
Pipeline load_checked(const Context& c, const CNode& root);
/// The name of an unsaved text in messages.
std::string source_name(const std::string& path);

} // namespace fp::host::serve_detail
