// `fixpoint explore`'s searched parameters (genes.hpp).
#include "genes.hpp"

#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/tools/measures.hpp>
#include <fixpoint/host/tools/symmetry.hpp>
#include <fixpoint/iteration.hpp>
#include <fixpoint/rng.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/transform.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>

namespace fp::host::explore_detail {

namespace {

/// Enough significant digits that a value is written to about a thousandth of its range.
int digits_for(double a, double b) {
    const double m = std::max({std::fabs(a), std::fabs(b), 1e-300});
    const double w = std::fabs(b - a);
    if (!(w > 0)) return 6;
    return std::clamp(int(std::ceil(std::log10(m / w))) + 4, 4, 15);
}

std::string real_text(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    std::string s = buf;
    if (s == "-0") s = "0";
    return s;
}

double reread(double v, int digits) { return std::strtod(real_text(v, digits).c_str(), nullptr); }

} // namespace

bool parse_double(std::string_view t, double& v) {
    while (!t.empty() && t.front() == ' ') t.remove_prefix(1);
    while (!t.empty() && t.back() == ' ') t.remove_suffix(1);
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return !t.empty() && ec == std::errc() && end == t.data() + t.size() && std::isfinite(v);
}

namespace {

bool parse_whole(std::string_view t, long long& v) {
    while (!t.empty() && t.front() == ' ') t.remove_prefix(1);
    while (!t.empty() && t.back() == ' ') t.remove_suffix(1);
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return !t.empty() && ec == std::errc() && end == t.data() + t.size();
}

/// a+bq, a-bq, bq, a (a q-number of paper 02).
bool parse_q(std::string t, Gene& g) {
    t.erase(std::remove(t.begin(), t.end(), ' '), t.end());
    if (t.empty()) return false;
    if (t.back() != 'q') {
        g[1] = 0;
        return parse_double(t, g[0]);
    }
    t.pop_back();
    std::size_t split = 0;
    for (std::size_t i = 1; i < t.size(); ++i)
        if ((t[i] == '+' || t[i] == '-') && t[i - 1] != 'e' && t[i - 1] != 'E') split = i;
    const std::string re = t.substr(0, split), im = t.substr(split);
    g[0] = 0;
    if (!re.empty() && !parse_double(re, g[0])) return false;
    if (im.empty() || im == "+")
        g[1] = 1;
    else if (im == "-")
        g[1] = -1;
    else if (!parse_double(im, g[1]))
        return false;
    return true;
}

bool inside(const ParamSpec& s, double v) {
    if (v < s.lo || (s.lo_open && v <= s.lo)) return false;
    if (v > s.hi || (s.hi_open && v >= s.hi)) return false;
    return true;
}

} // namespace

const TParam* param_of(const TObject& t, const std::string& name) {
    for (const auto& p : t.params)
        if (p.spec && name == p.spec->name) return &p;
    return nullptr;
}

std::string gene_text(const Dim& d, const Gene& g) {
    switch (d.kind) {
    case Dim::Kind::Real: return real_text(g[0], d.digits);
    case Dim::Kind::Int: return std::to_string(static_cast<long long>(g[0]));
    case Dim::Kind::QNum: {
        const std::string b = real_text(std::fabs(g[1]), d.digits);
        return real_text(g[0], d.digits) + (g[1] < 0 ? "-" : "+") + b + "q";
    }
    case Dim::Kind::Pair: return "[" + real_text(g[0], d.digits) + ", " + real_text(g[1], d.digits) + "]";
    case Dim::Kind::Choice: return d.choices[std::size_t(g[0])];
    }
    return "";
}

namespace {

/// Round to what is written, clamp into the range (nudging off an open end).
void settle(const Dim& d, Gene& g) {
    for (int c = 0; c < d.components(); ++c) {
        double v = std::clamp(g[c], d.lo[c], d.hi[c]);
        if (d.kind == Dim::Kind::Int || d.kind == Dim::Kind::Choice) {
            v = std::clamp(std::round(v), d.lo[c], d.hi[c]);
        } else {
            v = std::clamp(reread(v, d.digits), d.lo[c], d.hi[c]);
            const double eps = (d.hi[c] - d.lo[c]) * 1e-3;
            if (d.lo_open && v <= d.lo[c]) v = reread(d.lo[c] + eps, d.digits);
            if (d.hi_open && v >= d.hi[c]) v = reread(d.hi[c] - eps, d.digits);
        }
        g[c] = v;
    }
}

} // namespace

Gene draw(const Dim& d, Rng& r) {
    Gene g{};
    switch (d.kind) {
    case Dim::Kind::Real:
    case Dim::Kind::QNum:
    case Dim::Kind::Pair:
        for (int c = 0; c < 2; ++c) g[c] = d.lo[c] + (d.hi[c] - d.lo[c]) * uniform_double(r);
        break;
    case Dim::Kind::Int:
    case Dim::Kind::Choice:
        g[0] = d.lo[0] + double(uniform_below(r, std::uint32_t(d.hi[0] - d.lo[0] + 1)));
        break;
    }
    settle(d, g);
    return g;
}

namespace {

double gaussian(Rng& r) {
    const double u1 = std::max(uniform_double(r), 0x1.0p-53), u2 = uniform_double(r);
    return std::sqrt(-2 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

} // namespace

void mutate(const Dim& d, Gene& g, Rng& r) {
    if (d.kind == Dim::Kind::Choice) {
        g = draw(d, r);
        return;
    }
    for (int c = 0; c < d.components(); ++c) {
        const double sigma = 0.1 * (d.hi[c] - d.lo[c]);
        g[c] += (d.kind == Dim::Kind::Int ? std::max(sigma, 0.5) : sigma) * gaussian(r);
    }
    settle(d, g);
}

namespace {

std::vector<std::string> split_choices(const std::string& t) {
    std::vector<std::string> out;
    std::size_t a = 0;
    for (;;) {
        const auto b = t.find('|', a);
        std::string c = t.substr(a, b == std::string::npos ? b : b - a);
        const auto f = c.find_first_not_of(' ');
        c = f == std::string::npos ? "" : c.substr(f, c.find_last_not_of(' ') - f + 1);
        out.push_back(c);
        if (b == std::string::npos) break;
        a = b + 1;
    }
    return out;
}

std::vector<std::string> keys_of(const std::map<std::string, const TParam*>& m) {
    std::vector<std::string> k;
    for (const auto& [p, _] : m) k.push_back(p);
    return k;
}

} // namespace

Dim parse_param(const Registry& reg, const CNode& base, const Index& idx, const std::string& spec,
                const std::string& config) {
    const std::string shown = excerpt("--param " + spec, 100);
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0)
        throw InputError(shown + ": expected PATH=A..B, PATH=a+bq..c+dq or PATH=a|b|c");
    Dim d;
    d.path = spec.substr(0, eq);
    const std::string range = spec.substr(eq + 1);
    const auto it = idx.params.find(d.path);
    if (it == idx.params.end()) {
        const auto near = suggest(d.path, keys_of(idx.params));
        throw InputError(shown + ": " + quote(config, 200) + " has no parameter " + quote(d.path, 100) +
                         (near.empty() ? "" : " (did you mean '" + near[0] + "'?)"));
    }
    const ParamSpec& s = *it->second->spec;
    if (range.find('|') != std::string::npos) {
        d.kind = Dim::Kind::Choice;
        d.choices = split_choices(range);
        for (const auto& c : d.choices) {
            if (c.empty()) throw InputError(shown + ": an empty choice");
            CNode root = base;
            try {
                apply_override(root, d.path + "=" + c, "--param");
                validate(reg, Kind::Renderer, *root.find("renderer"), "renderer");
            } catch (const InputError& e) {
                throw InputError(shown + ": the choice " + quote(c, 60) + " is refused: " + e.what());
            }
        }
        d.lo = {0, 0};
        d.hi = {double(d.choices.size() - 1), 0};
        return d;
    }
    const auto dots = range.find("..");
    if (dots == std::string::npos)
        throw InputError(shown + ": expected a range A..B (or a+bq..c+dq, or choices a|b|c)");
    const std::string a = range.substr(0, dots), b = range.substr(dots + 2);
    const std::string type(param_type_name(s.type));
    switch (s.type) {
    case ParamType::Int: {
        long long x = 0, y = 0;
        if (!parse_whole(a, x) || !parse_whole(b, y) || x >= y)
            throw InputError(shown + ": " + quote(d.path, 100) +
                             " is an integer parameter: expected whole numbers A..B with A < B");
        if (y - x > 1000000) throw InputError(shown + ": at most 1000000 integer values");
        if (!inside(s, double(x)) || !inside(s, double(y)))
            throw InputError(shown + ": the range leaves the parameter's declared range " +
                             declared_range(s));
        d.kind = Dim::Kind::Int;
        d.lo = {double(x), 0};
        d.hi = {double(y), 0};
        return d;
    }
    case ParamType::Real:
    case ParamType::Sequence: {
        const bool q = s.type == ParamType::Sequence &&
                       (a.find('q') != std::string::npos || b.find('q') != std::string::npos);
        Gene x{}, y{};
        if (q) {
            if (!parse_q(a, x) || !parse_q(b, y) || x[0] > y[0] || x[1] > y[1] || x == y)
                throw InputError(shown + ": expected q-numbers a+bq..c+dq with a <= c, b <= d, not equal");
            d.kind = Dim::Kind::QNum;
            d.digits = std::max(digits_for(x[0], y[0]), digits_for(x[1], y[1]));
        } else {
            if (!parse_double(a, x[0]) || !parse_double(b, y[0]) || !(x[0] < y[0]))
                throw InputError(shown + ": expected finite numbers A..B with A < B");
            if (s.type == ParamType::Real && (!inside(s, x[0]) || !inside(s, y[0])) &&
                !(s.lo_open && x[0] == s.lo && inside(s, y[0])) &&
                !(s.hi_open && y[0] == s.hi && inside(s, x[0])))
                throw InputError(shown + ": the range leaves the parameter's declared range " +
                                 declared_range(s));
            d.kind = Dim::Kind::Real;
            d.digits = digits_for(x[0], y[0]);
            d.lo_open = s.lo_open && x[0] == s.lo;
            d.hi_open = s.hi_open && y[0] == s.hi;
        }
        d.lo = x;
        d.hi = y;
        return d;
    }
    default:
        throw InputError(shown + ": " + quote(d.path, 100) + " is a " + type +
                         " parameter: a range A..B takes a real, integer or sequence parameter (give choices "
                         "a|b|c instead)");
    }
}

std::vector<Dim> random_dims(const Index& idx, const std::string& path, const std::string& config,
                             const std::set<std::string>& taken) {
    const std::string shown = excerpt("--random " + path, 100);
    const auto it = idx.objects.find(path);
    if (it == idx.objects.end()) {
        std::vector<std::string> names;
        for (const auto& [p, _] : idx.objects) names.push_back(p);
        const auto near = suggest(path, names);
        throw InputError(shown + ": " + quote(config, 200) + " has no plugin at " + quote(path, 100) +
                         (near.empty() ? "" : " (did you mean '" + near[0] + "'?)"));
    }
    // The size and quality of a render are not searched (the finishing stage's settings among
    // them: they change how the pattern is shown, not the pattern).
    static const std::set<std::string> render_size = {"width",
                                                      "height",
                                                      "points",
                                                      "chains",
                                                      "skip",
                                                      "seed",
                                                      "samples",
                                                      "max_iterations",
                                                      "points_per_buffer",
                                                      "supersample",
                                                      "estimator_radius",
                                                      "estimator_minimum",
                                                      "estimator_curve"};
    const bool renderer = it->second->plugin->desc->kind == Kind::Renderer;
    std::vector<Dim> out;
    for (const auto& p : it->second->params) {
        const ParamSpec& s = *p.spec;
        if (taken.count(p.path) || (renderer && render_size.count(s.name))) continue;
        Dim d;
        d.path = p.path;
        // Around the config's value v when the declared range has an infinite end: v +- |v| / 2
        // (+- 0.5 around 0), within the declared range.
        auto around = [&](double v, int c) {
            const double half = v != 0 ? std::fabs(v) / 2 : 0.5;
            d.lo[c] = v - half;
            d.hi[c] = v + half;
        };
        auto within = [&] {
            if (d.lo[0] <= s.lo) d.lo[0] = s.lo, d.lo_open = s.lo_open;
            if (d.hi[0] >= s.hi) d.hi[0] = s.hi, d.hi_open = s.hi_open;
        };
        const bool bounded = std::isfinite(s.lo) && std::isfinite(s.hi);
        if (s.type == ParamType::Real) {
            d.kind = Dim::Kind::Real;
            if (bounded)
                d.lo = {s.lo, 0}, d.hi = {s.hi, 0}, d.lo_open = s.lo_open, d.hi_open = s.hi_open;
            else
                around(std::get<double>(p.value), 0), within();
            d.digits = digits_for(d.lo[0], d.hi[0]);
        } else if (s.type == ParamType::Int) {
            d.kind = Dim::Kind::Int;
            if (bounded && s.hi - s.lo <= 63) {
                d.lo = {s.lo, 0}, d.hi = {s.hi, 0};
            } else {
                const double v = double(std::get<std::int64_t>(p.value));
                const double half = std::max(1.0, std::round(std::fabs(v) / 2));
                d.lo = {std::max(v - half, s.lo_open ? s.lo + 1 : s.lo), 0};
                d.hi = {std::min(v + half, s.hi_open ? s.hi - 1 : s.hi), 0};
                d.lo[0] = std::ceil(d.lo[0]), d.hi[0] = std::floor(d.hi[0]);
            }
        } else if (s.type == ParamType::Sequence) {
            // A constant: a real, or a q-number (componentwise); a vector [a, b] (each component
            // around its value, within the declared range); periodic lists are left alone.
            const auto& seq = std::get<Sequence>(p.value);
            if (seq.bare_pair && seq.values.size() == 2) {
                d.kind = Dim::Kind::Pair;
                for (int c = 0; c < 2; ++c) {
                    around(seq.values[std::size_t(c)].x, c);
                    d.lo[c] = std::max(d.lo[c], s.lo), d.hi[c] = std::min(d.hi[c], s.hi);
                }
                d.lo_open = s.lo_open && d.lo[0] == s.lo, d.hi_open = s.hi_open && d.hi[0] == s.hi;
                d.digits = std::max(digits_for(d.lo[0], d.hi[0]), digits_for(d.lo[1], d.hi[1]));
                if (d.lo[0] < d.hi[0] && d.lo[1] < d.hi[1]) out.push_back(d);
                continue;
            }
            if (seq.values.size() != 1 || seq.bare_pair) continue;
            const Vec2 v = seq.values[0];
            d.kind = v.y != 0 ? Dim::Kind::QNum : Dim::Kind::Real;
            around(v.x, 0);
            if (v.y != 0) around(v.y, 1);
            d.digits = std::max(digits_for(d.lo[0], d.hi[0]),
                                d.kind == Dim::Kind::QNum ? digits_for(d.lo[1], d.hi[1]) : 0);
        } else {
            continue;
        }
        if (!(d.lo[0] < d.hi[0])) continue;
        out.push_back(d);
    }
    if (out.empty())
        throw InputError(shown + ": " + std::string(it->second->plugin->desc->name) +
                         " has no real, integer or constant sequence parameter to search");
    return out;
}

} // namespace fp::host::explore_detail
