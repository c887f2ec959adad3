// The accumulation buffer of point-plotting renderers.
//
// Integer sums: merging per-worker buffers is exact and independent of the order chains or
// workers are merged in, so the same recipe gives the same bytes on any number of threads.
#pragma once

#include <cstdint>
#include <vector>

namespace fp {

/// Colour sums are in units of 1/colour_scale.
constexpr std::uint64_t colour_scale = 65535;

/// One colour channel in units of 1/colour_scale, as a colour sum adds it: round(c *
/// colour_scale) of c clamped to [0, 1], NaN to 0, in float operations (the same bits as the
/// renderers' vectorised forms, compiled without contraction).
inline std::uint32_t quantise_colour(float c) {
    const float c0 = c > 0.0f ? c : 0.0f;
    const float c1 = c0 < 1.0f ? c0 : 1.0f;
    return std::uint32_t(c1 * float(colour_scale) + 0.5f);
}

struct HistBin {
    std::uint64_t hits = 0, r = 0, g = 0, b = 0;
};

/// The colour last written to a bin (PixelRule::last), in units of 1/colour_scale.
struct LastColour {
    std::uint16_t r = 0, g = 0, b = 0;
};

/// Where a bin's last colour came from: the (step, chain) of its last point, the order that
/// decides which colour is last. A shard's histogram carries it (Histogram::last_order), so
/// that shards merge as ranks do. (Added in ABI 21.)
struct LastOrder {
    std::uint64_t step = 0;
    std::uint32_t chain = 0, pad = 0;
};
/// Whether `a` comes after `b` in the order that decides a bin's last colour.
inline bool later(const LastOrder& a, const LastOrder& b) {
    return a.step > b.step || (a.step == b.step && a.chain > b.chain);
}

struct Histogram {
    int width = 0, height = 0;
    std::vector<HistBin> bins; ///< row-major, top row first
    /// Empty, or (for a colourer whose pixel_rule() is last) one entry per bin: the colour of
    /// the bin's last point in the order (step, chain); meaningful where hits > 0.
    std::vector<LastColour> last;
    /// Hit counts alone, row-major like `bins`: a renderer may fill these instead of `bins`
    /// (which is then empty; every colour sum is 0) for a colourer whose reads_hits_only() is
    /// true. 8 bytes a bin instead of 32: a quarter of the memory, and of the work of filling,
    /// summarising and shading it. Read a bin's hits with hits_at(), the bins' number with
    /// size(): they serve both forms. (Added in ABI 14.)
    std::vector<std::uint64_t> hits;
    /// Empty, or (a shard's histogram with `last`: RenderContext::shard) one entry per bin:
    /// the order of its last colour, by which a merge of shards picks each bin's. (Added in
    /// ABI 21.)
    std::vector<LastOrder> last_order;

    void resize(int w, int h) {
        width = w;
        height = h;
        bins.assign(std::size_t(w) * std::size_t(h), HistBin{});
    }
    /// The number of bins, in whichever form the histogram holds them.
    std::size_t size() const { return hits.empty() ? bins.size() : hits.size(); }
    /// Bin i's hit count, in whichever form the histogram holds them.
    std::uint64_t hits_at(std::size_t i) const { return hits.empty() ? bins[i].hits : hits[i]; }
};

class RenderContext;

/// Unsigned 128-bit integers: sums of hits times positions that no image size overflows.
__extension__ typedef unsigned __int128 uint128;

/// What a colourer reads of a whole histogram besides a bin's own entry: its largest hit
/// count, the hit-weighted sums of the bins' positions (the centre of mass), and each row's
/// first and last column with hits (the hit bin farthest from any point is one of those).
/// Integer sums and maxima: the same summary whether it is added up at once or strip by strip
/// (a render in strips of rows whose histogram never is whole: Colourer::resolve_rows), in any
/// order and on any number of workers. (Added in ABI 11.)
struct HistogramSummary {
    int width = 0, height = 0;
    std::uint64_t max_hits = 0;
    /// Sum of H, of H * column and of H * row over the bins (H: hits; columns and rows from 0).
    uint128 hits = 0, hits_column = 0, hits_row = 0;
    /// Per row: the first and the last column with hits; -1 in both for a row without.
    std::vector<std::int32_t> first, last;
    /// What a bin's hits are as a density of the points drawn over the plane: a bin's hits h are
    /// h * density points per point drawn and per unit of the view's area (1 / (points drawn *
    /// a bin's area): flam3's "samples per unit area", its k2). Set by a renderer that knows
    /// its points and its view (chaos-game), after begin(); 0 where it does not say. add() leaves
    /// it as it is. (Added in ABI 20.)
    double density = 0;

    /// An empty summary of a width x height histogram.
    void begin(int w, int h);
    /// Adds rows [row0, row0 + rows.height) of the histogram, given as `rows` (its width is the
    /// whole one's). With ctx, on its workers (pieces of 16 rows); polls it for a cancel.
    void add(const Histogram& rows, int row0, RenderContext* ctx = nullptr);
    /// The summary of a whole histogram.
    static HistogramSummary of(const Histogram& h, RenderContext* ctx = nullptr) {
        HistogramSummary s;
        s.begin(h.width, h.height);
        s.add(h, 0, ctx);
        return s;
    }
};

} // namespace fp
