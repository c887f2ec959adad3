#include "context.hpp"

#include <fixpoint/host/image_io.hpp>
#include <fixpoint/text.hpp>

#include <httplib.h>

#include <algorithm>
#include <cctype>
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

void Context::admit(const httplib::Request& req, Body body) const {
    if (loopback) {
        // DNS rebinding: a page of another site whose name is made to resolve to 127.0.0.1
        // reaches this server as the same origin; its requests name that site in Host.
        const std::string h = lower(req.get_header_value("Host")), p = ":" + std::to_string(port);
        const bool ok = h == "127.0.0.1" + p || h == "localhost" + p || h == "[::1]" + p ||
                        h == lower(host.find(':') != std::string::npos ? "[" + host + "]" : host) + p;
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
    const std::size_t limit = body == Body::Json ? max_json_body : max_image_body;
    if (req.body.size() > limit)
        throw HttpError{413, "POST " + req.path + ": a body of " + std::to_string(req.body.size()) +
                                 " bytes; at most " + std::to_string(limit)};
}

std::string Context::inside(const std::string& rel, const std::string& what, const std::string& mark) const {
    const std::string pre = (mark.empty() ? "" : mark + ": ") + what + " " + quote(rel, 200) + ": ";
    if (rel.empty()) throw HttpError{400, (mark.empty() ? "" : mark + ": ") + what + ": an empty path"};
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

json::Value parse_body(const httplib::Request& req) {
    json::Value v;
    try {
        v = json::parse(req.body);
    } catch (const json::ParseError& e) {
        throw HttpError{400, e.what()};
    }
    if (!v.is_object()) throw HttpError{400, "the body must be a JSON object"};
    return v;
}

std::string field(const json::Value& body, const std::string& key, bool required) {
    const json::Value* v = body.find(key);
    if (!v || v->type() == json::Value::Type::Null) {
        if (required) throw HttpError{400, "missing field '" + key + "' (a string)"};
        return "";
    }
    if (!v->is_string()) throw HttpError{400, "field '" + key + "': expected a string"};
    return v->str();
}

bool flag(const json::Value& body, const std::string& key) {
    const json::Value* v = body.find(key);
    if (!v || v->type() == json::Value::Type::Null) return false;
    if (!v->is_bool()) throw HttpError{400, "field '" + key + "': expected true or false"};
    return v->boolean();
}

void send_json(httplib::Response& res, int status, const json::Value& v) {
    res.status = status;
    res.set_header("Cache-Control", "no-store");
    res.set_content(json::dump(v), "application/json");
}

json::Value refusal(const std::string& text) {
    json::Value v = json::Value::object();
    v.set("ok", false);
    v.set("error", text);
    // The first "file:L:C:" of the line (the file's name may hold anything but that).
    static const std::regex at(":([0-9]{1,9}):([0-9]{1,9}):");
    std::smatch m;
    const bool has = std::regex_search(text, m, at);
    v.set("line", has ? std::stoi(m[1].str()) : 0);
    v.set("column", has ? std::stoi(m[2].str()) : 0);
    return v;
}

std::string source_name(const std::string& path) { return path.empty() ? "<config>" : path; }

CNode parse_config(const std::string& text, const std::string& source) {
    CNode root = parse_yaml(text, source);
    // As load_pipeline(path) does for an empty file: an empty mapping, refused for its
    // missing renderer at 1:1.
    if (root.type == CNode::Type::Null)
        root = map_node(), root.mark = Mark{std::make_shared<const std::string>(source), 1, 1};
    return root;
}

Pipeline load_checked(const Context& c, const CNode& root) {
    Pipeline p = load_pipeline(*c.reg, root);
    check_memory(p, c.threads);
    // An output.path of a format fixpoint does not write is refused by `render` before the
    // render starts: the preview refuses it too, at the same place.
    if (!p.output_path.empty()) try {
            format_for(p.output_path);
        } catch (const InputError& e) {
            throw InputError(p.output_mark.str() + ": output.path: " + e.what());
        }
    return p;
}

} // namespace fp::host::serve_detail
