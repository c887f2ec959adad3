#include "json.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>

namespace fp::host::json {

const Value* Value::find(std::string_view key) const {
    for (const auto& [k, v] : members_)
        if (k == key) return &v;
    return nullptr;
}

Value& Value::set(const std::string& key, Value v) {
    for (auto& [k, old] : members_)
        if (k == key) return old = std::move(v);
    members_.emplace_back(key, std::move(v));
    return members_.back().second;
}

Value& Value::push(Value v) {
    items_.push_back(std::move(v));
    return items_.back();
}

namespace {

constexpr int max_depth = 64;

struct Reader {
    std::string_view s;
    std::size_t i = 0;

    [[noreturn]] void fail(const std::string& what) const {
        throw ParseError("bad JSON: " + what + " at byte " + std::to_string(i));
    }
    void ws() {
        while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\n' || s[i] == '\r')) ++i;
    }
    bool eat(char c) {
        ws();
        if (i < s.size() && s[i] == c) return ++i, true;
        return false;
    }
    void expect(char c) {
        if (!eat(c)) fail(std::string("expected '") + c + "'");
    }
    bool word(std::string_view w) {
        if (s.substr(i, w.size()) != w) return false;
        i += w.size();
        return true;
    }

    Value value(int depth) {
        if (depth > max_depth) fail("nested more than 64 levels");
        ws();
        if (i >= s.size()) fail("unexpected end");
        const char c = s[i];
        if (c == '{') {
            ++i;
            Value o = Value::object();
            if (eat('}')) return o;
            do {
                ws();
                if (i >= s.size() || s[i] != '"') fail("expected a key in quotes");
                std::string k = string();
                expect(':');
                o.set(k, value(depth + 1));
            } while (eat(','));
            expect('}');
            return o;
        }
        if (c == '[') {
            ++i;
            Value a = Value::array();
            if (eat(']')) return a;
            do a.push(value(depth + 1));
            while (eat(','));
            expect(']');
            return a;
        }
        if (c == '"') return Value(string());
        if (word("true")) return Value(true);
        if (word("false")) return Value(false);
        if (word("null")) return Value();
        return Value(number());
    }

    double number() {
        // JSON's grammar: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?
        const std::size_t start = i;
        const auto digits = [&] {
            const std::size_t from = i;
            while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
            return i > from;
        };
        if (i < s.size() && s[i] == '-') ++i;
        if (i < s.size() && s[i] == '0')
            ++i;
        else if (!digits())
            fail("unexpected character");
        if (i < s.size() && s[i] == '.' && (++i, !digits())) fail("expected digits after '.'");
        if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
            ++i;
            if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
            if (!digits()) fail("expected digits in the exponent");
        }
        double d = 0;
        const auto [end, ec] = std::from_chars(s.data() + start, s.data() + i, d);
        if (ec != std::errc() || end != s.data() + i) fail("a number out of range");
        return d;
    }

    unsigned hex4() {
        if (i + 4 > s.size()) fail("a short \\u escape");
        unsigned v = 0;
        for (int k = 0; k < 4; ++k) {
            const char c = s[i++];
            v <<= 4;
            if (c >= '0' && c <= '9')
                v |= unsigned(c - '0');
            else if (c >= 'a' && c <= 'f')
                v |= unsigned(c - 'a' + 10);
            else if (c >= 'A' && c <= 'F')
                v |= unsigned(c - 'A' + 10);
            else
                fail("a bad \\u escape");
        }
        return v;
    }

    static void utf8(std::string& out, unsigned cp) {
        if (cp < 0x80) {
            out += char(cp);
        } else if (cp < 0x800) {
            out += char(0xC0 | (cp >> 6));
            out += char(0x80 | (cp & 0x3F));
        } else if (cp < 0x10000) {
            out += char(0xE0 | (cp >> 12));
            out += char(0x80 | ((cp >> 6) & 0x3F));
            out += char(0x80 | (cp & 0x3F));
        } else {
            out += char(0xF0 | (cp >> 18));
            out += char(0x80 | ((cp >> 12) & 0x3F));
            out += char(0x80 | ((cp >> 6) & 0x3F));
            out += char(0x80 | (cp & 0x3F));
        }
    }

    std::string string() {
        ++i; // the opening quote
        std::string out;
        while (true) {
            if (i >= s.size()) fail("an unterminated string");
            const char c = s[i++];
            if (c == '"') return out;
            if (static_cast<unsigned char>(c) < 0x20) fail("a control character in a string");
            if (c != '\\') {
                out += c;
                continue;
            }
            if (i >= s.size()) fail("an unterminated string");
            switch (s[i++]) {
            case '"': out += '"'; break;
            case '\\': out += '\\'; break;
            case '/': out += '/'; break;
            case 'b': out += '\b'; break;
            case 'f': out += '\f'; break;
            case 'n': out += '\n'; break;
            case 'r': out += '\r'; break;
            case 't': out += '\t'; break;
            case 'u': {
                unsigned cp = hex4();
                if (cp >= 0xD800 && cp < 0xDC00) {
                    // A surrogate pair: the low half must follow.
                    if (!word("\\u")) fail("a lone surrogate");
                    const unsigned lo = hex4();
                    if (lo < 0xDC00 || lo >= 0xE000) fail("a lone surrogate");
                    cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
                } else if (cp >= 0xDC00 && cp < 0xE000) {
                    fail("a lone surrogate");
                }
                utf8(out, cp);
                break;
            }
            default: fail("a bad escape");
            }
        }
    }
};

// The length of the UTF-8 sequence at s[i], or 0 when it is not one (overlong forms,
// surrogates and values above U+10FFFF included).
std::size_t utf8_length(std::string_view s, std::size_t i) {
    const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned c = b(i);
    std::size_t n = 0;
    unsigned cp = 0;
    if (c < 0x80) return 1;
    if (c >= 0xC2 && c <= 0xDF)
        n = 2, cp = c & 0x1F;
    else if (c >= 0xE0 && c <= 0xEF)
        n = 3, cp = c & 0x0F;
    else if (c >= 0xF0 && c <= 0xF4)
        n = 4, cp = c & 0x07;
    else
        return 0;
    if (i + n > s.size()) return 0;
    for (std::size_t k = 1; k < n; ++k) {
        if ((b(i + k) & 0xC0) != 0x80) return 0;
        cp = (cp << 6) | (b(i + k) & 0x3F);
    }
    if ((n == 3 && (cp < 0x800 || (cp >= 0xD800 && cp < 0xE000))) ||
        (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)))
        return 0;
    return n;
}

void write_string(std::string& out, std::string_view s) {
    out += '"';
    for (std::size_t i = 0; i < s.size();) {
        const char c = s[i];
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x80) {
            const std::size_t n = utf8_length(s, i);
            if (n == 0) {
                out += "\xEF\xBF\xBD"; // U+FFFD for a byte that is not UTF-8
                ++i;
            } else {
                out.append(s.substr(i, n));
                i += n;
            }
            continue;
        }
        ++i;
        switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\r': out += "\\r"; break;
        case '\t': out += "\\t"; break;
        default:
            if (u < 0x20 || u == 0x7F) {
                static const char hex[] = "0123456789abcdef";
                out += "\\u00";
                out += hex[u >> 4];
                out += hex[u & 15];
            } else {
                out += c;
            }
        }
    }
    out += '"';
}

void write(std::string& out, const Value& v) {
    switch (v.type()) {
    case Value::Type::Null: out += "null"; break;
    case Value::Type::Bool: out += v.boolean() ? "true" : "false"; break;
    case Value::Type::Number: {
        if (!std::isfinite(v.number())) {
            out += "null";
            break;
        }
        char buf[32];
        const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v.number());
        out.append(buf, ec == std::errc() ? end : buf);
        break;
    }
    case Value::Type::String: write_string(out, v.str()); break;
    case Value::Type::Array: {
        out += '[';
        bool first = true;
        for (const auto& item : v.items()) {
            if (!first) out += ',';
            first = false;
            write(out, item);
        }
        out += ']';
        break;
    }
    case Value::Type::Object: {
        out += '{';
        bool first = true;
        for (const auto& [k, item] : v.members()) {
            if (!first) out += ',';
            first = false;
            write_string(out, k);
            out += ':';
            write(out, item);
        }
        out += '}';
        break;
    }
    }
}

} // namespace

Value parse(std::string_view text) {
    Reader r{text};
    Value v = r.value(0);
    r.ws();
    if (r.i != text.size()) r.fail("text after the value");
    return v;
}

std::string dump(const Value& v) {
    std::string out;
    write(out, v);
    return out;
}

} // namespace fp::host::json
