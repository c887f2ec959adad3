// `fixpoint serve`: the HTTP server of the preview page (docs/serve-api.md). cpp-httplib runs
// each request's handler on a thread of its pool; the preview renders on one worker thread of
// its own (serve/preview.cpp), and the page long-polls its stages.
#include <fixpoint/host/serve/serve.hpp>

#include "api.hpp"
#include "context.hpp"
#include "gate.hpp"
#include "preview.hpp"
#include "web_assets.hpp"

#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/text.hpp>

#include <httplib.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iterator>
#include <random>
#include <thread>

namespace fs = std::filesystem;

namespace fp::host {

using namespace serve_detail;

namespace {

// An address of this machine only: 127.0.0.0/8, ::1 (or 127/8 mapped into IPv6), or the name
// localhost. Any other name may resolve anywhere ("127.example.com" too).
bool is_loopback(const std::string& host) {
    if (host == "localhost") return true;
    in_addr v4{};
    if (::inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
    in6_addr v6{};
    if (::inet_pton(AF_INET6, host.c_str(), &v6) != 1) return false;
    if (IN6_IS_ADDR_LOOPBACK(&v6)) return true;
    return IN6_IS_ADDR_V4MAPPED(&v6) && v6.s6_addr[12] == 127;
}

std::string make_token() {
    std::random_device rd;
    std::string t;
    static const char hex[] = "0123456789abcdef";
    for (int i = 0; i < 32; ++i) t += hex[rd() & 15];
    return t;
}

/// A handler with the rules of every request around it: refused requests answer their
/// HttpError, a refused config its refusal (200), anything else 500.
template <class F>
httplib::Server::Handler guarded(const Context& c, Body body, F f) {
    return [&c, body, f](const httplib::Request& req, httplib::Response& res) {
        // The request is read: the handler has no deadline, its response one (gate.hpp).
        struct Phase {
            Phase() { GatedServer::handler_starts(); }
            ~Phase() { GatedServer::handler_ends(); }
            Phase(const Phase&) = delete;
            Phase& operator=(const Phase&) = delete;
        } phase;
        try {
            c.admit(req, body);
            f(req, res);
        } catch (const HttpError& e) {
            send_json(res, e.status, error_body(e.message));
        } catch (const InputError& e) {
            send_json(res, 200, refusal(e.what()));
        } catch (const Cancelled&) {
            send_json(res, 503, error_body("the server is stopping"));
        } catch (const std::bad_alloc&) {
            send_json(res, 500, error_body("fixpoint: out of memory"));
        } catch (const std::exception& e) {
            send_json(res, 500, error_body(std::string("fixpoint: internal error: ") + e.what()));
        } catch (...) {
            send_json(res, 500,
                      error_body("fixpoint: internal error: an exception that is not a "
                                 "std::exception (thrown by a plugin?)"));
        }
    };
}

// ---------------------------------------------------------------- the page
void serve_asset(const Context& c, const WebAsset& a, httplib::Response& res) {
    std::string bytes(a.bytes);
    if (!c.token.empty() && a.path == "/index.html") {
        // The page's own files need the token too: the page links them with it (every file of
        // web/ that is built in, by its name).
        for (const WebAsset& linked : web_assets()) {
            if (linked.path == "/index.html") continue;
            const std::string name(linked.path.substr(1));
            for (const std::string& form : {"\"" + name + "\"", "\"./" + name + "\"", "\"/" + name + "\""})
                for (std::size_t at = bytes.find(form); at != std::string::npos;
                     at = bytes.find(form, at + 1))
                    bytes.replace(at, form.size(),
                                  form.substr(0, form.size() - 1) + "?token=" + c.token + "\"");
        }
    }
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_content(bytes, std::string(a.content_type));
}

// Works in `dir` while alive; back where it was after.
class WorkIn {
public:
    explicit WorkIn(const fs::path& dir) : old_(fs::current_path()) { fs::current_path(dir); }
    ~WorkIn() {
        std::error_code ec;
        fs::current_path(old_, ec);
    }
    WorkIn(const WorkIn&) = delete;
    WorkIn& operator=(const WorkIn&) = delete;

private:
    fs::path old_;
};

// A private temporary folder, removed with what it holds.
class Scratch {
public:
    Scratch() {
        std::string t = (fs::temp_directory_path() / "fixpoint-serve-XXXXXX").string();
        if (!::mkdtemp(t.data()))
            throw InputError("cannot make a temporary folder in " + fs::temp_directory_path().string());
        path_ = t;
    }
    ~Scratch() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

} // namespace

// The served folder and CONFIG's path in it (docs/serve-api.md). With --root, a relative
// CONFIG is relative to the root, as every path of a request is, and an absolute one must lie
// inside it. Without --root, CONFIG is a path from the working folder, like any path on the
// command line: the root is the working folder when CONFIG lies inside it, else CONFIG's own
// folder (a config elsewhere is served with its pictures and scripts beside it).
struct Served {
    std::string root, config;
    bool config_folder = false; ///< the root defaulted to CONFIG's folder (said at start)
};
Served served(const ServeOptions& o) {
    Served s{o.root.empty() ? "." : o.root, o.config};
    const fs::path given(o.config);
    if (o.config.empty() || (!o.root.empty() && given.is_relative())) return s;
    std::error_code ec;
    const fs::path root = fs::canonical(s.root, ec);
    if (ec) return s; // (refused below, naming the folder)
    // A plain relative path (no ..) is kept as given when it stays inside: messages name it so.
    const bool plain = given.is_relative() && std::none_of(given.begin(), given.end(),
                                                           [](const fs::path& part) { return part == ".."; });
    const fs::path abs = fs::weakly_canonical(fs::absolute(given, ec), ec);
    if (ec || !fs::is_regular_file(abs)) {
        if (plain) return s; // (refused below, as not a file in the root)
        throw InputError("CONFIG: " + quote(o.config, 200) + " is not a file");
    }
    const fs::path rel = abs.lexically_relative(root);
    if (!rel.empty() && *rel.begin() != "..") {
        if (!plain) s.config = rel.string();
        return s;
    }
    if (!o.root.empty())
        throw InputError("CONFIG " + quote(o.config, 200) + ": outside the served folder " +
                         quote(root.string(), 200) +
                         " (--root): serve a folder that holds it, or leave "
                         "--root out to serve the config's own folder");
    s.root = abs.parent_path().string();
    s.config = abs.filename().string();
    s.config_folder = true;
    return s;
}

int serve(const Registry& reg, const ServeOptions& o, const std::atomic<bool>& stop) {
    Context c;
    c.reg = &reg;
    const Served where = served(o);
    std::error_code ec;
    c.root = fs::canonical(where.root, ec);
    if (ec || !fs::is_directory(c.root))
        throw InputError("--root: " + quote(where.root, 200) + " is not a folder");
    if (where.config_folder && o.info)
        o.info("fixpoint serve: serving the config's folder " + quote(c.root.string(), 200) +
               " (--root serves another)");
    if (o.port < 0 || o.port > 65535)
        throw InputError("--port: " + std::to_string(o.port) + " is not a port (0 to 65535)");
    c.host = o.host;
    c.loopback = is_loopback(o.host);
    if (!c.loopback) c.token = make_token();
    c.threads = o.threads ? o.threads : hardware_threads();
    c.threads_asked = o.threads;
    c.stop = &stop;
    c.allow_python = o.allow_python;
    // Every path of a request is relative to the root, as the CLI's are to its folder: the
    // server works in the root, so that a config (and what it names: a picture, a script)
    // reads as `fixpoint render` run there would read it, and messages name paths alike.
    WorkIn work_in(c.root);
    if (!where.config.empty()) {
        try {
            c.config = c.inside(where.config, "CONFIG");
        } catch (const HttpError& e) {
            throw InputError(e.message);
        }
        if (!fs::is_regular_file(c.config))
            throw InputError("CONFIG: " + quote(where.config, 200) + " is not a file in " +
                             quote(c.root.string(), 200));
    }
    Scratch scratch;
    c.scratch = scratch.path();
    Previewer preview;
    c.preview = &preview;

    // Connections wait for their heads without a thread, within a deadline, and are capped
    // (gate.hpp); 32 request threads, for long polls hold one each for up to 10 s.
    GatedServer srv(GateLimits::from_environment());
    srv.set_payload_max_length(max_image_body);
    // httplib's default is SO_REUSEPORT, which lets a second server (of the same user) bind
    // the same port and share its requests: SO_REUSEADDR only, so that a port in use is refused
    // and a restart still binds while old connections wait in TIME_WAIT.
    srv.set_socket_options([](socket_t sock) {
        int yes = 1;
        ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    srv.set_keep_alive_timeout(2); // so that a stop does not wait long for idle connections
    srv.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return;
        const std::string m = res.status == 413
                                  ? "the body is larger than " + std::to_string(max_image_body) + " bytes"
                              : res.status == 404 ? "no such page: " + quote(req.path, 200)
                                                  : "HTTP " + std::to_string(res.status);
        send_json(res, res.status, error_body(m));
    });

    // The Host, token, content type and size are checked before httplib reads a body (its
    // pre-routing handler runs first), so that a client without them cannot make the server
    // read one; the handlers check them again (guarded), with the size of what was read.
    // This is as early as the token can be checked: it may come in a header
    // (X-Fixpoint-Token) as well as in the request line, so the whole head is needed; until
    // it is in, the connection waits in the gate's waiting room, holding no request thread,
    // for at most the deadline (gate.hpp).
    srv.set_pre_routing_handler([&c](const httplib::Request& req, httplib::Response& res) {
        const Body body = req.method != "POST"        ? Body::None
                          : req.path == "/api/recipe" ? Body::Bytes
                                                      : Body::Json;
        try {
            c.admit_head(req, body);
            // httplib reads a body for these methods before finding no route for them.
            if (req.method == "PUT" || req.method == "PATCH" || req.method == "DELETE" || req.method == "PRI")
                throw HttpError{405, req.method + " is not a method of this server (GET and POST are)"};
            if (body != Body::None && !GatedServer::may_read_body(req))
                throw HttpError{503, "the server is busy reading other requests' bodies: try again"};
        } catch (const HttpError& e) {
            send_json(res, e.status, error_body(e.message));
            return httplib::Server::HandlerResponse::Handled;
        }
        return httplib::Server::HandlerResponse::Unhandled;
    });

    for (const WebAsset& a : web_assets()) {
        const auto handler =
            guarded(c, Body::None,
                    [&c, &a](const httplib::Request&, httplib::Response& res) { serve_asset(c, a, res); });
        srv.Get(std::string(a.path), handler);
        if (a.path == "/index.html") srv.Get("/", handler);
    }
    const auto bind = [&c](void (*f)(const Context&, const httplib::Request&, httplib::Response&)) {
        return [&c, f](const httplib::Request& req, httplib::Response& res) { f(c, req, res); };
    };
    srv.Get("/api/state", guarded(c, Body::None, bind(api_state)));
    srv.Get("/api/plugins", guarded(c, Body::None, bind(api_plugins)));
    srv.Get("/api/frame", guarded(c, Body::None, bind(api_frame)));
    srv.Post("/api/check", guarded(c, Body::Json, bind(api_check)));
    srv.Post("/api/params", guarded(c, Body::Json, bind(api_params)));
    srv.Post("/api/edit", guarded(c, Body::Json, bind(api_edit)));
    srv.Post("/api/preview", guarded(c, Body::Json, bind(api_preview)));
    srv.Post("/api/save", guarded(c, Body::Json, bind(api_save)));
    srv.Post("/api/render", guarded(c, Body::Json, bind(api_render)));
    srv.Post("/api/recipe", guarded(c, Body::Bytes, bind(api_recipe)));

    if (o.port == 0) {
        c.port = srv.bind_to_any_port(o.host);
        if (c.port < 0) throw InputError("--host " + quote(o.host, 80) + ": cannot listen there");
    } else {
        c.port = o.port;
        if (!srv.bind_to_port(o.host, o.port))
            throw InputError("--host " + quote(o.host, 80) + " --port " + std::to_string(o.port) +
                             ": cannot listen there (is the port in use?)");
    }
    const std::string shown = o.host.find(':') != std::string::npos ? "[" + o.host + "]" : o.host;
    const std::string url =
        "http://" + shown + ":" + std::to_string(c.port) + "/" + (c.token.empty() ? "" : "?token=" + c.token);
    std::atomic<bool> listened{false};
    std::thread listener([&srv, &listened] {
        srv.listen_after_bind();
        listened.store(true);
    });
    const auto finish = [&] {
        preview.shutdown(); // wakes the long polls, so that the pool's threads end
        // httplib's stop() does nothing before the listener runs: wait for it to start (or fail).
        while (!srv.is_running() && !listened.load())
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        srv.stop();
        listener.join();
        srv.close_gate(); // the connections still open, and the request threads
    };
    try {
        if (o.on_listen) o.on_listen(url);
    } catch (...) {
        finish();
        throw;
    }
    while (!stop.load()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    finish();
    return 0;
}

} // namespace fp::host
