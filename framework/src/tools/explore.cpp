// `fixpoint explore CONFIG`: a seeded search for good parameters (issue 17, item 1).
//
// Design.
// - The searched parameters are named with ranges: `--param PATH=A..B` (a real parameter,
//   uniform; an integer parameter with whole A and B, uniform over A..B), `--param
//   PATH=a+bq..c+dq` (a sequence parameter such as an iteration's alpha, as a q-number drawn
//   componentwise; a plain A..B on a sequence draws a real), `--param 'PATH=a|b|c'` (choices, any
//   parameter: each choice is YAML text, checked against the config before the search), or
//   `--random PLUGIN-PATH` (every real, integer and constant sequence parameter of that
//   plugin: over its declared range when both ends are finite and, for an integer, it holds
//   at most 64 values; else over v +- |v|/2, or +- 0.5 around 0, for the config's value v,
//   within the declared range: the plugins declare few two-ended ranges). PATH is
//   the path of `--set` (renderer.maps[0].shape.radius); the parameter may be one the config
//   leaves at its default. A path that is not a parameter, a bad range, a range outside the
//   declared one or a parameter kind a range does not fit is one line of error (exit 2).
// - Each candidate is the config with --set and then its values applied, validated like any
//   config (a candidate the validator refuses is counted as invalid and not ranked). Every
//   candidate of a phase is validated before any of them is rendered. It is rendered as a
//   draft: its larger side --draft-size pixels (the aspect kept), at most --draft-points points
//   (renderers with `points`), one sample per pixel (renderers with `samples`).
// - Measures (measures.hpp; each mapped to a score in [0, 1]): coverage, grey-level entropy and
//   box-counting dimension of the draft, and the largest Lyapunov exponent of the map for the
//   chaos-game renderer (Gumowski–Mira maps, inversions, affine IFS; absent for other renderers,
//   and its weight then ignored). The total is the weighted mean of the scores of the measures
//   present (--weights, default coverage=1,entropy=1,dimension=2,lyapunov=1,symmetry=0). The
//   symmetry measure is `fixpoint symmetry`'s (symmetry.hpp): the best score of a rotation or
//   mirror about the origin, computed only when weighted. Adding a measure is one entry of
//   measure_table().
// - Search: --candidates N drawn at random, candidate i from fp::chain_stream(seed, i); then
//   --generations G, each of N children of the best K so far (two parents drawn from them,
//   uniform crossover of the values, each value mutated with probability 1/2 by a Gaussian step
//   of a tenth of its range, clamped, integers rounded; choices redrawn), child i of generation
//   g from chain_stream(seed, 2^32 g + i). A child equal to a candidate already scored is not
//   scored again. The best K distinct candidates of all generations are kept (elitism). Drafts
//   are rendered by --threads worker threads, one candidate per thread at a time, each renderer
//   run serially: the scores (and so the ranking and every file) do not depend on the thread
//   count.
// - Output (-o DIR, created if missing): best-1.yaml ... best-K.yaml (the config with --set and
//   the values applied, the scores in a comment), best-k.png (the full render, with its recipe),
//   sheet.png (a ranked contact sheet, captions: rank, score, values) and candidates.tsv (every
//   candidate: rank, scores, values, or why it was refused). An existing file among them is
//   replaced only with --force.
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/host/tools/explore.hpp>
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
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

namespace fs = std::filesystem;

namespace fp::host {

const char* const explore_help = R"(Ranges (--param PATH=RANGE, PATH as in --set):
  A..B         a real parameter: uniform in [A, B]; an integer parameter: whole A..B
  a+bq..c+dq   a sequence parameter (an iteration's alpha): a q-number, componentwise
  'a|b|c'      choices, for any parameter (each a YAML value)
  --random P   every real, integer and constant sequence parameter of the plugin at path P
               (renderer.iteration, renderer.maps[0].shape): over its declared range when
               both ends are finite (integers: at most 64 values), else over v +- |v|/2 (+- 0.5
               around 0) for the config's value v, within the declared range; a renderer's
               size and quality (width, height, points, chains, samples, ...) are kept
Measures, each scored in [0, 1] on a draft (--draft-size, --draft-points):
  coverage   fraction of pixels not of the background; score: 0 at <= 0.2% (dust), rising
             log-linearly to 1 at 2%, 1 up to 60%, falling linearly to 0 at 100% (a blob)
  entropy    entropy of the grey-level histogram in bits (0..8); score: bits / 6, at most 1
  dimension  box-counting dimension of the lit pixels (least-squares slope over boxes of 2 to
             64 pixels, at most a quarter of the lit extent); score: 1 in [1.3, 1.8], linear
             to 0 at 0.5 and at 2 (a filled blob measures 1.9 to 2)
  lyapunov   largest Lyapunov exponent of the map (chaos-game only: finite differences along
             32 orbits of the maps drawn by weight, through the iteration scheme); score:
             1 / (1 + exp(-L / 0.05)), chaos near 1, regular orbits 0.5; absent for other
             renderers, and its weight ignored
  symmetry   the best symmetry about the origin: the highest score of `fixpoint symmetry`
             (fraction of pixels that agree) over the rotations by 180, 90, 120, 60 degrees
             and the mirrors in the axes and the diagonal; score: 0 at 0.5, linear to 1 at 1;
             weight 0 by default (the background agrees with itself: on a sparse picture
             everything scores high, so weight it beside coverage); absent with fit_view
  The score of a candidate is the weighted mean over the measures present (--weights).
Search: --candidates random ones (candidate i from chain_stream(seed, i)), then --generations
  of as many children of the best --keep (uniform crossover, Gaussian mutation of a tenth of
  the range, elitism). The same seed gives the same files on any number of threads.
Writes to -o DIR: best-1.yaml ... (the configs, their scores in a comment), best-k.png (full
  renders), sheet.png (ranked contact sheet) and candidates.tsv (every candidate's scores).
)";

namespace {

// ---- the searched parameters ------------------------------------------------------------

struct Dim {
    enum class Kind { Real, Int, QNum, Choice } kind = Kind::Real;
    std::string path;
    std::array<double, 2> lo{}, hi{};
    std::vector<std::string> choices;
    bool lo_open = false, hi_open = false;
    int digits = 4; ///< significant digits written for reals
};

using Gene = std::array<double, 2>;

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

bool parse_double(std::string_view t, double& v) {
    while (!t.empty() && t.front() == ' ') t.remove_prefix(1);
    while (!t.empty() && t.back() == ' ') t.remove_suffix(1);
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return !t.empty() && ec == std::errc() && end == t.data() + t.size() && std::isfinite(v);
}

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

/// The validated tree's parameters and plugin instances by path.
struct Index {
    std::map<std::string, const TParam*> params;
    std::map<std::string, const TObject*> objects;
    void add(const TObject& t) {
        objects[t.path] = &t;
        for (const auto& p : t.params) {
            params[p.path] = &p;
            if (p.object) add(*p.object);
            for (const auto& it : p.items) {
                add(*it.object);
                for (const auto& e : it.extras) params[e.path] = &e;
            }
        }
    }
};

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
    case Dim::Kind::Choice: return d.choices[std::size_t(g[0])];
    }
    return "";
}

/// Round to what is written, clamp into the range (nudging off an open end).
void settle(const Dim& d, Gene& g) {
    for (int c = 0; c < (d.kind == Dim::Kind::QNum ? 2 : 1); ++c) {
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

Gene draw(const Dim& d, Rng& r) {
    Gene g{};
    switch (d.kind) {
    case Dim::Kind::Real:
    case Dim::Kind::QNum:
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

double gaussian(Rng& r) {
    const double u1 = std::max(uniform_double(r), 0x1.0p-53), u2 = uniform_double(r);
    return std::sqrt(-2 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

void mutate(const Dim& d, Gene& g, Rng& r) {
    if (d.kind == Dim::Kind::Choice) {
        g = draw(d, r);
        return;
    }
    for (int c = 0; c < (d.kind == Dim::Kind::QNum ? 2 : 1); ++c) {
        const double sigma = 0.1 * (d.hi[c] - d.lo[c]);
        g[c] += (d.kind == Dim::Kind::Int ? std::max(sigma, 0.5) : sigma) * gaussian(r);
    }
    settle(d, g);
}

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
    // The size and quality of a render are not searched.
    static const std::set<std::string> render_size = {"width",   "height",         "points",
                                                      "chains",  "skip",           "seed",
                                                      "samples", "max_iterations", "points_per_buffer"};
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
            // A constant: a real, or a q-number (componentwise); periodic lists are left alone.
            const auto& seq = std::get<Sequence>(p.value);
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

// ---- measures ----------------------------------------------------------------------------

struct Draft {
    const Image* image = nullptr;
    Rgb background;
    std::optional<double> lyapunov;
    const PixelFrame* frame = nullptr; ///< where the pixels stand in the plane; null: unknown
    bool symmetry = false;             ///< the symmetry measure is weighted (it costs a little)
};

/// The best symmetry about the origin: the highest score of `fixpoint symmetry` (symmetry.hpp:
/// the fraction of pixels whose colour agrees with the picture at g(p)) among the rotations by
/// 180, 90, 120 and 60 degrees and the mirrors in the axes and the diagonal. None when the frame
/// is unknown or no operation keeps enough of the picture to be measured.
std::optional<double> best_point_symmetry(const Draft& d) {
    if (!d.symmetry || !d.frame) return std::nullopt;
    static const std::set<std::string> point_ops = {"r2", "r4", "r3", "r6", "m(x,-y)", "m(-x,y)", "m(y,x)"};
    std::optional<double> best;
    for (const auto& op : symmetry_ops())
        if (point_ops.count(op.id)) {
            const OpScore sc = score_op(*d.image, *d.frame, op, SymmetryOptions{});
            if (sc.measured) best = std::max(best.value_or(0.0), sc.score);
        }
    return best;
}

struct MeasureDef {
    const char* name;
    double default_weight;
    std::optional<double> (*raw)(const Draft&);
    double (*score)(double);
};

const std::vector<MeasureDef>& measure_table() {
    static const std::vector<MeasureDef> table = {
        {"coverage", 1,
         [](const Draft& d) -> std::optional<double> { return coverage(*d.image, d.background); },
         coverage_score},
        {"entropy", 1, [](const Draft& d) -> std::optional<double> { return grey_entropy(*d.image); },
         entropy_score},
        {"dimension", 2,
         [](const Draft& d) -> std::optional<double> { return box_dimension(*d.image, d.background); },
         dimension_score},
        {"lyapunov", 1, [](const Draft& d) { return d.lyapunov; }, lyapunov_score},
        // Broken operations score 0.1 to 0.5 and kept ones 0.85 to 1 (symmetry.cpp): 0 at 0.5,
        // linear to 1 at 1. The background agrees with itself: on a sparse picture every
        // operation scores high, so weight it beside coverage.
        {"symmetry", 0, best_point_symmetry, [](double v) { return std::clamp((v - 0.5) / 0.5, 0.0, 1.0); }},
    };
    return table;
}

std::size_t symmetry_index() {
    const auto& t = measure_table();
    for (std::size_t k = 0; k < t.size(); ++k)
        if (std::string(t[k].name) == "symmetry") return k;
    return t.size();
}

std::vector<double> parse_weights(const std::string& text) {
    const auto& table = measure_table();
    std::vector<double> w;
    for (const auto& m : table) w.push_back(m.default_weight);
    if (text.empty()) return w;
    std::string names;
    for (const auto& m : table) names += std::string(names.empty() ? "" : ", ") + m.name;
    std::size_t a = 0;
    while (a <= text.size()) {
        const auto b = std::min(text.find(',', a), text.size());
        const std::string item = text.substr(a, b - a);
        const auto eq = item.find('=');
        double v = 0;
        if (eq == std::string::npos || !parse_double(item.substr(eq + 1), v) || v < 0)
            throw InputError("--weights " + excerpt(text, 80) + ": expected name=w,... with weights >= 0 (" +
                             names + ")");
        const std::string name = item.substr(0, eq);
        std::size_t k = 0;
        while (k < table.size() && name != table[k].name) ++k;
        if (k == table.size())
            throw InputError("--weights " + excerpt(text, 80) + ": unknown measure " + quote(name) +
                             " (the measures: " + names + ")");
        w[k] = v;
        a = b + 1;
    }
    if (std::all_of(w.begin(), w.end(), [](double x) { return x == 0; }))
        throw InputError("--weights " + excerpt(text, 80) + ": every weight is 0");
    return w;
}

/// The largest Lyapunov exponent of a chaos game's maps, by finite differences: 32 orbits
/// and a partner of each at distance 1e-7, all in one batch run through the scheme with the
/// map drawn by weight at each step (the same map for the whole batch), the partner pulled
/// back to 1e-7 after every step; the mean log stretch over 1000 steps after 100. None when
/// the renderer is not a chaos game or every orbit escapes.
std::optional<double> chaos_game_lyapunov(const Registry& reg, const TObject& r, std::uint64_t seed,
                                          std::uint64_t id) {
    if (std::string(r.plugin->desc->name) != "chaos-game") return std::nullopt;
    const TParam* maps = param_of(r, "maps");
    if (!maps || maps->items.empty()) return std::nullopt;
    std::vector<std::shared_ptr<const Transform>> ts;
    std::vector<double> cum;
    double total = 0;
    for (const auto& it : maps->items) {
        auto t = std::dynamic_pointer_cast<const Transform>(build(reg, *it.object));
        if (!t || !t->plane_map_problem().empty()) return std::nullopt;
        double w = 1;
        for (const auto& e : it.extras)
            if (std::string(e.spec->name) == "weight") w = std::get<double>(e.value);
        ts.push_back(t);
        cum.push_back(total += w);
    }
    std::shared_ptr<const IterationScheme> scheme;
    if (const TParam* s = param_of(r, "iteration"); s && s->object)
        scheme = std::dynamic_pointer_cast<const IterationScheme>(build(reg, *s->object));
    Box box{-1, 1, -1, 1};
    if (const TParam* v = param_of(r, "view"); v)
        if (const auto* xs = std::get_if<std::vector<double>>(&v->value); xs && xs->size() == 4)
            box = {(*xs)[0], (*xs)[1], (*xs)[2], (*xs)[3]};
    std::optional<Vec2> start;
    if (const TParam* st = param_of(r, "start"); st)
        if (const auto* p = std::get_if<Vec2>(&st->value)) start = *p;
    constexpr std::size_t m = 32;
    constexpr double delta = 1e-7;
    constexpr int transient = 100, steps = 1000;
    Rng rng = chain_stream(seed ^ 0x6c79617075ull, id);
    std::vector<double> x(2 * m), y(2 * m), sum(m, 0);
    std::vector<unsigned char> alive(m, 1);
    for (std::size_t j = 0; j < m; ++j) {
        if (start) {
            x[j] = start->x + 1e-3 * (uniform_double(rng) - 0.5);
            y[j] = start->y + 1e-3 * (uniform_double(rng) - 0.5);
        } else {
            x[j] = box.xmin + (box.xmax - box.xmin) * uniform_double(rng);
            y[j] = box.ymin + (box.ymax - box.ymin) * uniform_double(rng);
        }
        x[m + j] = x[j] + delta;
        y[m + j] = y[j];
    }
    Points<double> pts{x.data(), y.data(), 2 * m};
    for (int n = 0; n < transient + steps; ++n) {
        const double u = uniform_double(rng) * total;
        const std::size_t k = std::size_t(std::upper_bound(cum.begin(), cum.end(), u) - cum.begin());
        const Transform& t = *ts[std::min(k, ts.size() - 1)];
        if (scheme)
            scheme->step(t, pts, nullptr, std::uint64_t(n));
        else
            t.apply(pts, nullptr);
        for (std::size_t j = 0; j < m; ++j) {
            if (!alive[j]) continue;
            const double dx = x[m + j] - x[j], dy = y[m + j] - y[j];
            const double d = std::hypot(dx, dy);
            if (!std::isfinite(x[j]) || !std::isfinite(y[j]) || !std::isfinite(d) || std::fabs(x[j]) > 1e12 ||
                std::fabs(y[j]) > 1e12) {
                alive[j] = 0;
                x[j] = y[j] = x[m + j] = y[m + j] = 0;
                continue;
            }
            if (n >= transient) sum[j] += std::log(std::max(d, delta * 1e-12) / delta);
            if (d > 0) {
                x[m + j] = x[j] + dx * (delta / d);
                y[m + j] = y[j] + dy * (delta / d);
            } else {
                x[m + j] = x[j] + delta;
                y[m + j] = y[j];
            }
        }
    }
    double s = 0;
    std::size_t k = 0;
    for (std::size_t j = 0; j < m; ++j)
        if (alive[j]) s += sum[j], ++k;
    if (k == 0) return std::nullopt;
    return s / double(k) / steps;
}

// ---- candidates --------------------------------------------------------------------------

struct Candidate {
    std::uint64_t id = 0; ///< order of creation (the tie-break of the ranking)
    int generation = 0;
    std::vector<Gene> genes;
    std::vector<std::string> overrides; ///< PATH=VALUE
    std::string key;
    bool valid = false;
    std::string why; ///< why refused
    std::vector<std::optional<double>> raw;
    std::vector<double> scores;
    double total = 0;
    // Between validation and scoring:
    std::shared_ptr<const Renderer> renderer;
    std::unique_ptr<TObject> typed;
    Rgb background;
    std::optional<PixelFrame> frame;
};

/// A RenderContext that runs every task on the calling thread: a draft is small, and the
/// parallelism is over candidates.
class SerialContext final : public RenderContext {
public:
    explicit SerialContext(const std::atomic<bool>* cancel) : cancel_(cancel) {}
    unsigned workers() const override { return 1; }
    void parallel_for(std::size_t n, const std::function<void(std::size_t, unsigned)>& task) override {
        for (std::size_t i = 0; i < n; ++i) task(i, 0);
    }
    void progress(std::uint64_t) override {}
    bool cancelled() const override { return cancel_ && cancel_->load(std::memory_order_relaxed); }

private:
    const std::atomic<bool>* cancel_;
};

struct Search {
    const Registry& reg;
    const ExploreOptions& o;
    CNode base;                          ///< the config with --set applied
    std::vector<std::string> draft_sets; ///< the draft's overrides
    std::vector<Dim> dims;
    std::vector<double> weights;
    std::vector<Candidate> all;
    std::set<std::string> seen;
    unsigned threads = 1;

    void make(Candidate c) {
        for (std::size_t j = 0; j < dims.size(); ++j) {
            c.overrides.push_back(dims[j].path + "=" + gene_text(dims[j], c.genes[j]));
            c.key += c.overrides.back() + "\n";
        }
        if (!seen.insert(c.key).second) return; // scored already
        all.push_back(std::move(c));
    }

    // Validate every new candidate (serially), then render and measure them in parallel.
    void score(std::size_t from) {
        for (std::size_t i = from; i < all.size(); ++i) {
            Candidate& c = all[i];
            try {
                CNode root = base;
                for (const auto& s : c.overrides) apply_override(root, s, "--param");
                for (const auto& s : draft_sets) apply_override(root, s, "--draft");
                c.typed = validate(reg, Kind::Renderer, *root.find("renderer"), "renderer");
                const Pipeline dp = load_pipeline(reg, root);
                c.renderer = dp.renderer;
                // The draft's frame in the plane, for the symmetry measure: none with fit_view
                // (the recipe's view is not the one drawn) or without a view or area.
                const TParam* fit = param_of(*c.typed, "fit_view");
                if (!(fit && std::holds_alternative<bool>(fit->value) && std::get<bool>(fit->value))) try {
                        c.frame = frame_from_recipe(dp.recipe, dp.renderer->width(), dp.renderer->height(),
                                                    "draft");
                    } catch (const InputError&) {
                    }
                if (const TParam* bg = param_of(*c.typed, "background"))
                    if (const auto* rgb = std::get_if<Rgb>(&bg->value)) c.background = *rgb;
                c.valid = true;
            } catch (const InputError& e) {
                c.valid = false;
                c.why = e.what();
            }
        }
        std::atomic<std::size_t> next{from};
        std::mutex m;
        std::exception_ptr failure;
        auto work = [&] {
            for (;;) {
                const std::size_t i = next.fetch_add(1);
                if (i >= all.size()) return;
                Candidate& c = all[i];
                if (!c.valid) continue;
                try {
                    if (o.cancel && o.cancel->load()) throw Cancelled();
                    SerialContext ctx(o.cancel);
                    RenderStats stats;
                    const Image img = c.renderer->render(ctx, stats);
                    Draft d{&img, c.background, chaos_game_lyapunov(reg, *c.typed, o.seed, c.id),
                            c.frame ? &*c.frame : nullptr, weights[symmetry_index()] > 0};
                    double sw = 0, s = 0;
                    for (std::size_t k = 0; k < measure_table().size(); ++k) {
                        const auto& md = measure_table()[k];
                        c.raw.push_back(md.raw(d));
                        c.scores.push_back(c.raw.back() ? md.score(*c.raw.back()) : 0);
                        if (c.raw.back()) sw += weights[k], s += weights[k] * c.scores.back();
                    }
                    c.total = sw > 0 ? s / sw : 0;
                } catch (const InputError& e) {
                    c.valid = false;
                    c.why = e.what();
                } catch (...) {
                    const std::lock_guard<std::mutex> lock(m);
                    if (!failure) failure = std::current_exception();
                    next.store(all.size());
                }
                c.renderer.reset();
                c.typed.reset();
            }
        };
        std::vector<std::thread> pool;
        for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
        work();
        for (auto& t : pool) t.join();
        if (failure) std::rethrow_exception(failure);
    }

    /// Valid candidates, best first (ties: the earlier).
    std::vector<const Candidate*> ranking() const {
        std::vector<const Candidate*> r;
        for (const auto& c : all)
            if (c.valid) r.push_back(&c);
        std::stable_sort(r.begin(), r.end(), [](const Candidate* a, const Candidate* b) {
            if (a->total != b->total) return a->total > b->total;
            return a->id < b->id;
        });
        return r;
    }
};

std::string fixed(double v, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

std::string measures_line(const Candidate& c) {
    std::string s;
    for (std::size_t k = 0; k < measure_table().size(); ++k) {
        s += std::string(s.empty() ? "" : ", ") + measure_table()[k].name + " ";
        s += c.raw[k] ? fixed(*c.raw[k], 4) + " (score " + fixed(c.scores[k], 3) + ")" : "absent";
    }
    return s;
}

std::string short_name(const std::string& path) {
    const auto dot = path.rfind('.');
    return dot == std::string::npos ? path : path.substr(dot + 1);
}

} // namespace

int run_explore(const Registry& reg, const ExploreOptions& o) {
    auto say = [&](const std::string& s) {
        if (o.info) o.info(s);
    };
    if (o.params.empty() && o.random.empty())
        throw InputError(
            "explore: name the parameters to search with --param PATH=RANGE or --random PLUGIN-PATH");
    Search S{reg, o, {}, {}, {}, parse_weights(o.weights), {}, {}, 1};
    S.threads = o.threads ? o.threads : hardware_threads();

    // The config with --set, validated as a whole first.
    // A config, or an image fixpoint wrote (its recipe); either without output.path, so that a
    // best-k.yaml rendered without -o does not write where the original did.
    S.base = load_config(o.config, o.allow_python);
    if (CNode* out = S.base.find("output"); out && out->is_map())
        for (std::size_t i = 0; i < out->keys.size(); ++i)
            if (out->keys[i].first == "path") {
                out->keys.erase(out->keys.begin() + std::ptrdiff_t(i));
                out->key_marks.erase(out->key_marks.begin() + std::ptrdiff_t(i));
                break;
            }
    for (const auto& s : o.sets) apply_override(S.base, s);
    const Pipeline base_pipe = load_pipeline(reg, S.base);
    const auto typed = validate(reg, Kind::Renderer, *S.base.find("renderer"), "renderer");
    Index idx;
    idx.add(*typed);

    std::set<std::string> taken;
    for (const auto& p : o.params) {
        S.dims.push_back(parse_param(reg, S.base, idx, p, o.config));
        if (!taken.insert(S.dims.back().path).second)
            throw InputError(excerpt("--param " + p, 100) + ": " + quote(S.dims.back().path, 100) +
                             " is named twice");
    }
    for (const auto& r : o.random)
        for (auto& d : random_dims(idx, r, o.config, taken)) {
            taken.insert(d.path);
            S.dims.push_back(std::move(d));
        }

    // The draft: the larger side draft_size pixels, few points, one sample per pixel.
    {
        const TParam* w = param_of(*typed, "width");
        const TParam* h = param_of(*typed, "height");
        if (w && h && std::holds_alternative<std::int64_t>(w->value) &&
            std::holds_alternative<std::int64_t>(h->value)) {
            const double W = double(std::get<std::int64_t>(w->value)),
                         H = double(std::get<std::int64_t>(h->value));
            const double f = std::min(1.0, double(o.draft_size) / std::max(W, H));
            S.draft_sets.push_back("renderer.width=" + std::to_string(std::max(1LL, std::llround(W * f))));
            S.draft_sets.push_back("renderer.height=" + std::to_string(std::max(1LL, std::llround(H * f))));
        }
        if (const TParam* p = param_of(*typed, "points");
            p && std::holds_alternative<std::int64_t>(p->value)) {
            const long long pts = std::min<long long>(std::get<std::int64_t>(p->value), o.draft_points);
            S.draft_sets.push_back("renderer.points=" + std::to_string(pts));
            if (const TParam* c = param_of(*typed, "chains");
                c && std::holds_alternative<std::int64_t>(c->value))
                if (std::get<std::int64_t>(c->value) > pts)
                    S.draft_sets.push_back("renderer.chains=" + std::to_string(pts));
        }
        if (const TParam* p = param_of(*typed, "samples");
            p && std::holds_alternative<std::int64_t>(p->value))
            S.draft_sets.push_back("renderer.samples=1");
    }

    // Every file written, checked before the search.
    const fs::path dir(o.out_dir);
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw InputError("-o " + quote(o.out_dir, 200) + ": not a folder");
    std::vector<std::string> files = {(dir / "sheet.png").string(), (dir / "candidates.tsv").string()};
    for (int k = 1; k <= o.keep; ++k) {
        files.push_back((dir / ("best-" + std::to_string(k) + ".yaml")).string());
        files.push_back((dir / ("best-" + std::to_string(k) + ".png")).string());
    }
    if (!o.force)
        for (const auto& f : files)
            if (fs::exists(fs::symlink_status(f, ec)))
                throw InputError(quote(f, 200) + " exists: add --force to replace it");
    check_memory(base_pipe, S.threads);

    // Random phase.
    for (int i = 0; i < o.candidates; ++i) {
        Rng r = chain_stream(o.seed, std::uint64_t(i));
        Candidate c;
        c.id = std::uint64_t(i);
        for (const auto& d : S.dims) c.genes.push_back(draw(d, r));
        S.make(std::move(c));
    }
    S.score(0);
    auto summary = [&](const char* what) {
        const auto r = S.ranking();
        std::size_t invalid = 0;
        for (const auto& c : S.all) invalid += !c.valid;
        say(std::string(what) + ": " + std::to_string(S.all.size()) + " candidates, " +
            std::to_string(invalid) + " invalid; best " +
            (r.empty() ? std::string("none") : fixed(r[0]->total, 4)));
    };
    summary("random phase");
    if (o.cancel && o.cancel->load()) throw Cancelled();

    // Evolutionary phase.
    for (int g = 1; g <= o.generations; ++g) {
        const auto ranked = S.ranking();
        if (ranked.empty()) break;
        std::vector<std::vector<Gene>> parents;
        for (std::size_t k = 0; k < ranked.size() && k < std::size_t(o.keep); ++k)
            parents.push_back(ranked[k]->genes);
        const std::size_t from = S.all.size();
        for (int i = 0; i < o.candidates; ++i) {
            Rng r = chain_stream(o.seed, (std::uint64_t(g) << 32) | std::uint64_t(i));
            const auto& a = parents[uniform_below(r, std::uint32_t(parents.size()))];
            const auto& b = parents[uniform_below(r, std::uint32_t(parents.size()))];
            Candidate c;
            c.id = (std::uint64_t(g) << 32) | std::uint64_t(i);
            c.generation = g;
            for (std::size_t j = 0; j < S.dims.size(); ++j) {
                Gene x = uniform_double(r) < 0.5 ? a[j] : b[j];
                if (uniform_double(r) < 0.5) mutate(S.dims[j], x, r);
                c.genes.push_back(x);
            }
            S.make(std::move(c));
        }
        S.score(from);
        summary(("generation " + std::to_string(g)).c_str());
        if (o.cancel && o.cancel->load()) throw Cancelled();
    }

    const auto ranked = S.ranking();
    if (ranked.empty()) {
        std::string why;
        for (const auto& c : S.all)
            if (!c.why.empty()) {
                why = c.why;
                break;
            }
        throw InputError("explore: none of the " + std::to_string(S.all.size()) + " candidates is valid" +
                         (why.empty() ? "" : " (the first refusal: " + why + ")"));
    }
    const std::size_t keep = std::min<std::size_t>(ranked.size(), std::size_t(o.keep));

    // The full renders of the best, each checked like a render.
    std::vector<Pipeline> pipes;
    std::vector<CNode> roots;
    for (std::size_t k = 0; k < keep; ++k) {
        CNode root = S.base;
        for (const auto& s : ranked[k]->overrides) apply_override(root, s, "--param");
        pipes.push_back(load_pipeline(reg, root));
        check_memory(pipes.back(), S.threads);
        roots.push_back(std::move(root));
    }
    fs::create_directories(dir, ec);
    if (ec) throw InputError("-o " + quote(o.out_dir, 200) + ": cannot create the folder: " + ec.message());
    for (const auto& f : files)
        if (f.ends_with(".png")) check_output(f);
    std::vector<Image> images;
    std::vector<std::string> captions;
    for (std::size_t k = 0; k < keep; ++k) {
        Runtime rt(S.threads, o.cancel);
        RenderStats stats;
        Image img;
        try {
            img = pipes[k].renderer->render(rt, stats);
        } catch (const InputError& e) {
            throw InputError(pipes[k].renderer_mark.str() + ": renderer: " + e.what());
        }
        if (o.cancel && o.cancel->load()) throw Cancelled();
        images.push_back(std::move(img));
        // Rank, score and the values (3 digits; named when there is one): a caption fits a cell.
        std::string cap = "#" + std::to_string(k + 1) + " " + fixed(ranked[k]->total, 3) + " ";
        for (std::size_t j = 0; j < S.dims.size(); ++j) {
            Dim d = S.dims[j];
            d.digits = 3;
            cap += std::string(j ? ", " : "") + (S.dims.size() == 1 ? short_name(d.path) + " = " : "") +
                   gene_text(d, ranked[k]->genes[j]);
        }
        // Cut to the cell (12-pixel DejaVu Sans: digits about 7.6 pixels wide).
        const std::size_t fits = std::size_t(std::max(8.0, (images.back().width - 4) / 7.6));
        if (cap.size() > fits) cap = cap.substr(0, fits - 2) + "..";
        captions.push_back(cap);
        say("best-" + std::to_string(k + 1) + ": score " + fixed(ranked[k]->total, 4) + ": " +
            measures_line(*ranked[k]));
    }

    std::string command = "fixpoint explore " + o.config + " --seed " + std::to_string(o.seed) +
                          " --candidates " + std::to_string(o.candidates) + " --generations " +
                          std::to_string(o.generations);
    command += " --keep " + std::to_string(o.keep) + " --draft-size " + std::to_string(o.draft_size) +
               " --draft-points " + std::to_string(o.draft_points);
    for (const auto& s : o.sets) command += " --set '" + s + "'";
    for (const auto& p : o.params) command += " --param '" + p + "'";
    for (const auto& r : o.random) command += " --random " + r;
    if (!o.weights.empty()) command += " --weights " + o.weights;
    // All the files or none: a Ctrl-C or a full disk half way removes those written.
    FileSet written(o.cancel);
    for (std::size_t k = 0; k < keep; ++k) {
        const Candidate& c = *ranked[k];
        std::string head = "# " + command + "\n# rank " + std::to_string(k + 1) + " of " +
                           std::to_string(ranked.size()) + " valid candidates (generation " +
                           std::to_string(c.generation) + "), score " + fixed(c.total, 4) + "\n# " +
                           measures_line(c) + "\n";
        for (const auto& s : c.overrides) head += "# " + s + "\n";
        const std::string base_name = (dir / ("best-" + std::to_string(k + 1))).string();
        written.bytes(head + emit_yaml(roots[k]), base_name + ".yaml");
        written.image(images[k], base_name + ".png", pipes[k].bit_depth, pipes[k].recipe);
    }
    const Image sheet = contact_sheet(images, captions, o.columns);
    written.image(sheet, (dir / "sheet.png").string(), 8,
                  "# contact sheet: " + command + "\n# the recipe of best-1:\n" + pipes[0].recipe);

    // Every candidate: ranked ones by rank, then the refused ones.
    std::string tsv = "rank\tid\tgeneration\tscore";
    for (const auto& m : measure_table()) tsv += std::string("\t") + m.name + "\t" + m.name + "_score";
    for (const auto& d : S.dims) tsv += "\t" + d.path;
    tsv += "\trefused\n";
    auto row = [&](const Candidate& c, const std::string& rank) {
        tsv += rank + "\t" + std::to_string(c.id) + "\t" + std::to_string(c.generation) + "\t" +
               (c.valid ? fixed(c.total, 6) : "");
        for (std::size_t k = 0; k < measure_table().size(); ++k) {
            const bool has = c.valid && k < c.raw.size() && c.raw[k];
            tsv += "\t" + (has ? fixed(*c.raw[k], 6) : "") + "\t" + (has ? fixed(c.scores[k], 6) : "");
        }
        for (std::size_t j = 0; j < S.dims.size(); ++j) tsv += "\t" + gene_text(S.dims[j], c.genes[j]);
        std::string why = c.why;
        std::replace(why.begin(), why.end(), '\t', ' ');
        std::replace(why.begin(), why.end(), '\n', ' ');
        tsv += "\t" + why + "\n";
    };
    for (std::size_t k = 0; k < ranked.size(); ++k) row(*ranked[k], std::to_string(k + 1));
    for (const auto& c : S.all)
        if (!c.valid) row(c, "-");
    written.bytes(tsv, (dir / "candidates.tsv").string());
    written.commit();
    say(o.out_dir + ": best-1 ... best-" + std::to_string(keep) +
        " (.yaml, .png), sheet.png, candidates.tsv");
    return 0;
}

} // namespace fp::host
