// Numbers in messages: the shortest text that reads back as the value, so an error line quotes
// exactly what the user wrote ("got 0.5", not "got 0.500000"), whatever the plugin.
#pragma once

#include <charconv>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace fp {

/// Shortest decimal text that reads back as `v` ("0.5", "2", "1e-07", "inf").
inline std::string number_text(double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

/// A short, printable excerpt of user input for an error line: control characters (newlines,
/// terminal escape sequences, C1 controls) and bytes that are not UTF-8 are written as escapes
/// (\n, \t, \x1b, \u009b), and text past `max_chars` characters is cut with "...". Error
/// lines are one line on a terminal whatever the input held.
inline std::string excerpt(std::string_view s, std::size_t max_chars = 48) {
    static constexpr char hex[] = "0123456789abcdef";
    std::string out;
    std::size_t chars = 0, i = 0;
    while (i < s.size()) {
        if (chars == max_chars) return out + "...";
        const auto c = static_cast<unsigned char>(s[i]);
        // The length of a well-formed UTF-8 sequence starting here (0: not one).
        std::size_t len = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
        if (len > 1) {
            if (i + len > s.size()) len = 0;
            for (std::size_t k = 1; k < len; ++k)
                if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) len = 0;
        }
        if (len == 1 && c >= 0x20 && c != 0x7f) {
            out += char(c);
        } else if (len == 1 && (c == '\n' || c == '\t' || c == '\r')) {
            out += c == '\n' ? "\\n" : c == '\t' ? "\\t" : "\\r";
        } else if (len == 2 && c == 0xc2 && static_cast<unsigned char>(s[i + 1]) < 0xa0) {
            // C1 controls (U+0080..U+009F): some terminals take U+009B as an escape sequence.
            const auto d = static_cast<unsigned char>(s[i + 1]);
            out += "\\u00";
            out += hex[d >> 4];
            out += hex[d & 15];
        } else if (len > 1) {
            out.append(s.substr(i, len));
        } else {
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
            len = 1;
        }
        i += len;
        ++chars;
    }
    return out;
}

/// Edit distance (insertions, deletions, substitutions), for suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b);
/// The candidates near `word` (within a third of its length, at least 2 edits), nearest first, at
/// most 3: what "did you mean" lines offer (a plugin's name, a key, a palette's).
std::vector<std::string> suggest(std::string_view word, const std::vector<std::string>& candidates);

/// `excerpt(s)` in single quotes: what error lines say when they quote input.
inline std::string quote(std::string_view s, std::size_t max_chars = 48) {
    return "'" + excerpt(s, max_chars) + "'";
}

} // namespace fp
