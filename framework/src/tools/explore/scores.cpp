// `fixpoint explore`'s scores (scores.hpp).
#include "scores.hpp"

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

/// The declared group's strength against accidental extra symmetry, about the origin: the
/// lowest `fixpoint symmetry` score of the rotations and mirrors the recipe's wallpaper group
/// keeps there (its generators about the origin, in its best orientation), less the highest
/// score of those it does not keep (not in the point group they generate). Translations and
/// glides are left out: a draft's pixels do not fall on themselves under a lattice vector, so
/// a detailed pattern scores low on them whatever its coefficients. A wallpaper keeps its
/// operations by construction, up to resampling: near 1 less the others' 0.3 to 0.5; a flat
/// picture keeps every operation, and so does one whose coefficients happen to have more
/// symmetry than declared: near 0. None for a group with no rotation or mirror about the
/// origin (p1, pg, pgg).
std::optional<double> group_strength(const Draft& d) {
    if (!d.group_symmetry || !d.frame || d.group.empty()) return std::nullopt;
    struct Point {
        const PlaneOp* op;
        double score;
    };
    std::vector<Point> points;
    for (const auto& op : symmetry_ops())
        if (op.tx == 0 && op.ty == 0) {
            const OpScore sc = score_op(*d.image, *d.frame, op, SymmetryOptions{});
            if (sc.measured) points.push_back({&op, sc.score});
        }
    using M = std::array<double, 4>;
    const auto same = [](const M& a, const M& b) {
        for (int i = 0; i < 4; ++i)
            if (std::fabs(a[std::size_t(i)] - b[std::size_t(i)]) > 1e-9) return false;
        return true;
    };
    std::optional<double> best;
    for (const auto& g : wallpaper_groups()) {
        if (g.name != d.group) continue;
        // The point group its operations about the origin generate (at most 12 matrices).
        std::vector<M> closure{{1, 0, 0, 1}};
        double declared = 2;
        for (const auto& id : g.ops)
            for (const auto& p : points)
                if (p.op->id == id) {
                    declared = std::min(declared, p.score);
                    closure.push_back({p.op->a, p.op->b, p.op->c, p.op->d});
                }
        if (declared > 1) continue;
        for (std::size_t i = 0; i < closure.size() && closure.size() <= 24; ++i)
            for (std::size_t j = 0; j <= i && closure.size() <= 24; ++j)
                for (const auto& [x, y] : {std::pair{i, j}, std::pair{j, i}}) {
                    const M& a = closure[x];
                    const M& b = closure[y];
                    const M m{a[0] * b[0] + a[1] * b[2], a[0] * b[1] + a[1] * b[3], a[2] * b[0] + a[3] * b[2],
                              a[2] * b[1] + a[3] * b[3]};
                    if (std::none_of(closure.begin(), closure.end(), [&](const M& c) { return same(c, m); }))
                        closure.push_back(m);
                }
        double extra = 0;
        for (const auto& p : points) {
            const M m{p.op->a, p.op->b, p.op->c, p.op->d};
            if (std::none_of(closure.begin(), closure.end(), [&](const M& c) { return same(c, m); }))
                extra = std::max(extra, p.score);
        }
        best = std::max(best.value_or(-1.0), declared - extra);
    }
    return best;
}

} // namespace

const std::vector<MeasureDef>& measure_table() {
    static const std::vector<MeasureDef> table = {
        {"coverage", 1, 0,
         [](const Draft& d) -> std::optional<double> { return coverage(*d.image, d.background); },
         coverage_score},
        {"entropy", 1, 0, [](const Draft& d) -> std::optional<double> { return grey_entropy(*d.image); },
         entropy_score},
        {"dimension", 2, 0,
         [](const Draft& d) -> std::optional<double> { return box_dimension(*d.image, d.background); },
         dimension_score},
        {"lyapunov", 1, 0, [](const Draft& d) { return d.lyapunov; }, lyapunov_score},
        // Broken operations score 0.1 to 0.5 and kept ones 0.85 to 1 (symmetry.cpp): 0 at 0.5,
        // linear to 1 at 1. The background agrees with itself: on a sparse picture every
        // operation scores high, so weight it beside coverage.
        {"symmetry", 0, 0, best_point_symmetry,
         [](double v) { return std::clamp((v - 0.5) / 0.5, 0.0, 1.0); }},
        // Patterns that fill the image (measures.hpp; the scores calibrated on paper 04's
        // figures against random coefficients: explore --help).
        {"colour_entropy", 0, 1,
         [](const Draft& d) -> std::optional<double> { return colour_entropy(*d.image); },
         colour_entropy_score},
        {"edge_entropy", 0, 1, [](const Draft& d) -> std::optional<double> { return edge_entropy(*d.image); },
         edge_entropy_score},
        {"spectrum", 0, 1, [](const Draft& d) -> std::optional<double> { return spectral_spread(*d.image); },
         spectrum_score},
        {"group", 0, 1, group_strength, group_score},
        {"contrast", 0, 1, [](const Draft& d) -> std::optional<double> { return rms_contrast(*d.image); },
         contrast_score},
    };
    return table;
}

std::size_t measure_index(const std::string& name) {
    const auto& t = measure_table();
    for (std::size_t k = 0; k < t.size(); ++k)
        if (name == t[k].name) return k;
    return t.size();
}

std::size_t symmetry_index() { return measure_index("symmetry"); }

std::vector<double> parse_weights(const std::string& text, bool wallpaper) {
    const auto& table = measure_table();
    std::vector<double> w;
    for (const auto& m : table) w.push_back(wallpaper ? m.wallpaper_weight : m.default_weight);
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

namespace {

/// The largest Lyapunov exponent of a chaos game's maps, by finite differences: 32 orbits
/// and a partner of each at distance 1e-7, all in one batch run through the scheme with the
/// map drawn by weight at each step (the same map for the whole batch), the partner pulled
/// back to 1e-7 after every step; the mean log stretch over 1000 steps after 100. None when
/// the renderer is not a chaos game (fp::ability::weighted_maps) or every orbit escapes.
} // namespace

std::optional<double> chaos_game_lyapunov(const Registry& reg, const TObject& r, std::uint64_t seed,
                                          std::uint64_t id) {
    if (!(r.plugin->desc->abilities & ability::weighted_maps)) return std::nullopt;
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

} // namespace fp::host::explore_detail
