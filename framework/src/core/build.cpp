// Schema validation and object construction.
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/text.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>

namespace fp::host {

namespace {

[[noreturn]] void fail(const Mark& m, const std::string& path, const std::string& msg) {
    throw InputError(m.str() + ": " + (path.empty() ? "" : path + ": ") + msg);
}

std::string join(const std::vector<std::string>& v, const char* sep) {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
    return s;
}

std::string quoted_list(const std::vector<std::string>& v) {
    std::vector<std::string> q;
    for (const auto& s : v) q.push_back("'" + s + "'");
    return q.size() <= 1 ? join(q, "") : join({q.begin(), q.end() - 1}, ", ") + " or " + q.back();
}

std::string article(std::string_view kind) {
    return (kind[0] == 'a' || kind[0] == 'e' || kind[0] == 'i' || kind[0] == 'o' || kind[0] == 'u' ? "an "
                                                                                                   : "a ") +
           std::string(kind);
}

// ------------------------------------------------------------------ scalars
bool parse_real(const CNode& n, double& out) {
    if (!n.is_scalar() || n.quoted) return false;
    const std::string& s = n.scalar;
    if (s == ".nan" || s == ".NaN" || s == ".NAN" || s == "nan" || s == "NaN") {
        out = std::numeric_limits<double>::quiet_NaN();
        return true;
    }
    if (s == ".inf" || s == ".Inf" || s == "+.inf" || s == "inf" || s == "+inf") {
        out = std::numeric_limits<double>::infinity();
        return true;
    }
    if (s == "-.inf" || s == "-.Inf" || s == "-inf") {
        out = -std::numeric_limits<double>::infinity();
        return true;
    }
    const char* b = s.data();
    const char* e = s.data() + s.size();
    if (b != e && *b == '+') ++b;
    auto [p, ec] = std::from_chars(b, e, out);
    return ec == std::errc() && p == e && b != e;
}

bool parse_int(const CNode& n, std::int64_t& out) {
    if (!n.is_scalar() || n.quoted) return false;
    const char* b = n.scalar.data();
    const char* e = b + n.scalar.size();
    if (b != e && *b == '+') ++b;
    auto [p, ec] = std::from_chars(b, e, out);
    if (ec == std::errc() && p == e && b != e) return true;
    // 1e6 and 1000000.0 are integers too, when exact.
    double d;
    if (parse_real(n, d) && std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 9.0e15) {
        out = std::int64_t(d);
        return true;
    }
    return false;
}

std::string range_text(const ParamSpec& s) {
    const bool has_lo = std::isfinite(s.lo), has_hi = std::isfinite(s.hi);
    if (has_lo && has_hi)
        return std::string("in ") + (s.lo_open ? "(" : "[") + format_real(s.lo) + ", " + format_real(s.hi) +
               (s.hi_open ? ")" : "]");
    if (has_lo) return std::string(s.lo_open ? "> " : ">= ") + format_real(s.lo);
    if (has_hi) return std::string(s.hi_open ? "< " : "<= ") + format_real(s.hi);
    return "";
}

void check_number(const ParamSpec& s, double v, const CNode& n, const std::string& path) {
    if (!std::isfinite(v) && !s.allow_nonfinite)
        fail(n.mark, path, "must be a finite number, got " + excerpt(n.scalar));
    const bool below = s.lo_open ? !(v > s.lo) : !(v >= s.lo);
    const bool above = s.hi_open ? !(v < s.hi) : !(v <= s.hi);
    if ((std::isfinite(s.lo) && below) || (std::isfinite(s.hi) && above))
        fail(n.mark, path, "must be " + range_text(s) + ", got " + excerpt(n.scalar));
}

double real_value(const ParamSpec& s, const CNode& n, const std::string& path,
                  const char* what = "a real number") {
    double v;
    if (!parse_real(n, v)) fail(n.mark, path, std::string("expected ") + what + ", got " + n.describe());
    check_number(s, v, n, path);
    return v;
}

Vec2 vec2_value(const ParamSpec& s, const CNode& n, const std::string& path) {
    if (!n.is_seq() || n.items.size() != 2)
        fail(n.mark, path, "expected a point [x, y], got " + n.describe());
    return {real_value(s, n.items[0], path), real_value(s, n.items[1], path)};
}

Rgb colour_value(const CNode& n, const std::string& path) {
    if (n.is_scalar() && n.scalar.size() == 7 && n.scalar[0] == '#') {
        unsigned v = 0;
        auto [p, ec] = std::from_chars(n.scalar.data() + 1, n.scalar.data() + 7, v, 16);
        if (ec == std::errc() && p == n.scalar.data() + 7)
            return {float((v >> 16) & 255) / 255.f, float((v >> 8) & 255) / 255.f, float(v & 255) / 255.f};
    }
    if (!n.is_seq() || n.items.size() != 3)
        fail(n.mark, path,
             "expected a colour [r, g, b] with components in [0, 1] or \"#rrggbb\", got " + n.describe());
    ParamSpec unit = param::real("", "").min(0).max(1);
    return {float(real_value(unit, n.items[0], path)), float(real_value(unit, n.items[1], path)),
            float(real_value(unit, n.items[2], path))};
}

void check_count(const ParamSpec& s, const CNode& n, const std::string& path, const char* what) {
    if (!n.is_seq()) fail(n.mark, path, std::string("expected a list of ") + what + ", got " + n.describe());
    if (s.count && n.items.size() != s.count)
        fail(n.mark, path,
             "expected " + std::to_string(s.count) + " " + what + ", got " + std::to_string(n.items.size()));
    if (n.items.empty() && s.min_count) fail(n.mark, path, std::string("the list of ") + what + " is empty");
    if (n.items.size() < s.min_count)
        fail(n.mark, path,
             "expected at least " + std::to_string(s.min_count) + " " + what + ", got " +
                 std::to_string(n.items.size()));
}

/// A list of values of one type, each read by `item` at its own path ("maps[2]").
template <class V, class Item>
std::vector<V> list_value(const ParamSpec& s, const CNode& n, const std::string& path, const char* what,
                          Item item) {
    check_count(s, n, path, what);
    std::vector<V> v;
    for (std::size_t i = 0; i < n.items.size(); ++i)
        v.push_back(item(s, n.items[i], path + "[" + std::to_string(i) + "]"));
    return v;
}

TParam validate_param(const Registry& reg, const ParamSpec& s, const CNode& n, const std::string& path);

// A q-system number a + qb written as text: "0.5+0.5q", "0.75-0.9q", "-2q", "q", "1.5".
bool parse_qnumber(const std::string& text, Vec2& out) {
    std::string t;
    for (char c : text)
        if (c != ' ') t += c;
    auto real_of = [](const std::string& s, double& v) {
        const char* b = s.data();
        const char* e = b + s.size();
        if (b != e && *b == '+') ++b;
        auto [p, ec] = std::from_chars(b, e, v);
        return ec == std::errc() && p == e && b != e;
    };
    if (t.empty()) return false;
    if (t.back() != 'q') {
        out.y = 0;
        return real_of(t, out.x);
    }
    t.pop_back();
    // The sign that starts the q part: the last + or - not at the start and not an exponent's.
    std::size_t split = 0;
    for (std::size_t i = 1; i < t.size(); ++i)
        if ((t[i] == '+' || t[i] == '-') && t[i - 1] != 'e' && t[i - 1] != 'E') split = i;
    const std::string re = t.substr(0, split), im = t.substr(split);
    out.x = 0;
    if (!re.empty() && !real_of(re, out.x)) return false;
    if (im.empty() || im == "+")
        out.y = 1;
    else if (im == "-")
        out.y = -1;
    else if (!real_of(im, out.y))
        return false;
    return true;
}

Vec2 qnumber_value(const CNode& n, const std::string& path) {
    Vec2 v;
    double d;
    if (n.is_seq() && n.items.size() == 2 && parse_real(n.items[0], d) && parse_real(n.items[1], v.y)) {
        v.x = d;
    } else if (parse_real(n, d) && !std::isfinite(d)) {
        fail(n.mark, path, "must be a finite number, got " + excerpt(n.scalar));
    } else if (!n.is_scalar() || !parse_qnumber(n.scalar, v)) {
        fail(n.mark, path,
             "cannot read " + n.describe() +
                 " as a number or q-system number (write 0.7, 0.5+0.5q or [0.5, 0.5])");
    }
    if (!std::isfinite(v.x) || !std::isfinite(v.y)) fail(n.mark, path, "must be finite, got " + n.describe());
    return v;
}

// A range declared on a sequence (`seq(...).above(0).below(1)`) bounds real numbers: a ranged
// coefficient is a real one in every number system, for a + qb (or a + bi) with b != 0 has no
// order to compare with the bounds. Each value is checked where it is written. (A bare pair
// [x, y] is checked as the two reals it is over the reals; in a q-system it is the one number
// x + qy, which SchemeBase refuses for a ranged coefficient: fixpoint/scheme.hpp.)
Vec2 ranged_value(const ParamSpec& s, Vec2 v, const CNode& n, const std::string& path) {
    if (!std::isfinite(s.lo) && !std::isfinite(s.hi)) return v;
    const std::string got = n.is_scalar() ? excerpt(n.scalar) : n.describe();
    if (v.y != 0)
        fail(n.mark, path,
             "must be a real number " + range_text(s) +
                 " (a coefficient with a declared range is real in every number system), got " + got);
    const bool below = s.lo_open ? !(v.x > s.lo) : !(v.x >= s.lo);
    const bool above = s.hi_open ? !(v.x < s.hi) : !(v.x <= s.hi);
    if ((std::isfinite(s.lo) && below) || (std::isfinite(s.hi) && above))
        fail(n.mark, path, "must be " + range_text(s) + ", got " + got);
    return v;
}

Sequence sequence_value(const ParamSpec& s, const CNode& n, const std::string& path) {
    Sequence seq;
    if (!n.is_seq()) {
        seq.values.push_back(ranged_value(s, qnumber_value(n, path), n, path));
        return seq;
    }
    if (n.items.empty()) fail(n.mark, path, "a periodic list must not be empty");
    double a, b;
    if (n.items.size() == 2 && parse_real(n.items[0], a) && parse_real(n.items[1], b)) {
        seq.bare_pair = true;
        if (!std::isfinite(a) || !std::isfinite(b)) fail(n.mark, path, "must be finite, got " + n.describe());
        seq.values = {ranged_value(s, Vec2{a, 0}, n.items[0], path + "[0]"),
                      ranged_value(s, Vec2{b, 0}, n.items[1], path + "[1]")};
        return seq;
    }
    for (std::size_t i = 0; i < n.items.size(); ++i) {
        const std::string ip = path + "[" + std::to_string(i) + "]";
        seq.values.push_back(ranged_value(s, qnumber_value(n.items[i], ip), n.items[i], ip));
    }
    return seq;
}

std::vector<TParam> validate_params(const Registry& reg, const ParamSpec* specs, std::size_t n_specs,
                                    const CNode& node, const std::string& path, const std::string& owner,
                                    const std::vector<std::string>& ignore) {
    // Unknown keys first: a typo is the likeliest mistake.
    for (std::size_t i = 0; i < node.keys.size(); ++i) {
        const std::string& k = node.keys[i].first;
        bool known = std::find(ignore.begin(), ignore.end(), k) != ignore.end();
        for (std::size_t j = 0; j < n_specs && !known; ++j) known = k == specs[j].name;
        if (known) continue;
        // The keys of a list item that stand beside the plugin's (a map's weight and colour)
        // are candidates too: a typo in them is not the plugin's.
        std::vector<std::string> names, item;
        for (std::size_t j = 0; j < n_specs; ++j) names.emplace_back(specs[j].name);
        for (const auto& x : ignore)
            if (x != "type") item.push_back(x);
        names.insert(names.end(), item.begin(), item.end());
        const auto near = suggest(k, names);
        const std::string did = near.empty() ? "" : " (did you mean " + quoted_list(near) + "?)";
        if (item.empty())
            fail(node.key_marks[i], path, "unknown parameter " + quote(k) + " for " + owner + did);
        fail(node.key_marks[i], path,
             "unknown key " + quote(k) + ": not a parameter of " + owner + " nor a key of the item (" +
                 join(item, ", ") + ")" + did);
    }
    std::vector<TParam> out;
    for (std::size_t j = 0; j < n_specs; ++j) {
        const ParamSpec& s = specs[j];
        const std::string p = path.empty() ? s.name : path + "." + s.name;
        const CNode* v = node.find(s.name);
        // An optional parameter without a default written as null (`filter: null`, `--set
        // renderer.filter=null`) is unset, so that a config's choice can be taken back.
        // (Not a colour whose '#' began a comment: that one's hint is given below.)
        if (v && v->type == CNode::Type::Null && !v->hex_comment && s.optional && !s.default_yaml) continue;
        if (v) {
            out.push_back(validate_param(reg, s, *v, p));
        } else if (s.default_yaml) {
            CNode d = parse_yaml(s.default_yaml, std::string("<default of ") + owner + "." + s.name + ">");
            TParam t = validate_param(reg, s, d, p);
            t.mark = node.mark; // a bad default is reported where the owner stands
            out.push_back(std::move(t));
        } else if (!s.optional) {
            fail(node.mark, path, "missing required parameter '" + std::string(s.name) + "' for " + owner);
        }
    }
    return out;
}

TParam validate_param(const Registry& reg, const ParamSpec& s, const CNode& n, const std::string& path) {
    TParam t;
    t.spec = &s;
    t.mark = n.mark;
    t.path = path;
    switch (s.type) {
    case ParamType::Bool:
        if (!n.is_scalar() || n.quoted || (n.scalar != "true" && n.scalar != "false"))
            fail(n.mark, path, "expected true or false, got " + n.describe());
        t.value = n.scalar == "true";
        break;
    case ParamType::Int: {
        std::int64_t v;
        if (!parse_int(n, v)) {
            double d;
            if (parse_real(n, d) && !std::isfinite(d))
                fail(n.mark, path, "must be a finite number, got " + excerpt(n.scalar));
            fail(n.mark, path, "expected an integer, got " + n.describe());
        }
        check_number(s, double(v), n, path);
        t.value = v;
        break;
    }
    case ParamType::Real: t.value = real_value(s, n, path); break;
    case ParamType::String: {
        if (!n.is_scalar()) fail(n.mark, path, "expected a string, got " + n.describe());
        // ("\0" in a quoted YAML string): a file name would end there, silently another file.
        if (n.scalar.find('\0') != std::string::npos)
            fail(n.mark, path,
                 "the text holds a NUL character (\\0), which no name or text of a plugin takes: " +
                     quote(n.scalar, 80));
        if (s.choices) {
            std::vector<std::string> options;
            std::string all = s.choices;
            for (std::size_t a = 0;;) {
                const auto b = all.find('|', a);
                options.push_back(all.substr(a, b == std::string::npos ? b : b - a));
                if (b == std::string::npos) break;
                a = b + 1;
            }
            if (std::find(options.begin(), options.end(), n.scalar) == options.end())
                fail(n.mark, path, "must be one of " + quoted_list(options) + ", got " + quote(n.scalar));
        }
        // (The plugin gets the path from the working folder, which its messages show; the
        // recipe records it absolute: value_node.)
        t.value = s.role == ParamRole::file && !is_builtin_file(s, n.scalar)
                      ? file_from_config(n.scalar, n.mark)
                      : n.scalar;
        break;
    }
    case ParamType::Vec2: t.value = vec2_value(s, n, path); break;
    case ParamType::Colour: t.value = colour_value(n, path); break;
    case ParamType::Reals:
        t.value =
            list_value<double>(s, n, path, "numbers", [](const auto&... a) { return real_value(a...); });
        break;
    case ParamType::Vec2s:
        t.value = list_value<Vec2>(s, n, path, "points", [](const auto&... a) { return vec2_value(a...); });
        break;
    case ParamType::Sequence: t.value = sequence_value(s, n, path); break;
    case ParamType::Object: t.object = validate(reg, s.kind, n, path); break;
    case ParamType::Objects: {
        check_count(s, n, path, (std::string(kind_name(s.kind)) + "s").c_str());
        for (std::size_t i = 0; i < n.items.size(); ++i) {
            const std::string ip = path + "[" + std::to_string(i) + "]";
            TParam::Item item;
            std::vector<std::string> extra_keys;
            for (std::uint32_t j = 0; j < s.n_item_params; ++j)
                extra_keys.emplace_back(s.item_params[j].name);
            item.object = validate(reg, s.kind, n.items[i], ip, extra_keys);
            std::vector<std::string> own = {"type"};
            for (std::uint32_t j = 0; j < item.object->plugin->desc->n_params; ++j)
                own.emplace_back(item.object->plugin->desc->params[j].name);
            // Extras (weight, colour, ...) stand beside the object's own keys.
            item.extras = validate_params(reg, s.item_params, s.n_item_params, n.items[i], ip,
                                          std::string("an item of ") + s.name, own);
            t.items.push_back(std::move(item));
        }
        break;
    }
    }
    return t;
}

} // namespace

std::string format_real(double v) {
    if (std::isnan(v)) return ".nan";
    if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
    char buf[64];
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, p);
}

std::string declared_range(const ParamSpec& s) {
    const bool lo = std::isfinite(s.lo), hi = std::isfinite(s.hi);
    std::string r = s.lo_open || !lo ? "(" : "[";
    r += lo ? format_real(s.lo) : "-inf";
    r += ", ";
    r += hi ? format_real(s.hi) : "inf";
    r += s.hi_open || !hi ? ")" : "]";
    return r;
}

std::string format_float(float v) {
    char buf[64];
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, p);
}

std::unique_ptr<TObject> validate(const Registry& reg, Kind kind, const CNode& node, const std::string& path,
                                  const std::vector<std::string>& extra_keys) {
    const std::string kn(kind_name(kind));
    if (!node.is_map())
        fail(node.mark, path,
             "expected " + article(kn) + " (a mapping with a 'type:' key), got " + node.describe());
    const CNode* type = node.find("type");
    if (!type) {
        std::vector<std::string> names;
        for (const auto* e : reg.all(kind)) names.emplace_back(e->desc->name);
        fail(node.mark, path,
             "missing 'type:' for " + article(kn) +
                 (names.empty() ? "" : " (one of " + join(names, ", ") + ")"));
    }
    if (!type->is_scalar())
        fail(type->mark, path + ".type", "expected a plugin name, got " + type->describe());
    const PluginEntry* e = reg.find(type->scalar);
    // A plugin file in a folder that did not load, which would have provided this name (or a
    // second plugin of the name: which one is meant is not known).
    if (const RefusedPlugin* r = reg.refused_for(type->scalar))
        fail(type->mark, path + ".type", "plugin " + quote(type->scalar) + " is not available: " + r->reason);
    if (!e) {
        const auto near = reg.closest(type->scalar, kind);
        fail(type->mark, path + ".type",
             "unknown " + kn + " " + quote(type->scalar) +
                 (near.empty() ? "" : " (did you mean " + quoted_list(near) + "?)"));
    }
    if (e->desc->kind != kind)
        fail(type->mark, path + ".type",
             quote(type->scalar) + " is " + article(kind_name(e->desc->kind)) + ", but this slot expects " +
                 article(kn));
    // Code in a recipe read from an image: the image may come from anywhere, and rendering it
    // must not run what it carries. (A --set on such a node does not launder the rest of it.)
    if (e->desc->runs_code) {
        bool refused = node.mark.refuse_code || type->mark.refuse_code;
        for (const auto& [k, v] : node.keys) refused = refused || v.mark.refuse_code;
        if (refused)
            fail(type->mark, path,
                 quote(type->scalar) +
                     " runs the code it carries, and this config is the recipe of an image: fixpoint runs "
                     "code from an image only with --allow-python (read the recipe first: fixpoint recipe " +
                     (type->mark.source ? *type->mark.source : std::string("IMAGE")) + ")");
    }
    auto t = std::make_unique<TObject>();
    t->plugin = e;
    t->mark = node.mark;
    t->path = path;
    std::vector<std::string> ignore = extra_keys;
    ignore.emplace_back("type");
    t->params = validate_params(reg, e->desc->params, e->desc->n_params, node, path, e->desc->name, ignore);
    return t;
}

namespace {

ParamBag bag_of(const Registry& reg, const ParamSpec* specs, std::size_t n, const std::string& owner,
                const std::vector<TParam>& params);

void fill(const Registry& reg, ParamBag& bag, const TParam& p) {
    switch (p.spec->type) {
    case ParamType::Object: bag.set(p.spec->name, build(reg, *p.object)); break;
    case ParamType::Objects: {
        std::vector<ObjectItem> items;
        for (const auto& it : p.items) {
            auto extras =
                std::make_shared<ParamBag>(bag_of(reg, p.spec->item_params, p.spec->n_item_params,
                                                  std::string("an item of ") + p.spec->name, it.extras));
            items.push_back({build(reg, *it.object), extras});
        }
        bag.set(p.spec->name, std::move(items));
        break;
    }
    default: bag.set(p.spec->name, p.value);
    }
}

ParamBag bag_of(const Registry& reg, const ParamSpec* specs, std::size_t n, const std::string& owner,
                const std::vector<TParam>& params) {
    ParamBag bag(specs, n, owner);
    for (const auto& p : params) fill(reg, bag, p);
    return bag;
}

const TParam* param_named(const std::vector<TParam>& ps, const std::string& name) {
    for (const auto& p : ps)
        if (name == p.spec->name) return &p;
    return nullptr;
}

} // namespace

std::shared_ptr<const Object> build_from_text(const Registry& reg, Kind kind, const std::string& text,
                                              const std::string& source, const std::string& path) {
    return build(reg, *validate(reg, kind, parse_yaml(text, source), path));
}

std::shared_ptr<const Object> build(const Registry& reg, const TObject& t) {
    const PluginDescriptor& d = *t.plugin->desc;
    ParamBag bag = bag_of(reg, d.params, d.n_params, d.name, t.params);
    std::shared_ptr<const Object> obj;
    try {
        obj = reg.create(*t.plugin, bag);
    } catch (const ParamError& e) {
        // Item extras are read through their own bags: search those too.
        if (const TParam* p = param_named(t.params, e.param())) fail(p->mark, p->path, e.what());
        fail(t.mark, t.path, e.what());
    } catch (const InternalError&) {
        throw;
    } catch (const Cancelled&) {
        throw;
    } catch (const InputError& e) {
        fail(t.mark, t.path, e.what());
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw InternalError(t.path + ": plugin '" + d.name + "' failed: " + e.what());
    } catch (...) {
        throw InternalError(t.path + ": plugin '" + d.name +
                            "' failed with an exception that is not a std::exception");
    }
    auto unread = bag.unread();
    for (const auto& p : t.params) {
        if (p.spec->type != ParamType::Objects) continue;
        for (const auto& it : bag.objects(p.spec->name))
            if (it.extras)
                for (const auto& u : it.extras->unread())
                    unread.push_back(std::string(p.spec->name) + "[]." + u);
    }
    if (!unread.empty())
        throw InternalError("plugin '" + std::string(d.name) + "' (" + t.plugin->file.string() +
                            ") declares parameter '" + unread.front() + "' but never reads it");
    return obj;
}

namespace {

CNode value_node(const TParam& p, bool skip_finish);

// skip_finish: without the parameters whose role is finish, at every depth (a histogram's
// identity).
CNode object_node(const TObject& t, const std::vector<TParam>* extras, bool skip_finish) {
    CNode m = map_node();
    m.keys.emplace_back("type", scalar_node(t.plugin->desc->name));
    for (const auto& p : t.params)
        if (!skip_finish || p.spec->role != ParamRole::finish)
            m.keys.emplace_back(p.spec->name, value_node(p, skip_finish));
    if (extras)
        for (const auto& p : *extras)
            if (!skip_finish || p.spec->role != ParamRole::finish)
                m.keys.emplace_back(p.spec->name, value_node(p, skip_finish));
    m.key_marks.resize(m.keys.size());
    return m;
}

CNode value_node(const TParam& p, bool skip_finish) {
    // A file a plugin reads, in the recipe: absolute, so that the recipe rendered again from its
    // image, from any folder, reads the same file (file_from_config).
    if (const auto* file = std::get_if<std::string>(&p.value);
        file && p.spec->role == ParamRole::file && !file->empty() && !is_builtin_file(*p.spec, *file))
        return scalar_node(std::filesystem::absolute(*file).lexically_normal().string(), true);
    struct V {
        CNode operator()(bool b) const { return scalar_node(b ? "true" : "false"); }
        CNode operator()(std::int64_t i) const { return scalar_node(std::to_string(i)); }
        CNode operator()(double d) const { return scalar_node(format_real(d)); }
        CNode operator()(const std::string& s) const { return scalar_node(s, true); }
        CNode operator()(Vec2 v) const {
            CNode s = seq_node();
            s.items = {scalar_node(format_real(v.x)), scalar_node(format_real(v.y))};
            return s;
        }
        CNode operator()(Rgb c) const {
            CNode s = seq_node();
            s.items = {scalar_node(format_float(c.r)), scalar_node(format_float(c.g)),
                       scalar_node(format_float(c.b))};
            return s;
        }
        CNode operator()(const std::vector<double>& v) const {
            CNode s = seq_node();
            for (double d : v) s.items.push_back(scalar_node(format_real(d)));
            return s;
        }
        CNode operator()(const std::vector<Vec2>& v) const {
            CNode s = seq_node();
            for (Vec2 q : v) s.items.push_back((*this)(q));
            return s;
        }
        static CNode qnumber(Vec2 v) {
            if (v.y == 0) return scalar_node(format_real(v.x));
            std::string im = format_real(v.y);
            if (im[0] != '-') im = "+" + im;
            return scalar_node(format_real(v.x) + im + "q");
        }
        CNode operator()(const Sequence& q) const {
            if (q.values.size() == 1 && !q.bare_pair) return qnumber(q.values[0]);
            CNode s = seq_node();
            // Two plain numbers would read back as a bare pair (one q-number in a q-system):
            // a periodic list of two is written with its elements as pairs [a, b].
            const bool as_pairs = !q.bare_pair && q.values.size() == 2;
            for (Vec2 v : q.values) {
                if (!as_pairs) {
                    s.items.push_back(qnumber(v));
                    continue;
                }
                CNode pair = seq_node();
                pair.items = {scalar_node(format_real(v.x)), scalar_node(format_real(v.y))};
                s.items.push_back(std::move(pair));
            }
            return s;
        }
        CNode operator()(const std::shared_ptr<const Object>&) const { return {}; }
        CNode operator()(const std::vector<ObjectItem>&) const { return {}; }
    };
    if (p.spec->type == ParamType::Object) return object_node(*p.object, nullptr, skip_finish);
    if (p.spec->type == ParamType::Objects) {
        CNode s = seq_node();
        for (const auto& it : p.items) s.items.push_back(object_node(*it.object, &it.extras, skip_finish));
        return s;
    }
    return std::visit(V{}, p.value);
}

} // namespace

bool is_builtin_file(const ParamSpec& s, const std::string& value) {
    if (!s.builtins) return false;
    const std::string_view all(s.builtins);
    for (std::size_t a = 0; a <= all.size();) {
        const std::size_t b = std::min(all.find('|', a), all.size());
        if (all.substr(a, b - a) == value) return true;
        a = b + 1;
    }
    return false;
}

std::string file_from_config(const std::string& value, const Mark& at) {
    const std::filesystem::path file(value);
    if (file.is_absolute() || !at.source) return value;
    const std::string& source = *at.source;
    // "<text>", "<default of ...>": no file; "--set a=b", "--vary ...": the command line.
    if (source.empty() || source[0] == '<' || source.rfind("--", 0) == 0) return value;
    // The recipe of an image or a kept histogram: from the working folder, as recipes were
    // always read (one made since records the file absolute), so that an old recipe reads the
    // file it read before.
    if (is_recipe_image(source) || is_histogram_file(source)) return value;
    const std::filesystem::path folder = std::filesystem::path(source).parent_path();
    if (folder.empty()) return value;
    const std::filesystem::path joined = (folder / file).lexically_normal();
    // From the working folder where the file lies inside it (messages name it so), else as joined.
    std::error_code ec;
    const std::filesystem::path near = std::filesystem::proximate(joined, ec);
    return !ec && !near.empty() && *near.begin() != ".." ? near.string() : joined.string();
}

CNode resolved(const TObject& t, bool without_finish) { return object_node(t, nullptr, without_finish); }

} // namespace fp::host
