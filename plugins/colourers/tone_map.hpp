// Shared by the colourers: the per-chain colour update loop, and tone mapping (histogram
// bins to display pixels).
#pragma once

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace fp_colourers {

/// The body of Colourer::update for colourers whose new colour is f(old, c) per channel (c
/// the channel of the colour of the chain's map). Branch-free, so that the loops vectorise
/// (gathers of the map colours): every load is unconditional, then a blend; a masked-out
/// chain reads map_colours[0] (its own map index need not be valid) and keeps its colour.
/// __restrict on the parameters: GCC ignores it on local pointers.
template <class F>
[[gnu::always_inline]] inline void update_colours(const std::uint32_t* __restrict map, float* __restrict r,
                                                  float* __restrict g, float* __restrict b, std::size_t n,
                                                  const fp::Rgb* __restrict map_colours,
                                                  const unsigned char* __restrict mask, F f) {
    if (!mask) {
        for (std::size_t i = 0; i < n; ++i) {
            const fp::Rgb c = map_colours[map[i]];
            const float r0 = r[i], g0 = g[i], b0 = b[i];
            r[i] = f(r0, c.r);
            g[i] = f(g0, c.g);
            b[i] = f(b0, c.b);
        }
        return;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const bool live = mask[i] != 0;
        const std::uint32_t j = map[i] & (0u - std::uint32_t(live));
        const fp::Rgb c = map_colours[j];
        const float r0 = r[i], g0 = g[i], b0 = b[i];
        r[i] = live ? f(r0, c.r) : r0;
        g[i] = live ? f(g0, c.g) : g0;
        b[i] = live ? f(b0, c.b) : b0;
    }
}

/// The two colour rules (fp::ColourRule) as update_colours' f.
struct TakeMapColour {
    [[gnu::always_inline]] float operator()(float, float c) const { return c; }
};
struct AverageColour {
    [[gnu::always_inline]] float operator()(float old, float c) const { return (old + c) * 0.5f; }
};

/// The log-density shading of paper 02, eq. (28): (log2(1 + h) / log2(1 + max h))^(1/gamma).
/// The values for small h (most bins) come from a table filled once per resolve with the same
/// expression, so they are the same bits, for a fraction of the pow() calls.
/// The shading parameters every density-shaded colourer shares.
constexpr fp::ParamSpec density_param =
    fp::param::string("density", "how hit counts shade the pixels: flat (full colour wherever hit) or log "
                                 "(log-density, paper 02 eq. (28))")
        .def("log")
        .one_of("flat|log");
constexpr fp::ParamSpec gamma_param =
    fp::param::real("gamma", "gamma of the log-density shading (ignored with density: flat)")
        .def("2.2")
        .above(0);

/// Runs f(i0, i1) over the bins [i0, i1) of h: all at once without a context, else in pieces
/// of 16 rows on ctx's workers, polling ctx for a cancel before each piece (one worker too: an
/// 8000 x 8000 image takes a second). The serial and the parallel resolve share the per-bin
/// code, so they write the same bytes; each bin's pixel depends only on that bin and the
/// reductions.
template <class F>
void for_rows(fp::RenderContext* ctx, const fp::Histogram& h, F f) {
    const std::size_t n = h.size(), w = std::size_t(h.width), rows = 16;
    if (!ctx || w == 0) {
        f(std::size_t(0), n);
        return;
    }
    const std::size_t tasks = (std::size_t(h.height) + rows - 1) / rows;
    auto piece = [&](std::size_t t) {
        if (ctx->cancelled()) throw fp::Cancelled();
        f(t * rows * w, std::min(n, (t + 1) * rows * w));
    };
    if (ctx->workers() <= 1)
        for (std::size_t t = 0; t < tasks; ++t) piece(t);
    else
        ctx->parallel_for(tasks, [&](std::size_t t, unsigned) { piece(t); });
}

/// The pixel loop every histogram colourer shares: empty bins take `background`; a bin with
/// hits gets f(i, hits), an array of three unclamped channel values, clamped to [0, 1]. On
/// ctx's workers by rows when ctx is given (the same bytes either way). Either form of the
/// histogram (bins, or hit counts alone), one loop each.
template <class F>
void shade_bins(fp::RenderContext* ctx, const fp::Histogram& h, fp::Rgb background, float* rgb, F f) {
    auto shade = [&](std::size_t i0, std::size_t i1, auto at) {
        for (std::size_t i = i0; i < i1; ++i) {
            const std::uint64_t hits = at(i);
            float* px = rgb + 3 * i;
            if (hits == 0) {
                px[0] = background.r;
                px[1] = background.g;
                px[2] = background.b;
                continue;
            }
            const std::array<double, 3> c = f(i, hits);
            for (int k = 0; k < 3; ++k) px[k] = float(std::clamp(c[k], 0.0, 1.0));
        }
    };
    for_rows(ctx, h, [&](std::size_t i0, std::size_t i1) {
        if (!h.hits.empty())
            shade(i0, i1, [&](std::size_t i) { return h.hits[i]; });
        else
            shade(i0, i1, [&](std::size_t i) { return h.bins[i].hits; });
    });
}

class LogDensity {
public:
    /// With ctx, the table is filled on its workers (the same expression per entry: the same
    /// bits; up to 65537 pow() calls, milliseconds serially).
    LogDensity(std::uint64_t max_hits, double gamma, fp::RenderContext* ctx = nullptr)
        : inv_log_max_(max_hits > 0 ? 1.0 / std::log2(1.0 + double(max_hits)) : 0.0),
          inv_gamma_(1.0 / gamma) {
        table_.resize(std::size_t(std::min<std::uint64_t>(max_hits, table_max)) + 1);
        const std::size_t piece = 4096, n = table_.size();
        if (!ctx || ctx->workers() <= 1 || n <= piece) {
            for (std::size_t h = 0; h < n; ++h) table_[h] = direct(h);
            return;
        }
        ctx->parallel_for((n + piece - 1) / piece, [&](std::size_t t, unsigned) {
            for (std::size_t h = t * piece; h < std::min(n, (t + 1) * piece); ++h) table_[h] = direct(h);
        });
    }
    double operator()(std::uint64_t h) const { return h < table_.size() ? table_[h] : direct(h); }

private:
    static constexpr std::uint64_t table_max = 1u << 16;
    double direct(std::uint64_t h) const {
        return std::pow(std::log2(1.0 + double(h)) * inv_log_max_, inv_gamma_);
    }
    double inv_log_max_, inv_gamma_;
    std::vector<double> table_;
};

/// pixel = clamp(colour of the bin * density^(1/gamma) * brightness, 0, 1), where the colour
/// is the mean of its hits (colour sum / hits / colour_scale), or with `last` the colour
/// written last (Histogram::last / colour_scale, fp::PixelRule::last), and, with
/// `log_density`, density = log2(1 + hits) / log2(1 + max hits) (max over the whole histogram) (paper 02, eq.
/// (28)); otherwise density = 1. Empty bins take `background`. Fixed order, no state: the same histogram
/// gives the same bytes. With ctx, on its workers (rows in parallel; the same bytes).
inline void tone_map(const fp::Histogram& h, const fp::HistogramSummary& whole, fp::Rgb background,
                     float* rgb, bool log_density, double gamma, double brightness, bool last,
                     fp::RenderContext* ctx) {
    if (last && h.last.size() != h.bins.size())
        throw fp::InternalError("the renderer gave no last colours for a colourer whose pixel rule is last");
    const LogDensity density(log_density ? whole.max_hits : 0, gamma, ctx);
    shade_bins(ctx, h, background, rgb, [&](std::size_t i, std::uint64_t hits) {
        if (last) {
            const fp::LastColour& c = h.last[i];
            double k = brightness / double(fp::colour_scale);
            if (log_density) k *= density(hits);
            return std::array<double, 3>{double(c.r) * k, double(c.g) * k, double(c.b) * k};
        }
        const fp::HistBin& b = h.bins[i];
        double k = brightness / (double(hits) * double(fp::colour_scale));
        if (log_density) k *= density(hits);
        return std::array<double, 3>{double(b.r) * k, double(b.g) * k, double(b.b) * k};
    });
}

/// The three resolve entry points of a colourer whose work is one function
/// `run(rows, row0, whole, background, rgb, ctx)` (rows: the histogram's rows from row0; whole:
/// the whole histogram's summary; ctx null: serial), so that resolve(), resolve_parallel() and
/// resolve_rows() are the same code and give the same bytes by construction: a whole
/// histogram is its own rows from 0, with its own summary.
template <class Derived>
class Resolving : public fp::Colourer {
public:
    void resolve(const fp::Histogram& h, fp::Rgb background, float* rgb) const final {
        static_cast<const Derived&>(*this).run(h, 0, fp::HistogramSummary::of(h), background, rgb, nullptr);
    }
    void resolve_parallel(const fp::Histogram& h, fp::Rgb background, float* rgb,
                          fp::RenderContext& ctx) const final {
        static_cast<const Derived&>(*this).run(h, 0, fp::HistogramSummary::of(h, &ctx), background, rgb,
                                               &ctx);
    }
    bool resolves_rows() const final { return true; }
    void resolve_rows(const fp::Histogram& rows, int row0, const fp::HistogramSummary& whole,
                      fp::Rgb background, float* rgb, fp::RenderContext& ctx) const final {
        if (rows.width != whole.width || row0 < 0 || row0 + rows.height > whole.height)
            throw fp::InternalError("resolve_rows: rows outside the summarised histogram");
        static_cast<const Derived&>(*this).run(rows, row0, whole, background, rgb, &ctx);
    }
};

} // namespace fp_colourers
