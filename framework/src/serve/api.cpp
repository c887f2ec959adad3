// The endpoints of `fixpoint serve`'s API (docs/serve-api.md), one function each: they read
// the request, do the work through the host (the CLI's checks, the preview worker, the
// renderer) and write the answer. serve.cpp routes requests to them inside guarded().
#include "api.hpp"

#include "context.hpp"
#include "preview.hpp"

#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/param_list.hpp>
#include <fixpoint/host/core/render_version.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/host/core/yaml_edit.hpp>
#include <fixpoint/host/job/draft.hpp>
#include <fixpoint/host/job/render_job.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/version.hpp>

#include <httplib.h>

#include <charconv>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace fp::host::serve_detail {

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

static Json ok() {
    Json v = Json::object();
    v["ok"] = true;
    return v;
}

Json error_body(const std::string& message) {
    Json v = Json::object();
    v["error"] = message;
    return v;
}

/// The "path" of a request: "" (an unsaved text) or a path inside the root.
static std::string request_path(const Context& c, const Json& body) {
    const std::string p = field(body, "path", false);
    return p.empty() ? p : c.inside(p, "path");
}

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

void api_plugins(const Context& c, const httplib::Request& req, httplib::Response& res) {
    // With ?params=1 each plugin's parameter names too (what a switch of plugin can carry over).
    const bool params = req.get_param_value("params") == "1";
    Json v = Json::object();
    for (const PluginEntry* e : c.reg->all()) {
        const std::string kind(kind_name(e->desc->kind));
        if (!params) {
            v[kind].push_back(e->desc->name); // a null member becomes a list
            continue;
        }
        Json names = Json::array();
        for (std::uint32_t i = 0; i < e->desc->n_params; ++i) names.push_back(e->desc->params[i].name);
        v[kind][e->desc->name] = std::move(names);
    }
    send_json(res, 200, v);
}

// The request of a render to a file, as `fixpoint render` makes one: the output named, else the
// config's output.path, else the config's name with .png (in the served folder, as the CLI
// writes in its own), inside the root, replacing a file only with "force". (check_output_path
// plans it for /api/check and /api/preview too.)
static RenderRequest render_request(const Context& c, const Pipeline& p, const std::string& path,
                                    const std::string& out, bool force) {
    if (out.empty() && p.output_path.empty() && path.empty())
        throw HttpError{400, "render: name the output (field 'output'): the text has no output.path"};
    RenderRequest r;
    r.output = out;
    r.default_file = true;
    r.named_replaces = false;
    r.force = force;
    r.replace_hint = "render with \"force\": true to replace it";
    r.source = path;
    r.threads = c.threads_asked;
    r.check_path = [&c](const std::string& file, const Mark* mark) {
        c.inside(file, "output", mark ? mark->str() : "");
    };
    return r;
}

// The config's output.path checked as "render" will check it (its existence aside), so that
// the page shows a bad one at its line while the text is edited. A path the server refuses
// is reported like any refusal of the text.
static void check_output_path(const Context& c, const Pipeline& p, const std::string& path) {
    if (p.output_path.empty()) return;
    try {
        (void)plan_render(p, render_request(c, p, path, "", true));
    } catch (const HttpError& e) {
        throw InputError(e.message);
    }
}

void api_check(const Context& c, const httplib::Request& req, httplib::Response& res) {
    const Json body = parse_body(req);
    const std::string text = field(body, "text", true), path = request_path(c, body);
    const Pipeline p = load_checked(c, parse_config(text, source_name(path)));
    check_output_path(c, p, path);
    Json v = ok();
    v["renderer"] = p.renderer_type;
    v["width"] = p.renderer->width();
    v["height"] = p.renderer->height();
    Json warnings = Json::array();
    for (const auto& w : p.warnings) warnings.push_back(w);
    v["warnings"] = warnings;
    send_json(res, 200, v);
}

static Json number_or_null(const std::optional<double>& d) { return d ? Json(*d) : Json(); }

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

/// The largest histogram the preview keeps for re-toning (a 1024^2 flame at supersample 2 is
/// 128 MiB); a larger one renders every change stage by stage, as before.
constexpr std::uint64_t kept_histogram_bytes = std::uint64_t(256) << 20;

void api_preview(const Context& c, const httplib::Request& req, httplib::Response& res) {
    const Json body = parse_body(req);
    const std::string text = field(body, "text", true), path = request_path(c, body);
    const CNode root = parse_config(text, source_name(path));
    Pipeline full = load_checked(c, root);
    check_output_path(c, full, path);
    // Every stage is built and planned (and so checked) before the job starts: a draft is the
    // same recipe with --set assignments, loaded as render --draft would load it; each stage's
    // PNG is encoded in memory.
    RenderRequest request;
    request.encode = Format::Png;
    request.threads = c.threads_asked;
    std::vector<RenderPlan> stages;
    // A text whose histogram is the kept one (only finishing parameters changed: tone, filter,
    // density estimation, background) is finished from it in one stage, with no iterating.
    const std::shared_ptr<const HistogramFile> kept = c.preview->kept();
    // (The same recipe again renders again, stage by stage, as it always has.)
    const bool retone =
        kept && kept->header.recipe != full.recipe && kept->header.identity == full.histogram_identity &&
        kept->header.renderer == full.renderer_type && kept->header.version == render_version_tag();
    if (retone) {
        RenderRequest toned = request;
        toned.tone = kept;
        stages.push_back(plan_render(full, toned));
    }
    for (const int f : preview_factors(full.renderer->width(), full.renderer->height())) {
        if (retone) break;
        if (f == 1) {
            RenderRequest kept_one = request;
            // (Kept while the server runs: not a histogram of more than a quarter GiB.)
            kept_one.keep_histogram =
                histogram_bytes(full.renderer->histogram_shape()) <= kept_histogram_bytes;
            stages.push_back(plan_render(full, kept_one));
            continue;
        }
        CNode draft = root;
        for (const auto& s : draft_overrides(full, f)) apply_override(draft, s);
        stages.push_back(plan_render(load_pipeline(*c.reg, std::move(draft)), request));
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
    v["retoned"] = retone;
    send_json(res, 200, v);
}

static long long query_int(const httplib::Request& req, const std::string& key) {
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
        res.set_header("X-Retoned", a.frame->retoned ? "1" : "0");
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

static bool has_yaml_extension(const std::string& path) {
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
    const std::string out = field(body, "output", false);
    const Pipeline p = load_checked(c, parse_config(text, source_name(path)));
    RenderPlan plan = plan_render(p, render_request(c, p, path, out, flag(body, "force")));
    // A render takes every render thread (and the memory of a full image): two at once would
    // halve each, and a page could start any number. Taken once the text has passed its
    // checks, so that a refused request never turns away one that would render.
    const std::unique_lock<std::mutex> lock(c.render_lock, std::try_to_lock);
    if (!lock.owns_lock()) throw HttpError{409, "a render is running: wait for it to finish"};

    // Rendered on this request's thread, as `fixpoint render` would, stopped by the server's
    // stop flag (Ctrl-C) only: the preview goes on beside it.
    RenderHooks hooks;
    hooks.cancel = c.stop;
    const RenderResult r = run_render(plan, hooks);
    Json v = ok();
    v["output"] = plan.output;
    v["seconds"] = r.seconds;
    v["summary"] = summary_line(plan, r);
    Json warnings = Json::array();
    for (const auto& w : p.warnings) warnings.push_back(w);
    for (const auto& w : r.warnings) warnings.push_back(w);
    v["warnings"] = warnings;
    send_json(res, 200, v);
}

// The file name an image's bytes are read from: read_recipe tells formats by name.
static std::string image_extension(const std::string& b) {
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

} // namespace fp::host::serve_detail
