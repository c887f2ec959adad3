// circles — orbit traps that are circles of a metric (paper 04, Sec. 2-3): trap i holds the
// points p with d(p, c_i) < r_i, d any Metric plugin (Euclidean lp by default; Fig. 2 shows the
// circles of the other metrics). The traps are tried in the order of the list and the first
// that holds the point wins (Algorithm 3, lines 10-14); test() reports its index and d / r.
//
// Presets (the configurations of Figs. 1 and 3; the text of Fig. 1 is damaged in our copy,
// see below), all with the Euclidean radii the paper gives:
//   fig-1a  one circle: c = (0, 0), r = 3.5
//   fig-1b  three: (-3.5, -2), (3.5, -2), (0, -2 + 3.5 sqrt 3), r = 3.5
//   fig-1c  four: (-3.5, 3.5), (3.5, 3.5), (-3.5, -3.5), (3.5, -3.5), r = 3.5
//   fig-1d  seven: (0, 0) and six at distance 7: (0, 7), (-3.5 sqrt 3, 3.5), (-3.5 sqrt 3, -3.5),
//           (0, -7), (3.5 sqrt 3, -3.5), (3.5 sqrt 3, 3.5), r = 3.5
//   fig-3a  two: (0, 3.5), (0, -3.5), r = 3.5
//   fig-3b  four: (4, 0), (-4, 0), (0, 4), (0, -4), r = 2 sqrt 2
//   fig-3c  five: (0, 0), (-6, 0), (6, 0), (0, -6), (0, 6), r = 3
// Damage in the extracted text of Fig. 1 and what was decided:
//   - (b) is printed twice, the second time under the label (a) with "c0 = [0, c1]" garbage; the
//     first copy is consistent (three circles of radius 3.5 whose centres are 7 = 2r apart: an
//     equilateral triangle of mutually tangent circles), so it is taken. Its centroid is at
//     y = -2 + 3.5 / sqrt 3 = 0.02, not 0: kept as printed (-2), since both lower centres agree.
//   - (c) lists centres c4, c5 and "c7 = r1 = ..." beside r0 = ... = r3 = 3.5: the radius list
//     and the figure's caption ("four orbit traps") say four, so c0..c3 at (+-3.5, +-3.5), each
//     tangent to its two neighbours.
//   - (d) is legible: the six outer centres are at distance 3.5 sqrt(3 + 1) = 7 = 2r from the
//     origin and from each other (a hexagon of tangent circles around the central one).
// In every preset neighbouring circles only touch, so the order decides nothing but points of
// tangency.
//
// Errors: a preset together with centres/radii; neither; centres without radii or the other way
// round; radii neither one (for all) nor one per centre. The schema refuses a radius <= 0 and
// empty lists with the element's position.
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace {

struct Circle {
    fp::Vec2 c;
    double r;
};

std::vector<Circle> preset(const std::string& name) {
    const double s3 = std::sqrt(3.0), r2 = 2 * std::sqrt(2.0);
    if (name == "fig-1a") return {{{0, 0}, 3.5}};
    if (name == "fig-1b") return {{{-3.5, -2}, 3.5}, {{3.5, -2}, 3.5}, {{0, -2 + 3.5 * s3}, 3.5}};
    if (name == "fig-1c")
        return {{{-3.5, 3.5}, 3.5}, {{3.5, 3.5}, 3.5}, {{-3.5, -3.5}, 3.5}, {{3.5, -3.5}, 3.5}};
    if (name == "fig-1d")
        return {{{0, 0}, 3.5},  {{0, 7}, 3.5},           {{-3.5 * s3, 3.5}, 3.5}, {{-3.5 * s3, -3.5}, 3.5},
                {{0, -7}, 3.5}, {{3.5 * s3, -3.5}, 3.5}, {{3.5 * s3, 3.5}, 3.5}};
    if (name == "fig-3a") return {{{0, 3.5}, 3.5}, {{0, -3.5}, 3.5}};
    if (name == "fig-3b") return {{{4, 0}, r2}, {{-4, 0}, r2}, {{0, 4}, r2}, {{0, -4}, r2}};
    if (name == "fig-3c") return {{{0, 0}, 3}, {{-6, 0}, 3}, {{6, 0}, 3}, {{0, -6}, 3}, {{0, 6}, 3}};
    throw fp::InternalError("circles: unknown preset " + name); // the schema lists the choices
}

constexpr fp::ParamSpec params[] = {
    fp::param::object("metric", fp::Kind::Metric,
                      "the metric the circles are circles of (paper 04, eqs. (14)-(16))")
        .def("{type: lp, p: 2}"),
    fp::param::string("preset", "a configuration of the paper: fig-1a, fig-1b, fig-1c, fig-1d (Lu et al.'s, "
                                "Fig. 1), fig-3a, fig-3b, fig-3c (paper 04's, Fig. 3)")
        .one_of("fig-1a|fig-1b|fig-1c|fig-1d|fig-3a|fig-3b|fig-3c")
        .opt(),
    fp::param::vec2s("centres", "centres c_i of the circles, tried in this order (the first that holds a "
                                "point catches it)")
        .min_len(1)
        .opt(),
    fp::param::reals("radii", "radii r_i: one per centre, or one for all").min_len(1).above(0).opt(),
};

class Circles final : public fp::Trap {
public:
    explicit Circles(const fp::ParamBag& p) : metric_(p.object<fp::Metric>("metric")) {
        const bool has_preset = p.has("preset"), has_c = p.has("centres"), has_r = p.has("radii");
        if (has_preset && (has_c || has_r))
            throw fp::ParamError(has_c ? "centres" : "radii",
                                 "give either a preset or centres and radii, not both");
        if (has_preset) {
            circles_ = preset(p.string("preset"));
        } else {
            if (!has_c && !has_r)
                throw fp::ParamError("no traps: give centres and radii, or a preset (fig-1a, fig-1b, fig-1c, "
                                     "fig-1d, fig-3a, fig-3b, fig-3c)");
            if (!has_c) throw fp::ParamError("radii", "radii without centres: give the centres too");
            if (!has_r)
                throw fp::ParamError("centres", "centres without radii: give radii (one per centre, or one)");
            const auto& c = p.vec2s("centres");
            const auto& r = p.reals("radii");
            if (r.size() != 1 && r.size() != c.size())
                throw fp::ParamError("radii", "expected 1 radius (for all) or " + std::to_string(c.size()) +
                                                  " (one per centre), got " + std::to_string(r.size()));
            for (std::size_t i = 0; i < c.size(); ++i)
                circles_.push_back({c[i], r.size() == 1 ? r[0] : r[i]});
        }
        for (const Circle& c : circles_) {
            keys_f_.push_back(threshold<float>(c.r));
            keys_d_.push_back(threshold<double>(c.r));
            cx_.push_back(c.c.x), cy_.push_back(c.c.y), r_.push_back(c.r);
        }
    }

    // With the Euclidean metric, run() below is exactly TrapKernel::euclidean_circles (the metric's
    // key is dx * dx + dy * dy, from_key the rounded root; the order "first circle wins" and the
    // clamped ratio are the same), so renderers may test these circles inline.
    fp::TrapKernel kernel() const override {
        if (metric_->kind() != fp::Metric::Kind::euclidean) return {};
        return {fp::TrapKernel::Kind::euclidean_circles,
                circles_.size(),
                cx_.data(),
                cy_.data(),
                r_.data(),
                keys_f_.data(),
                keys_d_.data()};
    }

    std::size_t count() const override { return circles_.size(); }
    void test(fp::Points<const float> p, std::int32_t* trap, float* ratio) const override {
        run(p, trap, ratio);
    }
    void test(fp::Points<const double> p, std::int32_t* trap, double* ratio) const override {
        run(p, trap, ratio);
    }

private:
    // Per chunk of points: the keys of all circles (Metric::distance_key, one call per circle:
    // for the Euclidean metric squared distances, no root), merged in one pass over the points per
    // group of up to 8 circles, the circles and groups taken from last to first so that the first
    // circle that holds a point is the one left standing (Algorithm 3, lines 10-14) without
    // testing whether the point is already caught. A point is held when its key is below the
    // circle's threshold (below), which is exactly when its distance is below r. Then only the
    // caught points (a few per chunk) are gathered, their keys turned back into distances (one
    // batch call) and divided by their circle's radius; the ratio is clamped below 1.
    const std::vector<float>& keys(float) const { return keys_f_; }
    const std::vector<double>& keys(double) const { return keys_d_; }

    // The least key K (in T) whose distance from_key(K) is >= r: then key < K exactly when the
    // distance is < r, the test Algorithm 3 makes with the distance itself, rim included
    // (squaring r instead would catch points whose rounded distance equals r).
    template <class T>
    T threshold(double radius) const {
        const T r = T(radius);
        auto dist = [&](T k) {
            metric_->from_key(&k, 1);
            return k;
        };
        T k = T(metric_->key(radius));
        for (int i = 0; i < 64 && dist(k) >= r; ++i) k = std::nextafter(k, T(0));
        for (int i = 0; i < 64 && dist(k) < r; ++i) k = std::nextafter(k, std::numeric_limits<T>::infinity());
        return k;
    }

    static constexpr std::size_t group = 8;

    template <class T>
    void run(fp::Points<const T> p, std::int32_t* __restrict trap, T* __restrict ratio) const {
        alignas(64) T d[group][fp::chunk_size];
        alignas(64) T hit_key[fp::chunk_size];
        std::uint32_t hit_at[fp::chunk_size];
        const T below_one = std::nextafter(T(1), T(0));
        const std::vector<T>& key = keys(T{});
        const std::size_t nc = circles_.size();
        for (std::size_t b = 0; b < p.n; b += fp::chunk_size) {
            const std::size_t n = std::min(fp::chunk_size, p.n - b);
            std::int32_t* __restrict tr = trap + b;
            T* __restrict ra = ratio + b;
            std::fill(tr, tr + n, std::int32_t(-1));
            std::fill(ra, ra + n, T(0));
            for (std::size_t g_end = nc; g_end > 0;) {
                const std::size_t g0 = g_end > group ? g_end - group : 0, gn = g_end - g0;
                for (std::size_t j = 0; j < gn; ++j)
                    metric_->distance_key(p.sub(b, n), circles_[g0 + j].c, d[j]);
                for (std::size_t j = gn; j-- > 0;) {
                    const T kj = key[g0 + j];
                    const auto idx = std::int32_t(g0 + j);
                    const T* __restrict dj = d[j];
                    for (std::size_t i = 0; i < n; ++i) {
                        const bool hit = dj[i] < kj;
                        tr[i] = hit ? idx : tr[i];
                        ra[i] = hit ? dj[i] : ra[i];
                    }
                }
                g_end = g0;
            }
            // Caught points are few: test 16 lanes at once (a vectorised count), then look inside.
            std::size_t nh = 0;
            for (std::size_t i0 = 0; i0 < n; i0 += 16) {
                const std::size_t i1 = std::min(n, i0 + 16);
                unsigned caught = 0;
                for (std::size_t i = i0; i < i1; ++i) caught += tr[i] >= 0 ? 1u : 0u;
                if (caught == 0) continue;
                for (std::size_t i = i0; i < i1; ++i)
                    if (tr[i] >= 0) {
                        hit_at[nh] = std::uint32_t(i);
                        hit_key[nh++] = ra[i];
                    }
            }
            if (nh == 0) continue;
            metric_->from_key(hit_key, nh);
            for (std::size_t h = 0; h < nh; ++h) {
                const std::size_t i = hit_at[h];
                ra[i] = std::min(hit_key[h] / T(circles_[std::size_t(tr[i])].r), below_one);
            }
        }
    }

    std::shared_ptr<const fp::Metric> metric_;
    std::vector<Circle> circles_;
    std::vector<float> keys_f_;       ///< per circle: the least key whose distance is >= r (float)
    std::vector<double> keys_d_;      ///< the same in double
    std::vector<double> cx_, cy_, r_; ///< the circles again, as arrays (kernel())
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<Circles>(fp::Kind::Trap, "circles",
                          "orbit traps: circles of a metric, the first that holds a point catches it "
                          "(paper 04, Figs. 1-3)",
                          params)
        .with_example("{preset: fig-3b}"))
