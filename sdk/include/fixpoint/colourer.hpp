// Colourer: how a point-plotting renderer colours what it draws.
//
// Each chain carries a colour (paper 01: the colour of the map that produced the point;
// paper 02 Sec. 5: the running colour c = (c + c_j)/2). The renderer deposits it into a
// Histogram; the colourer then turns the histogram into an image (tone mapping).
#pragma once

#include <fixpoint/histogram.hpp>
#include <fixpoint/object.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <cstdint>

namespace fp {

class RenderContext; // render.hpp

/// Per-chain colours, structure of arrays.
struct ColourState {
    float* r = nullptr;
    float* g = nullptr;
    float* b = nullptr;
    std::size_t n = 0;
    // With a colourer whose palette_index() is true (added in ABI 18): each chain's palette index
    // (flam3's p[2]), and each map's `color` and `color_speed` (flam3's), by map; else null.
    float* index = nullptr;
    const float* map_index = nullptr;
    const float* map_speed = nullptr;
};

/// A chain's colour update that a renderer may run in its own loop instead of calling
/// update() (chaos-game's fused step does). The contract is exact, in float: with c_j the
/// colour of the map that moved the chain,
///   map:     c' = c_j                 (each point the colour of its map, paper 01);
///   average: c' = (c + c_j) * 0.5f    (the running colour of paper 02 Sec. 5).
enum class ColourRule : std::uint32_t { none, map, average };

/// What a pixel shows of the colours its points carried.
///   mean: the mean colour of its hits (Histogram::bins' colour sums): independent of the
///         order of the points, the default;
///   last: the colour written last (Histogram::last), paper 02's Algorithm 2 as written
///         ("I(x, y) = c"). Points have no time order across chains, so "last" is the largest
///         (step, chain) of the points in the bin: the order one chain (the paper's single
///         orbit) writes in, and one that no thread count changes. A renderer that honours it
///         also runs the algorithm's colour as written: each chain starts with a random colour
///         and update() changes it only with the points the chain plots (line 16 of the
///         algorithm sits under "if i > 20"). A renderer that cannot fill Histogram::last
///         refuses such a colourer when it is built.
enum class PixelRule : std::uint32_t { mean, last };

class Colourer : public Object {
public:
    ~Colourer() override;

    /// After a step in which chain i moved by map `map[i]` (colour map_colours[map[i]]),
    /// update its colour. Masked-out chains keep theirs.
    virtual void update(const std::uint32_t* map, ColourState s, const Rgb* map_colours,
                        const unsigned char* mask) const = 0;

    /// Turn the histogram into RGB pixels (3 floats per pixel, row-major, top row first,
    /// display values in [0, 1]). Empty bins take `background`.
    virtual void resolve(const Histogram& h, Rgb background, float* rgb) const = 0;

    /// resolve() with its work spread over the host's workers (rows in parallel): the same
    /// bytes for any number of workers (maximum and integer reductions are exact, each pixel
    /// depends only on its bin and those reductions). Renderers call this one: a serial
    /// resolve of a megapixel image is milliseconds that do not scale with the threads.
    /// The default calls resolve().
    virtual void resolve_parallel(const Histogram& h, Rgb background, float* rgb, RenderContext& ctx) const;

    /// Whether resolve_rows works. A renderer that renders in strips of rows (an image whose
    /// histogram does not fit in memory) asks before it starts, and refuses a colourer that
    /// cannot. The default is false. (Added in ABI 11.)
    virtual bool resolves_rows() const;
    /// Rows [row0, row0 + rows.height) of an image (rows: their histogram, of the image's
    /// width), shaded as resolve_parallel would shade them in the whole histogram, given that
    /// histogram's summary `whole` (HistogramSummary): the same bytes, row for row. rgb takes
    /// the rows' pixels. The default throws fp::Error.
    virtual void resolve_rows(const Histogram& rows, int row0, const HistogramSummary& whole, Rgb background,
                              float* rgb, RenderContext& ctx) const;

    /// False when resolve() reads only the hit counts of the histogram (its colour sums may
    /// all be 0): a renderer may then skip update() and the colour sums altogether and count
    /// hits only. The default is true.
    virtual bool needs_colour() const;
    /// True when resolve(), resolve_parallel() and resolve_rows() read the hit counts through
    /// Histogram::hits_at() and size() alone (so needs_colour() is false): a renderer may then
    /// give them a histogram of hit counts alone (Histogram::hits, `bins` empty). The default
    /// is false: a colourer that reads `bins` gets `bins`. (Added in ABI 14.)
    virtual bool reads_hits_only() const;
    /// update() as a ColourRule, when it is one (the conformance suite checks the promise bit
    /// for bit); the default is none.
    virtual ColourRule colour_rule() const;
    /// Whether resolve() reads the mean colours or the last ones (PixelRule); the default is
    /// mean.
    virtual PixelRule pixel_rule() const;

    /// The finishing stage (fixpoint/finish.hpp), for a renderer that supersamples, filters
    /// or density-estimates its histogram: true when linear() and display() work. The default
    /// is false, and such a renderer refuses the colourer. (Added in ABI 17.)
    virtual bool finishes() const;
    /// Bins [i0, i1) of `rows` (rows row0, ... of the histogram that `whole` summarises), 4
    /// floats a bin: its density a in [0, 1] (0 for a bin without hits) and its colour (r, g,
    /// b), before any filter, with each bin's hits read as `scale` times its own (supersampled
    /// bins: scale = N^2, the hits of an image pixel). The default throws fp::Error.
    virtual void linear(const Histogram& rows, int row0, const HistogramSummary& whole, double scale,
                        std::size_t i0, std::size_t i1, float* out) const;
    /// n pixels from their filtered channels, 5 floats each: density a, colour (r, g, b) (the
    /// density-weighted mean of the bins' colours), coverage in [0, 1] (the filtered share of
    /// bins with hits); writes 3 floats each, display values in [0, 1], over `background`. The
    /// default throws fp::Error.
    virtual void display(const float* in, std::size_t n, Rgb background, float* rgb) const;

    /// True when the chains carry a palette index (ColourState::index, from a random start in
    /// [0, 1)) that update() blends toward the map's `color` by its `color_speed`, flam3's rule
    /// (i' = s c_j + (1 - s) i), and turns into the chain's colour through the colourer's
    /// palette (fixpoint/palette.hpp). The default is false. (Added in ABI 18.)
    virtual bool palette_index() const;

    /// True when the colourer can colour orbit-trap hits (colour_hits); the default is false,
    /// and an orbit-trap renderer refuses such a colourer when it is built.
    virtual bool colours_trap_hits() const;

    /// Orbit traps (paper 04): for each of n samples, trap[i] is the index of the trap that
    /// caught the orbit (-1: never trapped), ratio[i] = d / r at the catch, in [0, 1), and
    /// iteration[i] the step (from 1) at which it was caught. Writes 3 floats per sample to
    /// rgb; never-trapped samples get *background, or the colourer's own choice when it is null
    /// (paper 04's Algorithm 3: the last colour of the table). Called per batch, never per point.
    virtual void colour_hits(const std::int32_t* trap, const float* ratio, const std::uint32_t* iteration,
                             std::size_t n, const Rgb* background, float* rgb) const;
};

} // namespace fp
