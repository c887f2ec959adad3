// A small JSON value, reader and writer for `fixpoint serve`: requests are flat objects of
// strings and booleans, answers a few nested objects and lists. Debian 12 has no JSON library
// in the packages fixpoint builds with, and this much is short.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fp::host::json {

/// A text that is not JSON: what() says what and at which byte.
class ParseError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Value {
public:
    enum class Type { Null, Bool, Number, String, Array, Object };

    Value() = default;
    Value(std::nullptr_t) {}
    Value(bool b) : type_(Type::Bool), bool_(b) {}
    Value(double d) : type_(Type::Number), number_(d) {}
    Value(int i) : type_(Type::Number), number_(i) {}
    Value(long i) : type_(Type::Number), number_(double(i)) {}
    Value(long long i) : type_(Type::Number), number_(double(i)) {}
    Value(unsigned long long i) : type_(Type::Number), number_(double(i)) {}
    Value(unsigned i) : type_(Type::Number), number_(i) {}
    Value(unsigned long i) : type_(Type::Number), number_(double(i)) {}
    Value(std::string s) : type_(Type::String), string_(std::move(s)) {}
    Value(const char* s) : type_(Type::String), string_(s) {}

    static Value array() { return Value(Type::Array); }
    static Value object() { return Value(Type::Object); }

    Type type() const { return type_; }
    bool is_string() const { return type_ == Type::String; }
    bool is_bool() const { return type_ == Type::Bool; }
    bool is_number() const { return type_ == Type::Number; }
    bool is_object() const { return type_ == Type::Object; }
    const std::string& str() const { return string_; }
    bool boolean() const { return bool_; }
    double number() const { return number_; }

    /// Object: the member `key`, or null when absent.
    const Value* find(std::string_view key) const;
    /// Object: set `key` (kept in insertion order; a key set again is replaced).
    Value& set(const std::string& key, Value v);
    /// Array: append.
    Value& push(Value v);
    const std::vector<Value>& items() const { return items_; }
    const std::vector<std::pair<std::string, Value>>& members() const { return members_; }

private:
    explicit Value(Type t) : type_(t) {}
    Type type_ = Type::Null;
    bool bool_ = false;
    double number_ = 0;
    std::string string_;
    std::vector<Value> items_;
    std::vector<std::pair<std::string, Value>> members_;
};

/// Parse one JSON value (RFC 8259; at most 64 levels deep). Throws ParseError.
Value parse(std::string_view text);
/// Write compactly; strings are escaped, bytes that are not UTF-8 become U+FFFD, numbers that
/// are not finite become null.
std::string dump(const Value& v);

} // namespace fp::host::json
