// The conformance checks of colourers (conformance_detail.hpp).
#include "conformance_detail.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp::host::detail {

namespace {

// ------------------------------------------------------------------ Colourer
// Rows [row0, row0 + n) of h (n clipped to its height) as a histogram of their own, in h's form
// (bins, last colours, or hit counts alone).
Histogram rows_of(const Histogram& h, int row0, int n) {
    Histogram part;
    part.width = h.width;
    part.height = std::min(n, h.height - row0);
    const auto b0 = std::ptrdiff_t(row0) * h.width, nb = std::ptrdiff_t(part.height) * h.width;
    auto cut = [&](const auto& from, auto& to) {
        if (!from.empty()) to.assign(from.begin() + b0, from.begin() + b0 + nb);
    };
    cut(h.bins, part.bins);
    cut(h.last, part.last);
    cut(h.hits, part.hits);
    return part;
}

// h shaded as a render in strips of `strip` rows shades it: the strips summarised one after
// another, then each shaded with resolve_rows() (on 2 workers) into its rows of rgb.
void resolve_in_strips(const Colourer& c, const Histogram& h, int strip, Rgb background, float* rgb) {
    HistogramSummary whole;
    whole.begin(h.width, h.height);
    for (int row0 = 0; row0 < h.height; row0 += strip) whole.add(rows_of(h, row0, strip), row0);
    Runtime rt(2, nullptr);
    for (int row0 = 0; row0 < h.height; row0 += strip)
        c.resolve_rows(rows_of(h, row0, strip), row0, whole, background,
                       rgb + 3 * std::size_t(row0) * std::size_t(h.width), rt);
}

// A colourer whose reads_hits_only() is true may be given hit counts alone (Histogram::hits,
// `bins` empty): each resolve entry point must then give the pixels of the same bins with
// their colour sums 0.
void check_hits_only(const Colourer& c, const Histogram& big, Findings& f) {
    if (c.needs_colour()) {
        f.push_back("colourer: reads_hits_only() is true but needs_colour() too");
        return;
    }
    Histogram zero = big, alone;
    for (HistBin& b : zero.bins) b.r = b.g = b.b = 0;
    alone.width = big.width;
    alone.height = big.height;
    for (const HistBin& b : big.bins) alone.hits.push_back(b.hits);
    const Rgb bg{0.1f, 0.2f, 0.3f};
    std::vector<float> want(big.bins.size() * 3), got(want.size());
    c.resolve(zero, bg, want.data());
    auto differs = [&] { return std::memcmp(want.data(), got.data(), want.size() * sizeof(float)) != 0; };
    c.resolve(alone, bg, got.data());
    if (differs()) {
        f.push_back("colourer: resolve() of hit counts alone differs from resolve() of the bins");
        return;
    }
    Runtime rt(2, nullptr);
    c.resolve_parallel(alone, bg, got.data(), rt);
    if (differs()) {
        f.push_back("colourer: resolve_parallel() of hit counts alone differs from resolve() of the bins");
        return;
    }
    if (!c.resolves_rows()) return;
    resolve_in_strips(c, alone, 7, bg, got.data());
    if (differs())
        f.push_back("colourer: resolve_rows() of hit counts alone differs from resolve() of the bins");
}

// Orbit-trap colouring (paper 04): batch == point by point, values in [0, 1], untrapped samples
// take the given background exactly, the same on two threads.
void check_trap_colours(const Colourer& c, Findings& f) {
    constexpr std::size_t n = 301;
    Sampler smp;
    std::vector<std::int32_t> trap(n);
    std::vector<float> ratio(n);
    std::vector<std::uint32_t> it(n);
    for (std::size_t i = 0; i < n; ++i) {
        trap[i] = std::int32_t(i % 5) - 1;
        ratio[i] = i % 7 == 0 ? 0.0f : float(smp.in(0, 1));
        if (ratio[i] >= 1) ratio[i] = 0.5f;
        it[i] = std::uint32_t(1 + i % 100);
    }
    const Rgb bg{0.1f, 0.2f, 0.3f};
    auto batch = [&](const Rgb* background) {
        std::vector<float> rgb(3 * n, -1.0f);
        c.colour_hits(trap.data(), ratio.data(), it.data(), n, background, rgb.data());
        return rgb;
    };
    const auto all = batch(&bg), own = batch(nullptr);
    std::vector<float> one(3 * n);
    for (std::size_t i = 0; i < n; ++i) c.colour_hits(&trap[i], &ratio[i], &it[i], 1, &bg, &one[3 * i]);
    if (all != one) f.push_back("colourer: colour_hits() on a batch differs from point-by-point");
    std::size_t bad = 0, background = 0;
    for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) bad += !(all[3 * i + k] >= 0 && all[3 * i + k] <= 1);
        for (int k = 0; k < 3; ++k) bad += !(own[3 * i + k] >= 0 && own[3 * i + k] <= 1);
        if (trap[i] < 0)
            background += !(all[3 * i] == bg.r && all[3 * i + 1] == bg.g && all[3 * i + 2] == bg.b);
    }
    if (bad) f.push_back("colourer: colour_hits() gives values outside [0, 1]");
    if (background) f.push_back("colourer: colour_hits() does not give untrapped samples the background");
    if (!same_on_two_threads([&] { return batch(&bg); }))
        f.push_back("colourer: colour_hits() differs when evaluated from two threads at once");
}

} // namespace

void check_colourer(const Colourer& c, Findings& f) {
    constexpr std::size_t n = 257;
    const Rgb maps[3] = {{1, 0, 0}, {0, 1, 0}, {0.2f, 0.3f, 1}};
    Sampler smp;
    std::vector<std::uint32_t> idx(n);
    std::vector<float> r0(n), g0(n), b0(n);
    for (std::size_t i = 0; i < n; ++i) {
        idx[i] = std::uint32_t(i % 3);
        r0[i] = float(smp.in(0, 1)), g0[i] = float(smp.in(0, 1)), b0[i] = float(smp.in(0, 1));
    }
    auto batch = [&] {
        std::vector<float> r = r0, g = g0, b = b0;
        c.update(idx.data(), {r.data(), g.data(), b.data(), n}, maps, nullptr);
        r.insert(r.end(), g.begin(), g.end());
        r.insert(r.end(), b.begin(), b.end());
        return r;
    };
    const auto all = batch();
    std::vector<float> one(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        float r = r0[i], g = g0[i], b = b0[i];
        c.update(&idx[i], {&r, &g, &b, 1}, maps, nullptr);
        one[i] = r, one[n + i] = g, one[2 * n + i] = b;
    }
    if (all != one) f.push_back("colourer: update() on a batch differs from point-by-point");
    if (const ColourRule rule = c.colour_rule(); rule != ColourRule::none) {
        // The promise of colour_rule(), bit for bit (renderers apply the rule themselves).
        std::size_t bad = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const Rgb m = maps[idx[i]];
            const float e[3] = {rule == ColourRule::map ? m.r : (r0[i] + m.r) * 0.5f,
                                rule == ColourRule::map ? m.g : (g0[i] + m.g) * 0.5f,
                                rule == ColourRule::map ? m.b : (b0[i] + m.b) * 0.5f};
            for (int ch = 0; ch < 3; ++ch) bad += std::memcmp(&e[ch], &all[ch * n + i], sizeof(float)) != 0;
        }
        if (rule != ColourRule::map && rule != ColourRule::average)
            f.push_back("colourer: colour_rule() reports an unknown rule");
        else if (bad)
            f.push_back("colourer: colour_rule() promises " +
                        std::string(rule == ColourRule::map ? "the map's colour" : "the running average") +
                        ", but update() differs from it in " + std::to_string(bad) + " of " +
                        std::to_string(3 * n) + " values");
    }
    if (!same_on_two_threads(batch))
        f.push_back("colourer: results differ when evaluated from two threads at once");
    Histogram h;
    h.resize(16, 16);
    for (std::size_t i = 0; i < h.bins.size(); ++i) {
        const std::uint64_t hits = i % 5 == 0 ? 0 : 1 + (i * 7919) % 1000;
        h.bins[i] = {hits, hits * (i % 3 == 0 ? colour_scale : 0), hits * colour_scale / 2,
                     hits * colour_scale / 4};
    }
    auto resolve = [&] {
        std::vector<float> px(h.bins.size() * 3);
        c.resolve(h, Rgb{0.1f, 0.2f, 0.3f}, px.data());
        return px;
    };
    const auto px = resolve();
    std::size_t bad = 0;
    for (float v : px) bad += !(v >= 0 && v <= 1);
    if (bad) f.push_back("colourer: resolve() gives values outside [0, 1]");
    if (px[0] != 0.1f || px[1] != 0.2f || px[2] != 0.3f)
        f.push_back("colourer: an empty bin does not take the background");
    if (!same_on_two_threads(resolve))
        f.push_back("colourer: resolve() differs when evaluated from two threads at once");
    {
        // Renderers call resolve_parallel(): it must give resolve()'s bytes on any number of
        // workers. 53 rows: several pieces of rows, the last one short.
        Histogram big;
        big.resize(37, 53);
        for (std::size_t i = 0; i < big.bins.size(); ++i) {
            const std::uint64_t hits = i % 7 == 0 ? 0 : 1 + (i * 104729) % 70000;
            big.bins[i] = {hits, hits * (i % 2 ? colour_scale : colour_scale / 3), hits * colour_scale / 5,
                           0};
        }
        std::vector<float> serial(big.bins.size() * 3), par(big.bins.size() * 3);
        c.resolve(big, Rgb{0.1f, 0.2f, 0.3f}, serial.data());
        for (unsigned threads : {1u, 2u, 3u}) {
            Runtime rt(threads, nullptr);
            c.resolve_parallel(big, Rgb{0.1f, 0.2f, 0.3f}, par.data(), rt);
            if (std::memcmp(serial.data(), par.data(), serial.size() * sizeof(float)) != 0) {
                f.push_back("colourer: resolve_parallel() with " + std::to_string(threads) + " worker" +
                            (threads == 1 ? "" : "s") + " differs from resolve()");
                break;
            }
        }
        // A render in strips (a histogram too large for memory) summarises the strips one after
        // another, then shades each with resolve_rows(): resolve()'s bytes, row for row.
        if (c.resolves_rows()) {
            for (int strip : {1, 7, 20}) {
                resolve_in_strips(c, big, strip, Rgb{0.1f, 0.2f, 0.3f}, par.data());
                if (std::memcmp(serial.data(), par.data(), serial.size() * sizeof(float)) != 0) {
                    f.push_back("colourer: resolve_rows() in strips of " + std::to_string(strip) +
                                " row(s) differs from resolve()");
                    break;
                }
            }
        }
        if (c.reads_hits_only()) check_hits_only(c, big, f);
    }
    if (c.colours_trap_hits()) check_trap_colours(c, f);
}

} // namespace fp::host::detail
