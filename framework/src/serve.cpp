// `fixpoint serve`: the HTTP server of the preview page (docs/serve-api.md). cpp-httplib runs
// each request's handler on a thread of its pool; the preview renders on one worker thread of
// its own (serve/preview.cpp), and the page long-polls its stages.
#include <fixpoint/host/serve.hpp>

#include "serve/context.hpp"
#include "serve/preview.hpp"
#include "serve/web_assets.hpp"

#include <fixpoint/host/draft.hpp>
#include <fixpoint/host/image_io.hpp>
#include <fixpoint/host/param_list.hpp>
#include <fixpoint/host/runtime.hpp>
#include <fixpoint/host/yaml_edit.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/version.hpp>

#include <httplib.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iterator>
#include <random>
#include <thread>

namespace fs = std::filesystem;

namespace fp::host {

using namespace serve_detail;

namespace {

// The config the page opens when serve was given none: configs/inversion/fig4a.yaml's circles,
// smaller and quicker.
const char* const starter_config =
    R"(# A config to start from (configs/ has many more): eight circles of inversion, as in
# configs/inversion/fig4a.yaml, at half its size. Save it under a name to keep it.
renderer:
  type: chaos-game
  width: 512
  height: 512
  points: 10000000
  view: [-1.75, 1.75, -1.75, 1.75]
  colourer: {type: flame, mode: set-colour}
  maps:
    - {type: inversion, shape: {type: circle, centre: [1, 1], radius: 1}, colour: "#ff6b6b"}
    - {type: inversion, shape: {type: circle, centre: [-1, 1], radius: 1}, colour: "#ffd93d"}
    - {type: inversion, shape: {type: circle, centre: [-1, -1], radius: 1}, colour: "#6bcb77"}
    - {type: inversion, shape: {type: circle, centre: [1, -1], radius: 1}, colour: "#4d96ff"}
    - {type: inversion, shape: {type: circle, centre: [0.30667, 0], radius: 0.21685}, colour: "#ff9f43"}
    - {type: inversion, shape: {type: circle, centre: [0, 0.30667], radius: 0.21685}, colour: "#c56cf0"}
    - {type: inversion, shape: {type: circle, centre: [-0.30667, 0], radius: 0.21685}, colour: "#48dbfb"}
    - {type: inversion, shape: {type: circle, centre: [0, -0.30667], radius: 0.21685}, colour: "#ff9ff3"}
)";

// How long /api/frame waits for a stage before answering 204.
constexpr auto frame_wait = std::chrono::seconds(10);

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

Json ok() {
    Json v = Json::object();
    v["ok"] = true;
    return v;
}

Json error_body(const std::string& message) {
    Json v = Json::object();
    v["error"] = message;
    return v;
}

/// A handler with the rules of every request around it: refused requests answer their
/// HttpError, a refused config its refusal (200), anything else 500.
template <class F>
httplib::Server::Handler guarded(const Context& c, Body body, F f) {
    return [&c, body, f](const httplib::Request& req, httplib::Response& res) {
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

/// The "path" of a request: "" (an unsaved text) or a path inside the root.
std::string request_path(const Context& c, const Json& body) {
    const std::string p = field(body, "path", false);
    return p.empty() ? p : c.inside(p, "path");
}

// ---------------------------------------------------------------- the page
void serve_asset(const Context& c, const WebAsset& a, httplib::Response& res) {
    std::string bytes(a.bytes);
    if (!c.token.empty() && a.path == "/index.html") {
        // The page's own files need the token too: the page links them with it.
        for (const std::string name : {"app.js", "style.css"})
            for (const std::string& form : {"\"" + name + "\"", "\"./" + name + "\"", "\"/" + name + "\""})
                for (std::size_t at = bytes.find(form); at != std::string::npos;
                     at = bytes.find(form, at + 1))
                    bytes.replace(at, form.size(),
                                  form.substr(0, form.size() - 1) + "?token=" + c.token + "\"");
    }
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_content(bytes, std::string(a.content_type));
}

// ---------------------------------------------------------------- the API
void api_state(const Context& c, const httplib::Request&, httplib::Response& res) {
    // Checked again at every read: CONFIG may have become a symlink out since the start.
    if (!c.config.empty()) c.inside(c.config, "CONFIG");
    Json v = Json::object();
    v["path"] = c.config;
    v["text"] = c.config.empty() ? std::string(starter_config) : read_yaml_text(c.config);
    v["version"] = FIXPOINT_VERSION;
    v["threads"] = c.threads;
    send_json(res, 200, v);
}

void api_plugins(const Context& c, const httplib::Request&, httplib::Response& res) {
    Json v = Json::object();
    for (const PluginEntry* e : c.reg->all()) {
        const std::string kind(kind_name(e->desc->kind));
        v[kind].push_back(e->desc->name); // a null member becomes a list
    }
    send_json(res, 200, v);
}

// The output as `fixpoint render` chooses it: `named`, else the config's output.path, else
// the config's name with .png (in the served folder, as the CLI writes in its own), checked
// as the CLI checks it. /api/check runs it too, so that the page marks a bad output.path at
// its line before anyone presses "render".
std::string render_output(const Context& c, const Pipeline& p, const std::string& path, std::string out,
                          bool force) {
    const Mark* mark = nullptr;
    if (out.empty() && !p.output_path.empty()) out = p.output_path, mark = &p.output_mark;
    if (out.empty() && !path.empty()) out = fs::path(path).stem().string() + ".png";
    if (out.empty())
        throw HttpError{400, "render: name the output (field 'output'): the text has no output.path"};
    c.inside(out, "output", mark ? mark->str() : "");
    try {
        std::error_code ec;
        if (!path.empty() && fs::equivalent(out, path, ec))
            throw InputError("cannot write " + quote(out, 200) + ": it is the config being rendered");
        check_output(out);
        if (!force && fs::exists(fs::symlink_status(out, ec)))
            throw InputError(quote(out, 200) + " exists: render with \"force\": true to replace it");
    } catch (const InputError& e) {
        if (mark) throw InputError(mark->str() + ": output.path: " + e.what());
        throw;
    }
    return out;
}

void api_check(const Context& c, const httplib::Request& req, httplib::Response& res) {
    const Json body = parse_body(req);
    const std::string text = field(body, "text", true), path = request_path(c, body);
    const Pipeline p = load_checked(c, parse_config(text, source_name(path)));
    // (A path the server refuses is shown like any refusal of the text: at its line.)
    if (!p.output_path.empty()) try {
            check_vector_output(p, render_output(c, p, path, "", true));
        } catch (const HttpError& e) {
            throw InputError(e.message);
        }
    Json v = ok();
    v["renderer"] = p.renderer_type;
    v["width"] = p.renderer->width();
    v["height"] = p.renderer->height();
    Json warnings = Json::array();
    for (const auto& w : p.warnings) warnings.push_back(w);
    v["warnings"] = warnings;
    send_json(res, 200, v);
}

Json number_or_null(const std::optional<double>& d) { return d ? Json(*d) : Json(); }

void api_params(const Context& c, const httplib::Request& req, httplib::Response& res) {
    const Json body = parse_body(req);
    const std::string text = field(body, "text", true), path = request_path(c, body);
    const std::vector<ParamEntry> entries = list_params(*c.reg, parse_config(text, source_name(path)));
    Json list = Json::array();
    for (const ParamEntry& e : entries) {
        Json o = Json::object();
        o["path"] = e.path;
        o["name"] = e.name;
        o["owner"] = e.owner;
        o["kind"] = e.kind;
        o["value"] = e.value;
        o["written"] = e.written;
        o["required"] = e.required;
        o["default_value"] = e.default_value;
        o["min"] = number_or_null(e.min);
        o["max"] = number_or_null(e.max);
        o["min_open"] = e.min_open;
        o["max_open"] = e.max_open;
        Json choices = Json::array();
        for (const auto& ch : e.choices) choices.push_back(ch);
        o["choices"] = choices;
        o["plugin_kind"] = e.plugin_kind;
        o["description"] = e.description;
        o["depth"] = e.depth;
        o["count"] = e.count;
        list.push_back(std::move(o));
    }
    Json v = ok();
    v["params"] = list;
    send_json(res, 200, v);
}

void api_edit(const Context& c, const httplib::Request& req, httplib::Response& res) {
    const Json body = parse_body(req);
    const std::string text = field(body, "text", true), path = request_path(c, body);
    const std::string op = field(body, "op", true), target = field(body, "target", true);
    const std::string source = source_name(path);
    std::string out;
    if (op == "set")
        out = edit_set(text, source, target, field(body, "value", true));
    else if (op == "append")
        out = edit_append(text, source, target, field(body, "value", true));
    else if (op == "remove")
        out = edit_remove(text, source, target);
    else
        throw HttpError{400, "field 'op': expected \"set\", \"remove\" or \"append\", not " + quote(op, 40)};
    Json v = ok();
    v["text"] = out;
    send_json(res, 200, v);
}

void api_preview(const Context& c, const httplib::Request& req, httplib::Response& res) {
    const Json body = parse_body(req);
    const std::string text = field(body, "text", true), path = request_path(c, body);
    const CNode root = parse_config(text, source_name(path));
    Pipeline full = load_checked(c, root);
    // Every stage is built (and so checked) before the job starts: a draft is the same
    // recipe with --set assignments, loaded as render --draft would load it.
    std::vector<Pipeline> stages;
    for (const int f : preview_factors(full.renderer->width(), full.renderer->height())) {
        if (f == 1) {
            stages.push_back(full);
            continue;
        }
        CNode draft = root;
        for (const auto& s : draft_overrides(full, f)) apply_override(draft, s);
        stages.push_back(load_pipeline(*c.reg, std::move(draft)));
    }
    const int n = int(stages.size());
    // The region the full picture shows (also where the text gives none: mfs fits the points'
    // box), from which the page pans and zooms; a draft shows the same region.
    Json region;
    if (const auto r = full.renderer->region()) region = Json::array({r->xmin, r->xmax, r->ymin, r->ymax});
    const std::uint64_t id = c.preview->start(std::move(stages));
    Json v = ok();
    v["job"] = static_cast<unsigned long long>(id);
    v["stages"] = n;
    v["region"] = region;
    send_json(res, 200, v);
}

long long query_int(const httplib::Request& req, const std::string& key) {
    if (!req.has_param(key)) throw HttpError{400, "missing query parameter '" + key + "'"};
    const std::string s = req.get_param_value(key);
    long long v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size())
        throw HttpError{400, "query parameter '" + key + "': expected a whole number, not " + quote(s, 40)};
    return v;
}

void api_frame(const Context& c, const httplib::Request& req, httplib::Response& res) {
    const long long job = query_int(req, "job"), after = query_int(req, "after");
    if (job < 1) throw HttpError{400, "query parameter 'job': expected a job's id (1, 2, ...)"};
    if (after < -1 || after > 1000) throw HttpError{400, "query parameter 'after': expected -1 or a stage"};
    const auto a = c.preview->wait(std::uint64_t(job), int(after), frame_wait);
    switch (a.what) {
    case Previewer::Wait::Frame: {
        res.status = 200;
        res.set_header("Cache-Control", "no-store");
        res.set_header("X-Stage", std::to_string(a.stage));
        res.set_header("X-Stages", std::to_string(a.stages));
        res.set_header("X-Done", a.stage + 1 == a.stages ? "1" : "0");
        res.set_header("X-Width", std::to_string(a.frame->width));
        res.set_header("X-Height", std::to_string(a.frame->height));
        res.set_header("X-Samples-Per-Pixel", Json(a.frame->samples_per_pixel).dump());
        res.set_header("X-Seconds", Json(a.frame->seconds).dump());
        res.set_content(a.frame->png, "image/png");
        return;
    }
    case Previewer::Wait::Timeout: res.status = 204; return;
    case Previewer::Wait::Cancelled: return send_json(res, 410, error_body("cancelled"));
    case Previewer::Wait::Unknown: throw HttpError{404, "no job " + std::to_string(job)};
    case Previewer::Wait::Failed: {
        Json e = refusal(a.error);
        e.erase("ok");
        return send_json(res, 422, e);
    }
    }
}

bool has_yaml_extension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (auto& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return ext == ".yaml" || ext == ".yml";
}

void api_save(const Context& c, const httplib::Request& req, httplib::Response& res) {
    const Json body = parse_body(req);
    const std::string text = field(body, "text", true), path = field(body, "path", true);
    if (!has_yaml_extension(path))
        throw HttpError{400, "save: " + quote(path, 200) + ": a config is saved as .yaml or .yml"};
    c.inside(path, "path");
    if (text.size() > max_yaml_bytes)
        throw InputError(path + ": more than " + std::to_string(max_yaml_bytes) +
                         " bytes: fixpoint would not read it");
    write_bytes(text, path);
    Json v = ok();
    v["path"] = path;
    send_json(res, 200, v);
}

void api_render(const Context& c, const httplib::Request& req, httplib::Response& res) {
    const Json body = parse_body(req);
    const std::string text = field(body, "text", true), path = request_path(c, body);
    std::string out = field(body, "output", false);
    const bool force = flag(body, "force");
    const Pipeline p = load_checked(c, parse_config(text, source_name(path)));
    out = render_output(c, p, path, out, force);
    const bool vector = check_vector_output(p, out);
    // A render takes every render thread (and the memory of a full image): two at once would
    // halve each, and a page could start any number. Taken once the text has passed its
    // checks, so that a refused request never turns away one that would render.
    const std::unique_lock<std::mutex> lock(c.render_lock, std::try_to_lock);
    if (!lock.owns_lock()) throw HttpError{409, "a render is running: wait for it to finish"};

    // Rendered on this request's thread, as `fixpoint render` would, stopped by the server's
    // stop flag (Ctrl-C) only: the preview goes on beside it.
    Runtime rt(c.threads, c.stop);
    RenderStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    Image img;
    std::string doc;
    try {
        if (vector)
            doc = p.renderer->render_vector(
                rt, stats, format_for(out) == Format::Svg ? VectorFormat::Svg : VectorFormat::Pdf, p.recipe);
        else
            img = p.renderer->render(rt, stats);
    } catch (const InputError& e) {
        throw InputError(p.renderer_mark.str() + ": renderer: " + e.what());
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (c.stop->load()) throw Cancelled();
    const std::string warning = check_drawn(p, stats);
    if (vector)
        write_bytes(doc, out);
    else
        write_image(img, out, p.bit_depth, p.recipe);
    char summary[512];
    std::snprintf(summary, sizeof summary, "%s: %llu %s in %.2f s, %llu restarted chain%s", out.c_str(),
                  static_cast<unsigned long long>(stats.samples), stats.unit.c_str(), secs,
                  static_cast<unsigned long long>(stats.restarts), stats.restarts == 1 ? "" : "s");
    Json v = ok();
    v["output"] = out;
    v["seconds"] = secs;
    v["summary"] = std::string(summary);
    Json warnings = Json::array();
    for (const auto& w : p.warnings) warnings.push_back(w);
    if (!warning.empty()) warnings.push_back(warning);
    v["warnings"] = warnings;
    send_json(res, 200, v);
}

// The file name an image's bytes are read from: read_recipe tells formats by name.
std::string image_extension(const std::string& b) {
    if (b.rfind("\x89PNG", 0) == 0) return ".png";
    if (b.rfind("\x76\x2f\x31\x01", 0) == 0) return ".exr";
    if (b.rfind("II*", 0) == 0 || b.rfind("MM\0*", 0) == 0) return ".tif";
    const auto first = b.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && b[first] == '<') return ".svg";
    return "";
}

void api_recipe(const Context& c, const httplib::Request& req, httplib::Response& res) {
    const std::string ext = image_extension(req.body);
    if (ext.empty())
        throw InputError("the dropped file is not an image fixpoint writes (PNG, EXR, TIFF, SVG)");
    // A name of its own per request: requests run side by side.
    static std::atomic<unsigned long long> serial{0};
    const fs::path file = c.scratch / ("recipe-" + std::to_string(++serial) + ext);
    write_bytes(req.body, file.string());
    std::string recipe;
    try {
        recipe = read_recipe(file.string());
    } catch (const InputError& e) {
        fs::remove(file);
        std::string m = e.what();
        for (std::size_t at = m.find(file.string()); at != std::string::npos; at = m.find(file.string()))
            m.replace(at, file.string().size(), "the image");
        throw InputError(m);
    }
    fs::remove(file);
    Json v = ok();
    v["text"] = recipe;
    send_json(res, 200, v);
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

int serve(const Registry& reg, const ServeOptions& o, const std::atomic<bool>& stop) {
    Context c;
    c.reg = &reg;
    std::error_code ec;
    c.root = fs::canonical(o.root, ec);
    if (ec || !fs::is_directory(c.root))
        throw InputError("--root: " + quote(o.root, 200) + " is not a folder");
    if (o.port < 0 || o.port > 65535)
        throw InputError("--port: " + std::to_string(o.port) + " is not a port (0 to 65535)");
    c.host = o.host;
    c.loopback = is_loopback(o.host);
    if (!c.loopback) c.token = make_token();
    c.threads = o.threads ? o.threads : hardware_threads();
    c.stop = &stop;
    c.allow_python = o.allow_python;
    // Every path of a request is relative to the root, as the CLI's are to its folder: the
    // server works in the root, so that a config (and what it names: a picture, a script)
    // reads as `fixpoint render` run there would read it, and messages name paths alike.
    WorkIn work_in(c.root);
    if (!o.config.empty()) {
        try {
            c.config = c.inside(o.config, "CONFIG");
        } catch (const HttpError& e) {
            throw InputError(e.message);
        }
        if (!fs::is_regular_file(c.config))
            throw InputError("CONFIG: " + quote(o.config, 200) + " is not a file in " +
                             quote(c.root.string(), 200));
    }
    Scratch scratch;
    c.scratch = scratch.path();
    Previewer preview(c.threads, c.scratch);
    c.preview = &preview;

    httplib::Server srv;
    // Long polls hold a thread each for up to 10 s: a pool larger than the default 8.
    srv.new_task_queue = [] { return new httplib::ThreadPool(32); };
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
    srv.set_pre_routing_handler([&c](const httplib::Request& req, httplib::Response& res) {
        const Body body = req.method != "POST"        ? Body::None
                          : req.path == "/api/recipe" ? Body::Bytes
                                                      : Body::Json;
        try {
            c.admit_head(req, body);
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
