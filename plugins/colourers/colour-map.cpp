// colour-map — the exponential colour maps of Lu et al. (paper 04, Algorithm 1 and Table 1)
// and their index rule for orbit traps (Algorithm 3, lines 16-17).
//
// The table (built once, at construction)
// ---------------------------------------
// Base colours b_0..b_N with colour ratios q_0 < q_1 < ... < q_N in [0, 1], Nc entries,
// exponent E. Entry i is the colour of the ratio q = (i / (1 + i))^E, linearly interpolated
// between the two base colours whose ratios bracket q (Algorithm 1):
//     k = 1; for i = 0 .. Nc - 1: q = (i / (1 + i))^E; while q > q_k: k = k + 1;
//            t = (q_k - q) / (q_k - q_{k-1}); table[i] = t b_{k-1} + (1 - t) b_k.
// Line 4, q = (i / (1 + i))^E, is not damage: it is the inverse of the index rule below
// (index = v / (1 - v) with v = (d / r)^(1 / E) solves to d / r = (i / (1 + i))^E), so entry i
// is the colour of the trap ratio d / r that lands on it, and q runs over [0, 1) as i grows.
// The paper's loop leaves two cases open, decided here: the while loop stops at k = N (q never
// reaches 1, but q_N may be below 1), and t is clamped to [0, 1], so a q below q_0 takes b_0 and
// one above q_N takes b_N (no extrapolation).
//
// Base colours are written as in Table 1: numbers in [0, 255], a flat list of r, g, b triples
// (`colours: [0, 0, 0,  255, 0, 0, ...]`), divided by 255 (the image is written without a
// transfer curve, so these are the display values of the paper). Presets fig-4a..fig-4d are the
// four maps of Table 1 (Fig. 4); E = 16 and Nc = 3000 are the defaults, as in all the paper's
// examples.
//
// Orbit-trap hits (colour_hits)
// -----------------------------
// v = 10^(log10(d / r) / E) = (d / r)^(1 / E), index = min(v / (1 - v), Nc - 1), integer part
// (computed in double: v / (1 - v) only for v < 1; d = 0 gives index 0; v >= 1 or NaN the last
// entry). A sample never trapped takes the renderer's background, or the last entry of the table
// when there is none (Algorithm 3, line 21). Hits find the index without pow, in a table of the
// ratios where it steps (exactly pow's index: see index_of).
//
// Histograms (resolve), for point-plotting renderers: a bin's log-density
// (log2(1 + h) / log2(1 + max h))^(1 / gamma) (paper 02, eq. (28)) is read as the ratio above
// and coloured by the same index rule, so the densest bins take the last colour; empty bins
// take the background.
//
// Errors: preset together with colours/ratios; neither; colours not r, g, b triples; fewer than
// two base colours; ratios not one per base colour or not strictly increasing. The schema
// refuses E <= 0, Nc < 2, ratios outside [0, 1] and colour values outside [0, 255].
#include "finishing.hpp"
#include "tone_map.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

std::string real_text(double v) {
    char buf[32];
    for (int prec = 1; prec <= 17; ++prec) {
        std::snprintf(buf, sizeof buf, "%.*g", prec, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

struct Map {
    std::vector<double> colours; // r, g, b triples in [0, 255]
    std::vector<double> ratios;
};

// Table 1 of paper 04.
Map preset(const std::string& name) {
    if (name == "fig-4a")
        return {{0, 0, 0, 255, 0, 0, 255, 128, 0, 0, 0, 0, 255, 128, 0, 255, 255, 255, 26, 0, 0},
                {0.0, 0.7, 0.75, 0.8, 0.85, 0.9, 1.0}};
    if (name == "fig-4b")
        return {
            {0, 0, 0, 0, 0, 150, 161, 202, 241, 243, 195, 0, 0, 0, 0, 243, 195, 0, 255, 255, 255, 26, 0, 0},
            {0.0, 0.5, 0.7, 0.75, 0.8, 0.85, 0.9, 1.0}};
    if (name == "fig-4c")
        return {{0, 0, 0, 6, 204, 2, 0, 0, 0, 19, 158, 245, 200, 200, 200, 115, 106, 55},
                {0.0, 0.6, 0.8, 0.85, 0.9, 1.0}};
    if (name == "fig-4d")
        return {{0, 0, 0, 254, 0, 0, 0, 255, 0, 255, 255, 127, 25, 0, 0, 255, 52, 0, 0, 128, 255, 25, 0, 0},
                {0.0, 0.25, 0.3, 0.47, 0.6, 0.7, 0.85, 1.0}};
    throw fp::InternalError("colour-map: unknown preset " + name); // the schema lists the choices
}

constexpr fp::ParamSpec params[] = {
    fp::param::string("preset", "one of the colour maps of Table 1 (Fig. 4): fig-4a, fig-4b, fig-4c, fig-4d")
        .one_of("fig-4a|fig-4b|fig-4c|fig-4d")
        .opt()
        .as(fp::ParamRole::finish),
    fp::param::reals("colours",
                     "base colours b_0..b_N as in Table 1: r, g, b triples of numbers in [0, 255], "
                     "one flat list")
        .min(0)
        .max(255)
        .opt()
        .as(fp::ParamRole::finish),
    fp::param::reals("ratios", "colour ratios q_0 < q_1 < ... < q_N in [0, 1], one per base colour")
        .min(0)
        .max(1)
        .opt()
        .as(fp::ParamRole::finish),
    fp::param::integer("Nc", "number of colours in the table")
        .def("3000")
        .min(2)
        .max(16777216)
        .as(fp::ParamRole::finish),
    fp::param::real("E", "exponent E of Algorithm 1 and of the index rule")
        .def("16")
        .above(0)
        .as(fp::ParamRole::finish),
    fp_colourers::gamma_param.as(fp::ParamRole::finish),
};

class ColourMap final : public fp_colourers::Resolving<ColourMap> {
public:
    explicit ColourMap(const fp::ParamBag& p) : inv_e_(1.0 / p.real("E")), gamma_(p.real("gamma")) {
        const bool has_preset = p.has("preset"), has_c = p.has("colours"), has_q = p.has("ratios");
        Map m;
        if (has_preset && (has_c || has_q))
            throw fp::ParamError(has_c ? "colours" : "ratios",
                                 "give either a preset or colours and ratios, not both");
        if (has_preset) {
            m = preset(p.string("preset"));
        } else {
            if (!has_c && !has_q)
                throw fp::ParamError(
                    "no colours: give colours and ratios, or a preset (fig-4a, fig-4b, fig-4c, "
                    "fig-4d)");
            if (!has_c) throw fp::ParamError("ratios", "ratios without colours: give the base colours too");
            if (!has_q)
                throw fp::ParamError("colours", "colours without ratios: give one ratio per base colour");
            m = {p.reals("colours"), p.reals("ratios")};
            if (m.colours.size() % 3 != 0)
                throw fp::ParamError("colours", "expected r, g, b triples (a multiple of 3 numbers), got " +
                                                    std::to_string(m.colours.size()) + " numbers");
            const std::size_t nb = m.colours.size() / 3;
            if (nb < 2)
                throw fp::ParamError("colours",
                                     "a colour map needs at least 2 base colours, got " + std::to_string(nb));
            if (m.ratios.size() != nb)
                throw fp::ParamError("ratios", "expected " + std::to_string(nb) +
                                                   " ratios (one per base colour), got " +
                                                   std::to_string(m.ratios.size()));
            for (std::size_t i = 1; i < nb; ++i)
                if (!(m.ratios[i] > m.ratios[i - 1]))
                    throw fp::ParamError("ratios", "the ratios must increase strictly: ratios[" +
                                                       std::to_string(i) + "] = " + real_text(m.ratios[i]) +
                                                       " is not above ratios[" + std::to_string(i - 1) +
                                                       "] = " + real_text(m.ratios[i - 1]));
        }
        build(m, std::size_t(p.integer("Nc")), p.real("E"));
        build_thresholds(p.real("E"));
    }

    void update(const std::uint32_t*, fp::ColourState, const fp::Rgb*, const unsigned char*) const override {}
    bool needs_colour() const override { return false; }
    bool reads_hits_only() const override { return true; }
    bool colours_trap_hits() const override { return true; }

    void colour_hits(const std::int32_t* trap, const float* ratio, const std::uint32_t*, std::size_t n,
                     const fp::Rgb* background, float* rgb) const override {
        const fp::Rgb bg = background ? *background : table_.back();
        for (std::size_t i = 0; i < n; ++i) {
            const fp::Rgb c = trap[i] < 0 ? bg : table_[index_of(ratio[i])];
            rgb[3 * i] = c.r;
            rgb[3 * i + 1] = c.g;
            rgb[3 * i + 2] = c.b;
        }
    }

    // Without ctx serial, with it on the host's workers: the same code per bin, the same bytes.
    void run(const fp::Histogram& h, int, const fp::HistogramSummary& whole, fp::Rgb background, float* rgb,
             fp::RenderContext* ctx) const {
        const fp_colourers::LogDensity density(whole.max_hits, gamma_, ctx);
        fp_colourers::for_rows(ctx, h, [&](std::size_t i0, std::size_t i1) {
            for (std::size_t i = i0; i < i1; ++i) {
                const std::uint64_t hits = h.hits_at(i);
                const fp::Rgb c = hits == 0 ? background : table_[index(density(hits))];
                rgb[3 * i] = c.r;
                rgb[3 * i + 1] = c.g;
                rgb[3 * i + 2] = c.b;
            }
        });
    }

    bool finishes() const override { return true; }
    void linear(const fp::Histogram& h, int, const fp::HistogramSummary& whole, double scale, std::size_t i0,
                std::size_t i1, float* out) const override {
        fp_colourers::linear_bins(h, whole, scale, true, i0, i1, out,
                                  [](std::size_t, std::uint64_t) { return fp::Rgb{}; });
    }
    /// The colour of the mean density where hit (density a / coverage), over the background by
    /// the coverage: a colour map is a lookup, not light that adds.
    void display(const float* in, std::size_t n, fp::Rgb background, float* rgb) const override {
        const double inv_gamma = 1.0 / gamma_;
        for (std::size_t i = 0; i < n; ++i) {
            const float* p = in + 5 * i;
            const double cov = p[4];
            const fp::Rgb c = cov > 0 && p[0] > 0
                                  ? table_[index(std::pow(std::min(1.0, p[0] / cov), inv_gamma))]
                                  : background;
            rgb[3 * i] = float(cov * c.r + (1 - cov) * background.r);
            rgb[3 * i + 1] = float(cov * c.g + (1 - cov) * background.g);
            rgb[3 * i + 2] = float(cov * c.b + (1 - cov) * background.b);
        }
    }

    const std::vector<fp::Rgb>& table() const { return table_; }

private:
    // Algorithm 1, with the loop bound and the clamp of t described above.
    void build(const Map& m, std::size_t nc, double e) {
        const std::size_t last = m.ratios.size() - 1;
        auto base = [&](std::size_t j, int ch) { return m.colours[3 * j + std::size_t(ch)] / 255.0; };
        table_.resize(nc);
        std::size_t k = 1;
        for (std::size_t i = 0; i < nc; ++i) {
            const double q = std::pow(double(i) / double(1 + i), e);
            while (k < last && q > m.ratios[k]) ++k;
            const double t = std::clamp((m.ratios[k] - q) / (m.ratios[k] - m.ratios[k - 1]), 0.0, 1.0);
            auto mix = [&](int ch) { return float(t * base(k - 1, ch) + (1 - t) * base(k, ch)); };
            table_[i] = {mix(0), mix(1), mix(2)};
        }
    }

    // Algorithm 3, lines 16-17.
    std::size_t index(double ratio) const {
        const std::size_t last = table_.size() - 1;
        const double v = std::pow(ratio, inv_e_);
        if (!(v < 1)) return last;
        const double f = v / (1 - v);
        return f >= double(last) ? last : std::size_t(f);
    }

    // The index of a float ratio without pow (orbit-trap hits: one per caught sample, 5-20% of a
    // render with pow). index() is a non-decreasing step function of the ratio, so it is the
    // number of thresholds t_k <= ratio, t_k the least float ratio in [0, 1) whose index is >= k
    // (k = 1 .. Nc - 1; 1 where there is none). It is non-decreasing over the floats exactly, not
    // only in exact arithmetic: neighbouring floats differ by at least 2^-24 relatively, so their
    // v = ratio^(1 / E) by about 2^-24 / E, far more than pow's error (< 1 ulp of a double) when
    // E <= 2^20, and v / (1 - v) and the comparisons are monotone. So the count gives exactly
    // pow's index (tests/unit/test_orbit_trap.cpp compares them at and next to every threshold).
    // The count: the bucket b = floor(ratio * 4096) (exact: a power of two) knows how many
    // thresholds lie at or below b / 4096 and below (b + 1) / 4096; a binary search between.
    // Ratios outside [0, 1) or NaN, E > 2^20 and tables over 2^16 entries use pow.
    static constexpr std::size_t buckets = 4096;

    std::size_t index_of(float ratio) const {
        if (thresholds_.empty() || !(ratio >= 0.0f && ratio < 1.0f)) return index(ratio);
        const auto b = std::size_t(ratio * float(buckets));
        // upper_bound in [bucket_[b], bucket_[b + 1]) with one select per step (a cmov): the
        // branches of std::upper_bound mispredict on every other step, most of colour_hits' time.
        const float* t = thresholds_.data();
        const float* base = t + bucket_[b];
        std::size_t len = bucket_[b + 1] - bucket_[b];
        if (len == 0) return bucket_[b];
        while (len > 1) { // the answer lies in [base, base + len]
            const std::size_t half = len / 2;
            base = base[half] <= ratio ? base + half : base;
            len -= half;
        }
        return std::size_t(base - t) + (*base <= ratio ? 1 : 0);
    }

    /// The least float ratio in [0, 1) whose index is >= k, or 1: a bisection on the bits (the
    /// order of non-negative floats), first within 64 floats of the exact value (k / (k + 1))^E.
    float least_ratio(std::size_t k, double e) const {
        auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f); };
        auto at_least = [&](std::uint32_t u) {
            return u >= bits(1.0f) || index(std::bit_cast<float>(u)) >= k;
        };
        std::uint32_t lo = 0, hi = bits(1.0f); // !at_least(lo) unless lo = 0; at_least(hi)
        const std::uint32_t g = bits(std::min(float(std::pow(double(k) / double(k + 1), e)), 1.0f));
        if (g >= 64 && !at_least(g - 64) && at_least(std::min(g + 64, hi)))
            lo = g - 64, hi = std::min(g + 64, hi);
        if (at_least(lo)) return std::bit_cast<float>(lo);
        while (hi - lo > 1) {
            const std::uint32_t mid = lo + (hi - lo) / 2;
            (at_least(mid) ? hi : lo) = mid;
        }
        return std::bit_cast<float>(hi);
    }

    void build_thresholds(double e) {
        const std::size_t last = table_.size() - 1;
        if (e > 1048576.0 || last > 65536) return; // pow for every hit (see index_of)
        thresholds_.resize(last);
        for (std::size_t k = 1; k <= last; ++k) thresholds_[k - 1] = least_ratio(k, e);
        bucket_.resize(buckets + 1);
        for (std::size_t b = 0; b <= buckets; ++b) {
            const float edge = float(b) / float(buckets);
            bucket_[b] = std::uint32_t(std::upper_bound(thresholds_.begin(), thresholds_.end(), edge) -
                                       thresholds_.begin());
        }
        // The search between bucket_[b] and bucket_[b + 1] covers (b / 4096, (b + 1) / 4096].
    }

    double inv_e_, gamma_;
    std::vector<fp::Rgb> table_;
    std::vector<float> thresholds_;     ///< t_1 .. t_{Nc - 1} (empty: pow)
    std::vector<std::uint32_t> bucket_; ///< per bucket edge b / 4096: the thresholds <= it
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<ColourMap>(fp::Kind::Colourer, "colour-map",
                            "Lu et al.'s exponential colour maps (paper 04, Algorithm 1, Table 1), "
                            "coloured by the trap ratio d/r",
                            params)
        .with_example("{preset: fig-4a}"))
