// Parameter schemas and the parameter bag plugins are built from.
//
// A plugin declares its parameters as a static array of ParamSpec (plain data, so the host
// can read it from the descriptor without constructing anything: `fixpoint describe`, YAML
// validation and the conformance suite all use it). The host checks a config against the
// schema (types, ranges, finiteness, unknown keys), fills in defaults and hands the plugin a
// ParamBag of typed values. Every read marks its key; a declared key the plugin never reads
// is reported by the host and by the conformance suite.
#pragma once

#include <fixpoint/errors.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace fp {

class Object;

enum class ParamType : std::uint32_t {
    Bool,
    Int,
    Real,
    String,   ///< free text, or one of `choices`
    Vec2,     ///< [x, y]
    Colour,   ///< [r, g, b] in [0, 1], or "#rrggbb"
    Reals,    ///< list of reals (`count` fixes the length when non-zero)
    Vec2s,    ///< list of [x, y]
    Object,   ///< a plugin instance of kind `kind`: a mapping with a `type:` key
    Objects,  ///< a list of plugin instances of kind `kind`, each with `item_params`
    Sequence, ///< a parameter sequence over the step index n: a number, a q-number, or a periodic list
};

std::string_view param_type_name(ParamType t);

/// What the host may do with a parameter besides handing it to the plugin. Declared in the
/// schema, so that the host asks a plugin's declaration instead of testing its name; plain
/// data, so a new use adds a value here, not a virtual function to every plugin. (ABI 16.)
enum class ParamRole : std::uint8_t {
    none,
    /// A count of work in proportion to the picture's pixels (chaos-game `points`, superfractal
    /// `points_per_buffer`): a draft of factor f (host/job/draft.hpp) takes 1/f^2 of it, so a
    /// pixel of the draft gets the points a pixel of the full render gets.
    work,
    /// Samples per pixel (orbit-trap `samples`): a draft takes one.
    samples,
    /// A file the plugin reads (a picture, a script): the host hands the plugin its path from the
    /// working folder, resolved from the folder of the config that names it (host/core/build.hpp's
    /// file_from_config), the recipe records it absolute, and serve keeps it inside its root. `builtins`
    /// names the values that are not files ("hues").
    file,
    /// Read only when the histogram is finished into an image (tone, filter, density estimation,
    /// the background): `fixpoint tone` may change it on a kept histogram (`render --histogram`),
    /// and a histogram file's recipe identity leaves it out. (ABI 18.)
    finish,
};

struct ParamSpec {
    const char* name = nullptr;
    ParamType type = ParamType::Real;
    const char* doc = nullptr;
    /// Default as YAML text ("1", "[0, 0]", "{type: picard}"); nullptr: required, or
    /// absent when `optional`.
    const char* default_yaml = nullptr;
    bool optional = false;
    /// Hard range of numeric values (each element of a list); open ends exclude the bound.
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false, hi_open = false;
    bool allow_nonfinite = false;
    /// Lists: exact length when non-zero; otherwise at least `min_count` elements.
    std::uint32_t count = 0, min_count = 0;
    Kind kind = Kind::Shape;                ///< Object, Objects
    const char* choices = nullptr;          ///< String: "a|b|c"
    const ParamSpec* item_params = nullptr; ///< Objects: extra keys beside `type:`
    std::uint32_t n_item_params = 0;
    ParamRole role = ParamRole::none;
    const char* builtins = nullptr; ///< role file: the values, "a|b", that name no file

    // constexpr builders: `param::real("radius", "radius of the circle").def("1").above(0)`
    constexpr ParamSpec def(const char* yaml) const {
        auto s = *this;
        s.default_yaml = yaml;
        return s;
    }
    constexpr ParamSpec opt() const {
        auto s = *this;
        s.optional = true;
        return s;
    }
    constexpr ParamSpec min(double v) const {
        auto s = *this;
        s.lo = v;
        s.lo_open = false;
        return s;
    }
    constexpr ParamSpec above(double v) const {
        auto s = *this;
        s.lo = v;
        s.lo_open = true;
        return s;
    }
    constexpr ParamSpec max(double v) const {
        auto s = *this;
        s.hi = v;
        s.hi_open = false;
        return s;
    }
    constexpr ParamSpec below(double v) const {
        auto s = *this;
        s.hi = v;
        s.hi_open = true;
        return s;
    }
    constexpr ParamSpec len(std::uint32_t n) const {
        auto s = *this;
        s.count = n;
        return s;
    }
    constexpr ParamSpec min_len(std::uint32_t n) const {
        auto s = *this;
        s.min_count = n;
        return s;
    }
    constexpr ParamSpec nonfinite() const {
        auto s = *this;
        s.allow_nonfinite = true;
        return s;
    }
    constexpr ParamSpec one_of(const char* c) const {
        auto s = *this;
        s.choices = c;
        return s;
    }
    constexpr ParamSpec as(ParamRole r) const {
        auto s = *this;
        s.role = r;
        return s;
    }
    /// role file, with the values that are built in rather than files ("hues").
    constexpr ParamSpec reads_file(const char* builtin_values = nullptr) const {
        auto s = *this;
        s.role = ParamRole::file;
        s.builtins = builtin_values;
        return s;
    }
    template <std::size_t N>
    constexpr ParamSpec items(const ParamSpec (&p)[N]) const {
        auto s = *this;
        s.item_params = p;
        s.n_item_params = N;
        return s;
    }
};

namespace param {
constexpr ParamSpec make(const char* n, ParamType t, const char* d) {
    ParamSpec s;
    s.name = n;
    s.type = t;
    s.doc = d;
    return s;
}
constexpr ParamSpec boolean(const char* n, const char* d) { return make(n, ParamType::Bool, d); }
constexpr ParamSpec integer(const char* n, const char* d) { return make(n, ParamType::Int, d); }
constexpr ParamSpec real(const char* n, const char* d) { return make(n, ParamType::Real, d); }
constexpr ParamSpec string(const char* n, const char* d) { return make(n, ParamType::String, d); }
constexpr ParamSpec vec2(const char* n, const char* d) { return make(n, ParamType::Vec2, d); }
constexpr ParamSpec colour(const char* n, const char* d) { return make(n, ParamType::Colour, d); }
constexpr ParamSpec reals(const char* n, const char* d) { return make(n, ParamType::Reals, d); }
constexpr ParamSpec vec2s(const char* n, const char* d) { return make(n, ParamType::Vec2s, d); }
constexpr ParamSpec object(const char* n, Kind k, const char* d) {
    auto s = make(n, ParamType::Object, d);
    s.kind = k;
    return s;
}
constexpr ParamSpec sequence(const char* n, const char* d) { return make(n, ParamType::Sequence, d); }
constexpr ParamSpec objects(const char* n, Kind k, const char* d) {
    auto s = make(n, ParamType::Objects, d);
    s.kind = k;
    return s;
}
} // namespace param

class ParamBag;

/// A parameter sequence over the step index n (paper 02): periodic, the value at step n is
/// values[n % values.size()]. Each value is a q-system number a + qb stored as (a, b) (a real
/// number has b = 0). Written in YAML as
///   0.7                      a constant
///   0.5+0.5q  or  "-0.9q"    a constant q-number
///   [0.7, 0.9]               two plain numbers: see `bare_pair`
///   [0.7, 0.9, 0.5]          a periodic list (eq. (29) alternates two values)
///   [0.5+0.5q, [0.1, 2]]     a periodic list of q-numbers (an element [a, b] is a + qb)
struct Sequence {
    std::vector<Vec2> values;
    /// Written as a list of exactly two plain numbers [x, y]: over the reals the periodic
    /// list (x, y), in a q-system the single number x + qy. The scheme decides, knowing its
    /// number system (resolve()).
    bool bare_pair = false;

    /// (A constant without the division: renderers ask at every step.)
    Vec2 at(std::uint64_t n) const { return values.size() == 1 ? values[0] : values[n % values.size()]; }
    /// The sequence as the scheme sees it, given whether it computes in the reals.
    Sequence resolve(bool real_numbers) const {
        if (!bare_pair || real_numbers) return {values, false};
        return {{Vec2{values[0].x, values[1].x}}, false};
    }
};

/// One element of an Objects parameter: the object and its extra keys (`weight`, ...).
struct ObjectItem {
    std::shared_ptr<const Object> object;
    std::shared_ptr<const ParamBag> extras;
};

/// A typed value of a parameter.
using ParamValue =
    std::variant<bool, std::int64_t, double, std::string, Vec2, Rgb, std::vector<double>, std::vector<Vec2>,
                 std::shared_ptr<const Object>, std::vector<ObjectItem>, Sequence>;

/// The typed parameters of one plugin instance. Built by the host; read by the plugin's
/// constructor. Reads of a name the schema does not declare are a plugin bug (InternalError);
/// reads of wrong type likewise.
class ParamBag {
public:
    ParamBag() = default;
    ParamBag(const ParamSpec* specs, std::size_t n, std::string owner);

    bool has(const std::string& name) const;
    bool boolean(const std::string& name) const;
    std::int64_t integer(const std::string& name) const;
    double real(const std::string& name) const;
    const std::string& string(const std::string& name) const;
    Vec2 vec2(const std::string& name) const;
    Rgb colour(const std::string& name) const;
    const std::vector<double>& reals(const std::string& name) const;
    const std::vector<Vec2>& vec2s(const std::string& name) const;
    const std::shared_ptr<const Object>& object_ptr(const std::string& name) const;
    const std::vector<ObjectItem>& objects(const std::string& name) const;
    const Sequence& sequence(const std::string& name) const;

    /// The object parameter `name` as interface I (the host has checked its kind).
    template <class I>
    std::shared_ptr<const I> object(const std::string& name) const {
        auto p = std::dynamic_pointer_cast<const I>(object_ptr(name));
        if (!p) bad_cast(name);
        return p;
    }

    // Host side.
    void set(const std::string& name, ParamValue v);
    /// Names of values present but never read.
    std::vector<std::string> unread() const;
    const std::string& owner() const { return owner_; }
    const ParamSpec* spec(const std::string& name) const;

private:
    const ParamValue& get(const std::string& name, ParamType t) const;
    [[noreturn]] void bad_cast(const std::string& name) const;

    struct Entry {
        ParamValue value;
        mutable bool read = false;
    };
    const ParamSpec* specs_ = nullptr;
    std::size_t n_specs_ = 0;
    std::string owner_;
    std::map<std::string, Entry> values_;
};

/// Cast an ObjectItem's object to interface I.
template <class I>
std::shared_ptr<const I> as(const ObjectItem& item) {
    return std::dynamic_pointer_cast<const I>(item.object);
}

} // namespace fp
