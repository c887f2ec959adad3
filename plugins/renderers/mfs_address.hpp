// Addresses of polygons in an mfs (paper 05): the path of map numbers that produced a polygon,
// written as in the paper's labels, 1-based and dotted: "5" is f_5's polygon at level 1,
// "2.5" the polygon f_5 makes of it at level 2. Several addresses: "1; 3; 7; 9".
#pragma once

#include <fixpoint/errors.hpp>
#include <fixpoint/text.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fp_mfs {

using Address = std::vector<std::uint32_t>; ///< 0-based map indices, level 1 first

inline std::string address_text(const std::uint32_t* a, std::size_t len) {
    std::string s;
    for (std::size_t i = 0; i < len; ++i) s += (i ? "." : "") + std::to_string(a[i] + 1);
    return len ? s : "(the initial set)";
}
inline std::string address_text(const Address& a) { return address_text(a.data(), a.size()); }

/// Groups of non-negative integers: groups split at ';', numbers at `sep` (and spaces).
/// Throws fp::ParamError(param, ...) on anything else.
inline std::vector<std::vector<std::uint32_t>> parse_groups(const std::string& text, char sep,
                                                            const char* param, const char* what) {
    std::vector<std::vector<std::uint32_t>> out(1);
    std::string tok;
    auto flush = [&] {
        if (tok.empty()) return;
        if (tok.size() > 6) throw fp::ParamError(param, fp::quote(tok) + " is too large in " + what);
        out.back().push_back(std::uint32_t(std::stoul(tok)));
        tok.clear();
    };
    for (char c : text) {
        if (c >= '0' && c <= '9') {
            tok += c;
        } else if (c == sep || c == ' ') {
            if (c == sep && tok.empty() && sep != ' ')
                throw fp::ParamError(param, fp::quote(text) + " is not " + what);
            flush();
        } else if (c == ';') {
            flush();
            if (out.back().empty()) throw fp::ParamError(param, fp::quote(text) + " is not " + what);
            out.emplace_back();
        } else {
            throw fp::ParamError(param, fp::quote(text) + " is not " + what);
        }
    }
    flush();
    if (out.back().empty()) throw fp::ParamError(param, fp::quote(text) + " is not " + what);
    return out;
}

/// Addresses "2.5; 3": 1-based map numbers, each checked against the number of maps.
inline std::vector<Address> parse_addresses(const std::string& text, std::size_t maps, const char* param) {
    auto groups = parse_groups(text, '.', param, "a list of addresses such as \"5\" or \"2.5; 3.5\"");
    for (auto& g : groups)
        for (auto& v : g) {
            if (v == 0 || v > maps) {
                std::string shown;
                for (std::size_t i = 0; i < g.size(); ++i) shown += (i ? "." : "") + std::to_string(g[i]);
                throw fp::ParamError(param, "address " + fp::excerpt(shown) + " does not exist: " +
                                                (maps == 1 ? std::string("there is 1 map, f1")
                                                           : "there are " + std::to_string(maps) +
                                                                 " maps, f1 to f" + std::to_string(maps)));
            }
        }
    for (auto& g : groups)
        for (auto& v : g) --v;
    return groups;
}

} // namespace fp_mfs
