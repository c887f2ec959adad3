// libFuzzer target: the bytes are a request to `fixpoint serve`, and go through what the
// server does with one before any render: the checks of its head (Host, token, content type,
// size: Context::admit_head and admit), the parse of its JSON body (parse_body, with its
// depth and key limits), its fields, the path it names (Context::inside) and the config text it
// carries (parse_config, then check_served_config: python-scheme and files outside the root).
//
// Input: "METHOD PATH" on the first line, then "Name: value" header lines, an empty line, and
// the body (the rest). The first byte's low bit picks a loopback server (no token) or one on
// another address (token "t0ken"). Refusals (HttpError, fp::InputError) are the expected
// answers; anything else escaping is a finding (printed, then abort()). Writes no file.
#include "serve/context.hpp"
#include "verdict.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/config.hpp>

#include <httplib.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

namespace {

using namespace fp::host::serve_detail;

httplib::Request parse_request(const std::string& text) {
    httplib::Request req;
    const auto head_end = text.find("\n\n");
    const std::string head = text.substr(0, head_end);
    req.body = head_end == std::string::npos ? "" : text.substr(head_end + 2);
    std::size_t at = 0;
    bool first = true;
    while (at <= head.size()) {
        auto end = head.find('\n', at);
        if (end == std::string::npos) end = head.size();
        const std::string line = head.substr(at, end - at);
        at = end + 1;
        if (first) {
            first = false;
            const auto sp = line.find(' ');
            req.method = line.substr(0, sp);
            req.path = sp == std::string::npos ? "/" : line.substr(sp + 1);
            continue;
        }
        const auto colon = line.find(':');
        if (colon == std::string::npos) continue;
        std::string value = line.substr(colon + 1);
        while (!value.empty() && value.front() == ' ') value.erase(0, 1);
        req.headers.emplace(line.substr(0, colon), value);
    }
    // As httplib sets them: the query's parameters (the token) from the path.
    if (const auto q = req.path.find('?'); q != std::string::npos) {
        httplib::detail::parse_query_text(req.path.substr(q + 1), req.params);
        req.path.erase(q);
    }
    return req;
}

void serve_request(const Context& c, const std::string& text) {
    const httplib::Request req = parse_request(text);
    const Body body = req.method != "POST"        ? Body::None
                      : req.path == "/api/recipe" ? Body::Bytes
                                                  : Body::Json;
    c.admit_head(req, body);
    c.admit(req, body);
    if (body != Body::Json) return;
    const Json v = parse_body(req);
    const std::string path = field(v, "path", false);
    if (!path.empty()) (void)c.inside(path, "path");
    (void)flag(v, "force");
    const std::string config = field(v, "text", true);
    const fp::host::CNode root = fp::host::parse_config(config, source_name(path));
    check_served_config(c, root);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::filesystem::path root =
        std::filesystem::canonical(std::filesystem::temp_directory_path());
    // The plugins, as serve has them: its checks ask each `type:` what its plugin declares
    // (code it runs, files it reads).
    static const fp::host::Registry* const reg = [] {
        static fp::host::Registry r;
        for (const auto& d : fp::host::Registry::default_dirs()) r.load_dir(d);
        return &r;
    }();
    Context c;
    c.root = root;
    c.reg = reg;
    const bool loopback = size == 0 || (data[0] & 1) == 0;
    c.host = loopback ? "127.0.0.1" : "192.0.2.1";
    c.port = 8420;
    c.loopback = loopback;
    if (!loopback) c.token = "t0ken";
    const std::string text(reinterpret_cast<const char*>(data) + (size ? 1 : 0), size ? size - 1 : 0);
    fp::fuzz::verdict("fuzz_serve", [&] {
        try {
            serve_request(c, text);
        } catch (const HttpError&) {
            // A refusal with its status: the expected answer to most inputs.
        }
    });
    return 0;
}
