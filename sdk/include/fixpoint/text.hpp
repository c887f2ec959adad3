// Numbers in messages: the shortest text that reads back as the value, so an error line quotes
// exactly what the user wrote ("got 0.5", not "got 0.500000"), whatever the plugin.
#pragma once

#include <charconv>
#include <string>

namespace fp {

/// Shortest decimal text that reads back as `v` ("0.5", "2", "1e-07", "inf").
inline std::string number_text(double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

} // namespace fp
