#include "context.hpp"

#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/text.hpp>

#include <httplib.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <regex>

namespace fs = std::filesystem;

namespace fp::host::serve_detail {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

// Compared in a time that does not depend on where the strings first differ.
bool same_secret(const std::string& a, const std::string& b) {
    if (a.size() != b.size()) return false;
    unsigned char d = 0;
    for (std::size_t i = 0; i < a.size(); ++i) d |= static_cast<unsigned char>(a[i] ^ b[i]);
    return d == 0;
}

// Whether `inner` (canonical) is `outer` (canonical) or inside it, component by component
// (so that /srv/ab is not taken for inside /srv/a).
bool is_within(const fs::path& inner, const fs::path& outer) {
    auto i = inner.begin();
    for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
        if (o->empty()) continue; // a trailing separator
        if (i == inner.end() || *i != *o) return false;
    }
    return true;
}

} // namespace

void Context::admit_head(const httplib::Request& req, Body body) const {
    if (loopback) {
        // DNS rebinding: a page of another site whose name is made to resolve to 127.0.0.1
        // reaches this server as the same origin; its requests name that site in Host.
        const std::string h = lower(req.get_header_value("Host"));
        const std::string shown = lower(host.find(':') != std::string::npos ? "[" + host + "]" : host);
        bool ok = false;
        for (const std::string& name :
             {std::string("127.0.0.1"), std::string("localhost"), std::string("[::1]"), shown})
            // A browser leaves out the port when it is HTTP's own.
            ok = ok || h == name + ":" + std::to_string(port) || (port == 80 && h == name);
        if (!ok)
            throw HttpError{403,
                            "this server answers only requests to http://127.0.0.1:" + std::to_string(port) +
                                "/ or http://localhost:" + std::to_string(port) + "/ (the Host header was " +
                                quote(req.get_header_value("Host"), 80) + ")"};
    }
    if (!token.empty()) {
        const std::string given =
            req.has_param("token") ? req.get_param_value("token") : req.get_header_value("X-Fixpoint-Token");
        if (!same_secret(given, token))
            throw HttpError{403,
                            "this server needs its token: open the address it printed, with its ?token=, "
                            "or send the header X-Fixpoint-Token"};
    }
    if (body == Body::None) return;
    const std::string want = body == Body::Json ? "application/json" : "application/octet-stream";
    std::string type = req.get_header_value("Content-Type");
    type = lower(type.substr(0, type.find(';')));
    type.erase(type.find_last_not_of(" \t") + 1);
    if (type != want)
        throw HttpError{415, "POST " + req.path + " takes Content-Type: " + want + ", not " +
                                 (type.empty() ? std::string("none") : quote(type, 80))};
    // Refused before it is read (httplib reads up to its own limit, that of /api/recipe). A
    // body without its length (chunked) is refused too: httplib would read it whole, up to
    // that limit, before its size could be checked (34 at once held 2.7 GB). The page and
    // every ordinary client send the length.
    const std::string length = req.get_header_value("Content-Length");
    if (length.empty())
        throw HttpError{411, "POST " + req.path +
                                 ": a body without a Content-Length (chunked) is refused: send its length"};
    unsigned long long n = 0;
    const auto [end, ec] = std::from_chars(length.data(), length.data() + length.size(), n);
    const std::size_t limit = body == Body::Json ? max_json_body : max_image_body;
    if (!length.empty() && end == length.data() + length.size() &&
        (ec == std::errc::result_out_of_range || n > limit))
        throw HttpError{413, "POST " + req.path + ": a body of " + length + " bytes; at most " +
                                 std::to_string(limit)};
}

void Context::admit(const httplib::Request& req, Body body) const {
    admit_head(req, body);
    // (The length the client gave is the size read; checked again all the same.)
    const std::size_t limit = body == Body::Json ? max_json_body : max_image_body;
    if (body != Body::None && req.body.size() > limit)
        throw HttpError{413, "POST " + req.path + ": a body of " + std::to_string(req.body.size()) +
                                 " bytes; at most " + std::to_string(limit)};
}

std::string Context::inside(const std::string& rel, const std::string& what, const std::string& mark) const {
    const std::string pre = (mark.empty() ? "" : mark + ": ") + what + " " + quote(rel, 200) + ": ";
    if (rel.empty()) throw HttpError{400, (mark.empty() ? "" : mark + ": ") + what + ": an empty path"};
    // A NUL ends the name the system calls see ("evil.sh\0.yaml" would write evil.sh, past
    // the extension check); the other control characters have no place in a name either.
    for (const char ch : rel)
        if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f)
            throw HttpError{403, pre + "a control character in a name is refused"};
    const fs::path p(rel);
    if (p.is_absolute())
        throw HttpError{403, pre + "an absolute path; paths are relative to the served folder " +
                                 quote(root.string(), 200)};
    for (const auto& part : p)
        if (part == "..") throw HttpError{403, pre + "'..' is refused: paths stay inside the served folder"};
    std::error_code ec;
    // The real path, symlinks followed, of the part that exists.
    fs::path real = fs::weakly_canonical(root / p, ec);
    // weakly_canonical stops at the first part that does not exist; a dangling symlink there
    // would still be followed by a write, so its target is resolved in turn.
    for (int hops = 0; !ec; ++hops) {
        fs::path head;
        std::error_code missing; // (set for a part that does not exist: that is the question)
        auto part = real.begin();
        for (; part != real.end(); ++part)
            if (head /= *part; !fs::exists(fs::status(head, missing))) break;
        if (part == real.end() || !fs::is_symlink(fs::symlink_status(head, missing))) break;
        if (hops == 40) throw HttpError{403, pre + "too many levels of symbolic links"};
        fs::path target = fs::read_symlink(head, ec);
        if (target.is_relative()) target = head.parent_path() / target;
        for (++part; part != real.end(); ++part) target /= *part;
        real = fs::weakly_canonical(target, ec);
    }
    if (ec) throw HttpError{403, pre + "cannot resolve it: " + ec.message()};
    if (!is_within(real, root))
        throw HttpError{403, pre + "leaves the served folder through a symbolic link (to " +
                                 quote(real.string(), 200) + ")"};
    return rel;
}

namespace {

constexpr int max_depth = 64;
// The most keys a request body holds, all objects together (the page sends a handful).
constexpr std::size_t max_keys = 4096;

// nlohmann's message, less its "[json.exception.parse_error.101] " id, as one line of ours:
// "bad JSON at line 1, column 2: syntax error while parsing ...".
std::string json_message(const nlohmann::json::exception& e) {
    std::string m = e.what();
    if (m.rfind("[json.exception.", 0) == 0 && m.find("] ") != std::string::npos)
        m.erase(0, m.find("] ") + 2);
    const std::string parse = "parse error ";
    m = m.rfind(parse, 0) == 0 ? "bad JSON " + m.substr(parse.size()) : "bad JSON: " + m;
    // It quotes the token it was reading ("last read: '...'", "number overflow parsing '...'"),
    // which may be a whole string of the body: keep the token's end, where the error is.
    std::size_t begin = std::string::npos;
    for (const std::string lead : {"last read: '", "parsing '"}) {
        if (const std::size_t at = m.find(lead); at != std::string::npos) {
            begin = at + lead.size();
            break;
        }
    }
    if (begin == std::string::npos) return m;
    std::size_t end = m.rfind("'; expected ");
    if (end == std::string::npos || end < begin) end = m.size() - 1;
    constexpr std::size_t keep = 40;
    if (end <= begin + keep) return m;
    std::size_t cut = end - keep;
    while (cut < end && (static_cast<unsigned char>(m[cut]) & 0xC0) == 0x80) ++cut; // whole UTF-8
    return m.substr(0, begin) + "..." + m.substr(cut);
}

} // namespace

Json parse_body(const httplib::Request& req) {
    // The page's bodies are flat objects: one nested more than 64 deep is no request of ours,
    // and is refused while it is read (nlohmann's parser itself sets no limit).
    // Nor one of more than max_keys keys: an ordered object finds a key by a linear search, so
    // 100 000 keys took 12.7 s of a request thread (a 4 MiB body, minutes).
    std::size_t keys = 0;
    const auto limit = [&keys](int depth, Json::parse_event_t event, Json&) {
        if ((event == Json::parse_event_t::object_start || event == Json::parse_event_t::array_start) &&
            depth >= max_depth)
            throw HttpError{400, "bad JSON: nested more than " + std::to_string(max_depth) + " levels"};
        if (event == Json::parse_event_t::key && ++keys > max_keys)
            throw HttpError{400, "bad JSON: more than " + std::to_string(max_keys) + " keys"};
        return true;
    };
    Json v;
    try {
        v = Json::parse(req.body, limit);
    } catch (const nlohmann::json::exception& e) {
        throw HttpError{400, json_message(e)};
    }
    if (!v.is_object()) throw HttpError{400, "the body must be a JSON object"};
    return v;
}

std::string field(const Json& body, const std::string& key, bool required) {
    const auto v = body.find(key);
    if (v == body.end() || v->is_null()) {
        if (required) throw HttpError{400, "missing field '" + key + "' (a string)"};
        return "";
    }
    if (!v->is_string()) throw HttpError{400, "field '" + key + "': expected a string"};
    return v->get<std::string>();
}

bool flag(const Json& body, const std::string& key) {
    const auto v = body.find(key);
    if (v == body.end() || v->is_null()) return false;
    if (!v->is_boolean()) throw HttpError{400, "field '" + key + "': expected true or false"};
    return v->get<bool>();
}

void send_json(httplib::Response& res, int status, const Json& v) {
    res.status = status;
    res.set_header("Cache-Control", "no-store");
    // Texts read from files may hold bytes that are not UTF-8: U+FFFD stands for each
    // (dump would throw otherwise).
    res.set_content(v.dump(-1, ' ', false, Json::error_handler_t::replace), "application/json");
}

Json refusal(const std::string& text) {
    Json v = Json::object();
    v["ok"] = false;
    v["error"] = text;
    // The first "file:L:C:" of the line (the file's name may hold anything but that).
    static const std::regex at(":([0-9]{1,9}):([0-9]{1,9}):");
    std::smatch m;
    const bool has = std::regex_search(text, m, at);
    v["line"] = has ? std::stoi(m[1].str()) : 0;
    v["column"] = has ? std::stoi(m[2].str()) : 0;
    return v;
}

std::string source_name(const std::string& path) { return path.empty() ? "<config>" : path; }

namespace {

// The path of a node in messages, as the loader writes it: "renderer.maps[0].shape".
std::string child_path(const std::string& parent, const std::string& key) {
    return parent.empty() ? key : parent + "." + key;
}

// A file a plugin reads, named by `key` of `node` (a plugin's mapping at `at`): inside the root.
void check_read_file(const Context& c, const CNode& node, const std::string& key, const std::string& at) {
    const CNode* v = node.find(key);
    if (!v || !v->is_scalar()) return; // (the plugin refuses what is not a string)
    try {
        // The file the render will read: from the config's folder (file_from_config).
        c.inside(file_from_config(v->scalar, v->mark), child_path(at, key), v->mark.str());
    } catch (const HttpError& e) {
        throw InputError(e.message); // config content: a refusal at its line
    }
}

void check_node(const Context& c, const CNode& n, const std::string& at) {
    if (n.is_seq()) {
        for (std::size_t i = 0; i < n.items.size(); ++i)
            check_node(c, n.items[i], at + "[" + std::to_string(i) + "]");
        return;
    }
    if (!n.is_map()) return;
    // What the plugin named by `type:` declares (its descriptor): whether building it runs code
    // its parameters carry, and which parameters name files it reads. Any node with a `type:` is
    // asked, wherever it stands (a plugin may not even take it there: refused before validation
    // would say so). A name no plugin has is left to validation ("unknown plugin").
    if (const CNode* type = n.find("type"); type && type->is_scalar())
        if (const PluginEntry* e = c.reg->find(type->scalar)) {
            const PluginDescriptor& d = *e->desc;
            // It runs the code of its parameters when the config loads: a page (or any local
            // process) could run anything as this user through /api/check.
            if (d.runs_code && !c.allow_python)
                throw InputError(n.mark.str() + ": " + (at.empty() ? std::string("the config") : at) + ": " +
                                 d.name +
                                 " runs Python code: fixpoint serve refuses it unless started with "
                                 "--allow-python");
            for (std::uint32_t i = 0; i < d.n_params; ++i) {
                const ParamSpec& s = d.params[i];
                if (s.role != ParamRole::file) continue;
                const CNode* v = n.find(s.name);
                if (v && v->is_scalar() && !is_builtin_file(s, v->scalar)) check_read_file(c, n, s.name, at);
            }
        }
    for (const auto& [key, child] : n.keys) check_node(c, child, child_path(at, key));
}

} // namespace

void check_served_config(const Context& c, const CNode& root) { check_node(c, root, ""); }

Pipeline load_checked(const Context& c, const CNode& root) {
    check_served_config(c, root);
    Pipeline p = load_pipeline(*c.reg, root);
    check_memory(p, c.threads);
    // An output.path of a format fixpoint does not write is refused by `render` before the
    // render starts: the preview refuses it too, at the same place.
    if (!p.output_path.empty()) {
        try {
            format_for(p.output_path);
        } catch (const InputError& e) {
            throw InputError(p.output_mark.str() + ": output.path: " + e.what());
        }
        check_vector_output(p, p.output_path); // (an SVG from a raster renderer, as render refuses it)
    }
    return p;
}

} // namespace fp::host::serve_detail
