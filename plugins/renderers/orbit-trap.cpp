// orbit-trap: the modified orbit trap method of paper 04 (Algorithm 3; Lu et al.'s Algorithm 2
// with the Picard step replaced by any iteration scheme and the circles by any Trap).
//
// What it computes
// ----------------
// For every pixel sample p_0, iterate p_{k+1} = S(p_k) reduced mod 2 pi, k = 0 .. M - 1, where
// S is one step of `iteration` (default Picard: p <- f(p); the S-iteration of eq. (13) is
// `{type: s-iteration, numbers: {type: complex}, alpha: [1.1, 0.5], beta: [0.5, 0]}`, whose
// product is the complex one: eq. (12)'s second component "x1 y2 + y1 x1" is a misprint for
// x1 y2 + y1 x2) and f the `mapping`. After every step the traps are tested; the first step
// whose point some trap holds stops the orbit, and the colourer colours the sample by that trap's
// ratio d / r (colour-map: Algorithm 3, lines 16-17). A sample never trapped takes `background`,
// or the colourer's own colour when there is none (colour-map: the last colour of its table,
// line 21). The pixel is the mean of its samples.
//
// The reduction (`reduction`, after every scheme step): eq. (13) reduces the S-iteration's
// combination mod 2 pi again, since (1 - alpha) f(p) + alpha f(u) leaves the period cell. The
// default is C's fmod (symmetric about 0; the wallpaper transform's default too): a floor-based
// mod into [0, 2 pi) makes the traps at negative coordinates unreachable and breaks the
// symmetry. For Picard the step's own reduction already did it, and fmod / centred are
// idempotent (exactly: orbit-trap/reduce.hpp). `none` for maps that are not periodic.
// `hexagonal` (x and y together, into the hexagon about 0 modulo the hexagonal lattice of periods
// of p3 ... p6m; the wallpaper transform's `reduction: hexagonal`, the same function) keeps the
// 3- and 6-fold rotations of those maps exact (orbit-trap/reduce.hpp); with Picard give it to the
// mapping (which then leaves nothing to do here), with another scheme to both. The renderer
// does not know the mapping's lattice: it is the recipe's choice (a square-lattice map reduced
// on the hexagonal lattice is simply another map).
//
// Pixel coordinates
// -----------------
// As Algorithm 3 (pixel 0 at xmin, pixel W - 1 at xmax, y flipped), in a form exactly symmetric
// about the area's centre: sample (dx, dy) of pixel (i, j) (offsets in pixels) is at
//     x0 = cx + hx (((2 i - (W - 1)) + 2 dx) * (1 / (W - 1))),
//     y0 = cy - hy (((2 j - (H - 1)) + 2 dy) * (1 / (H - 1)))
// with (cx, cy) the centre and (hx, hy) the half sizes of the area, in double, then rounded to
// the lanes' precision. So for an area centred at 0, the mirrored pixel's mirrored sample is
// exactly the negated point, and for a square area with W = H the transposed one exactly the
// swapped point. (W = 1 or H = 1: that axis is sampled at the centre.)
//
// Bands (an image over the memory budget: `fixpoint render --memory`, Renderer::render_rows)
// ------------------------------------------------------------------------------------------
// The image is streamed to the output by bands of rows, each rendered by the tiles that cover
// it (as render() cuts and deals them, so the same pixels) into a buffer of the band alone:
// memory is the band and the workers' batches, whatever the image's size. A tile that straddles
// two bands is rendered in both (the same values); its stats count once.
//
// Tiles (`tile: true`, `fixpoint render --tile`)
// ----------------------------------------------
// The pattern is periodic when the map is (Transform::periods(): the wallpaper maps, with the
// lattice 2 pi Z^2 for the square groups and 2 pi Z (1, 0) + 2 pi Z (1/2, sqrt(3)/2) for the
// hexagonal ones) and the iteration is Picard: the traps are tested after each step, never on
// the start point p_0 itself, so a sample's colour depends on p_0 only through f(p_0), and
// f(p_0 + t) = f(p_0) for a period t (the reductions act on f's output only). Under any other
// scheme a step also uses p_0 itself (the S-iteration's (1 - beta) p + beta f(p), Mann's
// (1 - alpha) p + alpha f(p)), a translation by a period survives the first step, and the
// pattern is not periodic: `tile` refuses it, as it refuses a map without periods.
// With `tile`, the area is replaced by the smallest rectangle of periods (2 pi x 2 pi, or
// 2 pi x 2 pi sqrt(3) for the hexagonal groups) centred on the area's centre (the default area
// gives [-pi, pi)^2 and [-pi, pi) x [-pi sqrt 3, pi sqrt 3)), and the height by
// round(W * cell height / cell width), so that pixels are square (to within 1 / (2 H) for the
// hexagonal cell, whose sides are incommensurable). The pixels then divide the cell exactly:
// pixel (i, j)'s sample (dx, dy) is at
//     x0 = cx + (w / 2) (((2 i - (W - 1)) + 2 dx) * (1 / W)),  (xmin + (i + 1/2 + dx) w / W)
// and y0 likewise (y flipped), the formula above with 1 / W for 1 / (W - 1): the pixel centres
// lie half a pixel inside the cell's edges, so that pixel W would be pixel 0 one period on,
// and copies of the image join without a seam (tests/cli/test_tile.cpp). In floating point
// f(p_0 + t) and f(p_0) differ by rounding, which chaotic orbits can grow: the join matches
// as closely as two renders of the same pattern at slightly different start points do.
//
// Samples: 1 is the pixel's own point (as the paper's algorithm); 8 is the pattern
// (+-1/8, +-3/8), (+-3/8, +-1/8) (eight rooks, one per row and column of an 8 x 8 grid of the
// pixel); s^2 (4, 9, 16, ...) a centred s x s grid. Each pattern is closed under the square's
// eight symmetries, and a pixel's colour is the mean of its samples' colours summed in
// integers (each channel rounded to 24 fractional bits), so the sum does not depend on the
// order: symmetric patterns render to symmetric images with supersampling too. Other counts are
// refused.
//
// Performance
// -----------
// Tiles of consecutive pixels (about 1024 samples each: the batch's arrays stay in L1) over
// RenderContext::parallel_for; a tile's samples form one batch (structure of arrays, sample-major:
// sample q of the tile's pixel p is lane q * np + p, so the start points and the means are vector
// loops) that all start together, so every lane of the batch is at the same step k (a scheme's
// parameter sequences are indexed by k, so lanes at different steps could not share a call).
// Per step: one IterationScheme::step call on the batch (which calls the transform per chunk),
// then
//   - with a known trap (Trap::kernel(): circles of the Euclidean metric, TrapKernel), one fused
//     pass over the batch, 16 lanes at a time (AVX-512 intrinsics for float lanes, plain code
//     otherwise): the reduction's range check (the whole batch is reduced first while a step
//     leaves values outside the range, as the S-iteration does; after Picard with a map that
//     reduces itself nothing is), the trap test inline, the caught lanes recorded (scatters) and
//     the survivors compacted (compress stores). No virtual call, no per-circle key array.
//   - otherwise: the reduction (a vectorised scan first: values already in range are left alone),
//     one Trap::test call, then the caught samples recorded and the survivors compacted.
// Both give the same bytes (tests/unit/test_orbit_trap.cpp: FusedAndGeneralPassesAreAlgorithm3
// checks them against Algorithm 3 written out point by point through the plugins' interfaces).
// The next step works on live lanes only: no idle lanes and no masks, and the work is the sum of
// the samples' iteration counts plus a constant per step. Lanes are not refilled with new samples
// (that would mix step indices); the cost of the shrinking batch is only the per-call overhead of
// its last steps. bench/README.md has the figures.
// Scratch space is per worker, allocated before the render; nothing is allocated, looked up or
// logged per point. Cancellation is polled per tile, progress reported per tile (units: pixels).
//
// Determinism: a sample's orbit depends only on its own start point, and a pixel's colour on its
// samples (summed in integers), so the image is the same on any number of threads and with any
// tiling.
//
// RenderStats: samples = pixel samples, drawn = the samples some trap caught (the CLI refuses a
// render where none was caught), bad_values = samples whose orbit ended on NaN or infinity;
// unit "pixel samples".
//
// Errors (ParamError): "area": "the area must be [xmin, xmax, ymin, ymax] with xmin < xmax" (or
// ymin < ymax); "samples": "expected 1, 8 or a square number (4, 9, 16, ...) of samples: patterns
// closed under the square's symmetries, got 3"; "colourer": "this colourer cannot colour
// orbit-trap hits (use colour-map)"; "height": the image is too large; "tile": the mapping
// has no periods, or the iteration is not Picard (see Tiles), or the tile is too large.
#include "orbit-trap/batch.hpp"
#include "orbit-trap/reduce.hpp"
#include "orbit-trap/renderer.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace fp_orbit_trap {
namespace {

// The sample pattern for `n` samples, or empty when n is not a supported count.
std::vector<Offset> pattern(int64_t n) {
    if (n == 1) return {{0, 0}};
    if (n == 8) {
        const double a = 0.125, b = 0.375;
        return {{-b, -a}, {-a, b}, {a, -b}, {b, a}, {-b, a}, {-a, -b}, {a, b}, {b, -a}};
    }
    const auto s = int64_t(std::llround(std::sqrt(double(n))));
    if (s * s != n) return {};
    std::vector<Offset> out;
    for (int64_t j = 0; j < s; ++j)
        for (int64_t i = 0; i < s; ++i)
            out.push_back({double(2 * i + 1 - s) / double(2 * s), double(2 * j + 1 - s) / double(2 * s)});
    return out;
}

} // namespace

OrbitTrap::OrbitTrap(const fp::ParamBag& p) {
    frame_ = fp::Frame::read(p, "area");
    const fp::Box& a = frame_.region;
    cx_ = (a.xmin + a.xmax) / 2, hx_ = (a.xmax - a.xmin) / 2;
    cy_ = (a.ymin + a.ymax) / 2, hy_ = (a.ymax - a.ymin) / 2;
    max_iterations_ = uint32_t(p.integer("max_iterations"));
    const auto n = p.integer("samples");
    offsets_ = pattern(n);
    if (offsets_.empty())
        throw fp::ParamError("samples",
                             "expected 1, 8 or a square number (4, 9, 16, ...) of samples: patterns "
                             "closed under the square's symmetries, got " +
                                 std::to_string(n));
    tile_pixels_ = std::max<size_t>(1, tile_samples / offsets_.size());
    mapping_ = p.object<fp::Transform>("mapping");
    if (const std::string why = mapping_->plane_map_problem(); !why.empty())
        throw fp::ParamError("mapping", why);
    iteration_ = p.object<fp::IterationScheme>("iteration");
    traps_ = p.object<fp::Trap>("traps");
    if (const fp::TrapKernel k = traps_->kernel(); k.kind == fp::TrapKernel::Kind::euclidean_circles) {
        known_trap_ = true;
        for (size_t i = 0; i < k.n; ++i) {
            circles_f_.cx.push_back(float(k.cx[i])), circles_f_.cy.push_back(float(k.cy[i]));
            circles_f_.key.push_back(k.key_f[i]), circles_f_.r.push_back(float(k.r[i]));
            circles_d_.cx.push_back(k.cx[i]), circles_d_.cy.push_back(k.cy[i]);
            circles_d_.key.push_back(k.key_d[i]), circles_d_.r.push_back(k.r[i]);
        }
    }
    colourer_ = p.object<fp::Colourer>("colourer");
    if (!colourer_->colours_trap_hits())
        throw fp::ParamError("colourer", "this colourer cannot colour orbit-trap hits (use colour-map)");
    reduction_ = fp::kernels::reduction_named(p.string("reduction"));
    double_ = p.string("precision") == "double";
    iteration_->check_steps(*mapping_, max_iterations_);
    iw_ = 1.0 / double(std::max(frame_.width - 1, 1)), ih_ = 1.0 / double(std::max(frame_.height - 1, 1));
    if (p.boolean("tile")) set_tile();
}

// `tile`: one rectangular period centred on the area's centre, square pixels (see Tiles).
void OrbitTrap::set_tile() {
    const std::optional<fp::PeriodLattice> cell = mapping_->periods();
    if (!cell || !(cell->width > 0) || !(cell->height > 0))
        throw fp::ParamError("tile", "the mapping is not periodic, so its pattern has no tile (the wallpaper "
                                     "maps are)");
    if (!iteration_->is_picard())
        throw fp::ParamError("tile", "the pattern is periodic only under the Picard iteration: a step of "
                                     "this iteration also uses the point itself, so a translation by a "
                                     "period does not cancel");
    const double h = std::max(1.0, std::round(double(frame_.width) * cell->height / cell->width));
    if (h > 65536)
        throw fp::ParamError("tile", "the tile would be " + std::to_string(frame_.width) + "x" +
                                         std::to_string(std::int64_t(h)) +
                                         " pixels, taller than 65536: give a smaller width");
    if (double(frame_.width) * h >= 4294967295.0)
        throw fp::ParamError("tile", "the tile is too large: width * height must be below 4294967295 pixels");
    frame_.height = int(h);
    hx_ = cell->width / 2, hy_ = cell->height / 2;
    frame_.region = {cx_ - hx_, cx_ + hx_, cy_ - hy_, cy_ + hy_};
    iw_ = 1.0 / double(frame_.width), ih_ = 1.0 / double(frame_.height);
}

uint64_t OrbitTrap::scratch_bytes(unsigned workers) const {
    const uint64_t per_sample = 3 * (double_ ? 8 : 4) + 4 * 4 + 4 + 4 * 3 + 4 * 3 + 8 * 3 + 8 * 2;
    return uint64_t(std::max(1u, workers)) * tile_samples * per_sample;
}

uint64_t OrbitTrap::memory_bytes(unsigned workers) const {
    const uint64_t image = uint64_t(frame_.width) * uint64_t(frame_.height) * 3 * sizeof(float);
    return image + scratch_bytes(workers);
}

// A band's buffer: its rows, plus the parts of the tiles at its two ends that stick out of it.
size_t OrbitTrap::band_rows(unsigned workers, uint64_t budget) const {
    const uint64_t row = uint64_t(frame_.width) * 3 * sizeof(float);
    const uint64_t fixed = scratch_bytes(workers) + 2 * uint64_t(tile_pixels_) * 3 * sizeof(float);
    if (budget < fixed + row) return 0;
    return size_t(std::min<uint64_t>(uint64_t(frame_.height), (budget - fixed) / row));
}

uint64_t OrbitTrap::memory_within(unsigned workers, uint64_t budget) const {
    const size_t rows = std::max<size_t>(1, band_rows(workers, budget));
    return scratch_bytes(workers) +
           (uint64_t(rows) * uint64_t(frame_.width) + 2 * uint64_t(tile_pixels_)) * 3 * sizeof(float);
}

} // namespace fp_orbit_trap

namespace {

constexpr fp::ParamSpec params[] = {
    fp::param::integer("width", "image width W in pixels").def("512").min(1).max(65536),
    fp::param::integer("height", "image height H in pixels").def("512").min(1).max(65536),
    fp::param::reals("area", "the drawn area [xmin, xmax, ymin, ymax] (pixel 0 at xmin, pixel W - 1 at xmax; "
                             "default the paper's [-2 pi, 2 pi]^2)")
        .def("[-6.283185307179586, 6.283185307179586, -6.283185307179586, 6.283185307179586]")
        .len(4),
    fp::param::integer("max_iterations", "M: the most steps of an orbit").def("100").min(1).max(100000000),
    fp::param::integer("samples",
                       "samples per pixel: 1 (the pixel's point), 8 (the paper's count) or a square "
                       "number, on fixed patterns closed under the square's symmetries")
        .def("8")
        .min(1)
        .max(1024)
        .as(fp::ParamRole::samples),
    fp::param::object("mapping", fp::Kind::Transform,
                      "the map f iterated (a wallpaper map for paper 04's patterns)"),
    fp::param::object(
        "iteration", fp::Kind::IterationScheme,
        "the iteration process replacing p <- f(p) (eq. (13): s-iteration with complex numbers)")
        .def("{type: picard}"),
    fp::param::object("traps", fp::Kind::Trap, "the orbit traps (circles of a metric)"),
    fp::param::object("colourer", fp::Kind::Colourer, "colours a caught sample by its trap ratio d / r")
        .def("{type: colour-map, preset: fig-4a}"),
    fp::param::colour("background",
                      "colour of samples never caught (default: the colourer's own, colour-map: "
                      "the last colour of its table)")
        .opt(),
    fp::param::string("reduction", "mod 2 pi after every step (eq. (13)): fmod (C's, symmetric about 0), "
                                   "centred ([-pi, pi)), floor ([0, 2 pi)), none, or hexagonal (modulo the "
                                   "hexagonal lattice of p3 ... p6m into its hexagon about 0)")
        .def("fmod")
        .one_of("fmod|centred|floor|none|hexagonal"),
    fp::param::boolean("tile",
                       "render one period of the pattern, to be repeated without a seam: the area becomes "
                       "the smallest rectangle of the map's periods, centred on the area's centre, and "
                       "the height follows from the width (square pixels); needs a periodic mapping "
                       "(wallpaper) and the Picard iteration")
        .def("false"),
    fp::param::string("precision", "arithmetic of the orbits: float (twice the SIMD width) or double")
        .def("float")
        .one_of("float|double"),
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<fp_orbit_trap::OrbitTrap>(
                    fp::Kind::Renderer, "orbit-trap",
                    "the modified orbit trap method: patterns with wallpaper symmetry (paper 04, "
                    "Algorithm 3)",
                    params)
                    .with_example("{mapping: {type: gumowski-mira}, traps: {type: circles, preset: fig-1a}, "
                                  "width: 64, height: 64, samples: 1, max_iterations: 20}"))
