// chaos-game: the random inversion algorithm (paper 01, Algorithm 1) and general chaos games.
//
// What it computes
// ----------------
// Many independent chains p_0, p_1, ... each move by one of the maps in `maps` per step and
// plot every point after the first `skip`. Under the inversion rules (paper 01: "not the
// previous map, not a map whose set holds the point") the next map is one of the allowed
// maps with probabilities proportional to `weight`, drawn as the paper's Algorithm 1 does:
// draw, and draw again while the map is the previous one or its set holds the point ("while
// j = l or inSet(S_l, p)"), so that a step tests one set, not every map's. With equal weights
// the draw is among the maps other than the previous one (which the loop would only reject),
// else by weight among all. After 4 draws (kernels.hpp's rejection_draws) a chain still
// rejected takes the direct draw among the allowed maps (their weights summed), so a point
// deep inside several sets costs a bounded number of draws; the distribution is the same
// either way. A chain with no allowed
// map, or whose point becomes NaN or infinite, restarts from a fresh start point and is
// counted (RenderStats::restarts, ::bad_values); a chain that restarts 100 times in a row
// without plotting a point is retired, so no recipe spins forever. With the rules off the
// draw is a plain weighted one (Walker's alias table: O(1) whatever the number of maps), as
// in an affine IFS. `inversion_rules: auto` turns them on exactly when every map has a set.
//
// How (the hot path)
// ------------------
// Chains run in blocks of 512 (the last few of a render on several workers: 128), in
// lockstep, as structure-of-arrays state (x, y, previous map, colour, pcg32 state, age,
// points left); one task per worker of the host's parallel_for takes the next block until
// none is left. (The block state, buffers and histograms are in chaos-game/state.hpp, the
// steady runs in chaos-game/steady.hpp, the vectorised stages and the fused step in
// chaos-game/kernels-inl.hpp, compiled per SIMD target.)
// One step of a block:
//   1. inside tests: one Transform::contains call per map with a set on the whole block
//      (rules on);
//   2. the draw: one pcg32 output per chain (a few more for the chains rejected: paper 01's
//      loop, above), a vector of chains at a time; the rare chains still rejected after
//      rejection_draws take the direct draw (the total allowed weight and the cumulative
//      search, branch-free, the per-map tests as masks); with the rules off, Walker's alias
//      table;
//   3. grouping by map: each map's chains compressed into its own staging segment (AVX-512
//      vcompress, up to 16 maps; a scalar counting sort otherwise), one IterationScheme::step
//      call per map on its segment, expanded back in place;
//   4. one Colourer::update call for the block (skipped when the colourer needs no colour);
//   5. bookkeeping (finite?, plotted?, age, points left), bin indices and colours packed
//      {1, r, g, b} in 16 bits each (not when the colourer needs no colour), in one pass
//      (AVX-512, float) or a few vectorised loops;
//   6. the deposit: one 4 x 32-bit add per point into the worker's own histogram, or one
//      32-bit increment when counting hits only. The fused step with hits only makes the
//      increments of the previous step's points inside its own pass, 16 after each vector of
//      chains: their cache misses (a 4 MiB histogram does not fit in L2) then overlap the
//      arithmetic instead of following it in a loop of their own (about 20% of the render's
//      time on one thread; bench/README.md).
// Known kernels: when every map is a known kernel of one kind (Transform::kernel(): inversion
// in a circle about its centre, affine, Gumowski-Mira) and the scheme is the Picard step or
// one that writes its step as a program (IterationScheme::program: every scheme of paper 02
// on fp::SchemeBase), steps 1-5 run instead as one fused pass per SIMD target, a vector of
// chains at a time with the maps' parameters in registers and tables, no calls and no
// grouping (chaos-game/kernels-inl.hpp's fused_t). A scheme's program is asked for at each
// block step (its coefficients change with n) and must be the same for every map; a step
// where it is not (Schu composing T more often than a program holds) takes the generic path,
// the fused step's pending work settled first. It computes the same draws and the same operations
// in the same order, so the image is the same bytes; `kernels: generic` turns it off
// (tests/unit/test_chaos_kernel.cpp renders recipes both ways). While every chain of a block is
// past its skip and far from its last point, the block runs steady (chaos-game/steady.hpp):
// the pass leaves age, idle, points left and activity alone, and they are settled at the run's
// end, with colour or without.
// So a step costs 2k + 1 virtual calls per block (k maps), none per point; nothing is
// allocated, looked up, thrown or logged per point. Block buffers are allocated once per
// worker and stay in L1/L2 (about 100 bytes per chain, k more for the tests, 8 k for the
// staging segments).
//
// The workers' histograms have 16-byte bins {hits, r, g, b} of 32 bits (half of
// fp::HistBin: the bins a fractal touches are what limits the deposit, and twice as many
// stay in cache); a bin spills into a list of 64-bit bins when its hits reach 65536, before
// its colour sums (at most 65535 per point) can overflow. They live in 2 MiB-aligned memory
// advised for transparent huge pages (no TLB miss per deposit). At the end they and the
// spills are summed into one fp::Histogram (rows in parallel), which the colourer resolves
// on the workers too (Colourer::resolve_parallel: rows in parallel, the same bytes as the
// serial resolve). A colourer whose needs_colour() is false (density) reads hit counts
// only: then the chains carry no colour and the workers count hits alone in 4-byte
// counters (as the reference kernels do: four times as many bins per cache line), flushed
// whole into 64-bit counters every 2^31 deposits of a worker, before any can overflow; the
// fp::Histogram gets hits and zero colour sums, or hit counts alone (fp::Histogram::hits)
// where its reader asks for no more (Colourer::reads_hits_only, and the summary of a render
// in strips).
//
// Tallies: with the map rule (map-colour: each point the colour of the map that made it) and
// at most 8 maps, on the fused path (a recipe's steps that fall back to the generic one too),
// a worker's bins are instead 16-bit counters, the points each map put there, in a plane per
// map (map j's counter of bin i at j * plane + i: a map's points lie in a region of their own,
// the image of its set, so its counters share cache lines; a bin's 8 counters side by side
// took as many lines as the 16-byte bins, more than twice those of 4-byte hit counts).
// The deposit is one 16-bit increment by the point's map; the chains carry no colour and no
// colour is packed per point. A counter spills (the whole bin, into the list of 64-bit bins)
// before it can wrap, and the sums into fp::Histogram turn a bin's counts n_j into {sum n_j,
// sum n_j q_j} with q_j map j's quantised colour: the integers the colour deposits would have
// summed, so the image is the same bytes (the generic path keeps {hits, r, g, b}: `kernels:
// generic` renders compare the two in tests/unit/test_chaos_kernel.cpp). On bench/circles.yaml
// with map-colour this took one core from 212 to 271 M points/s pinned to AVX2, and from 313 to
// about 375 on AVX-512 (a 2-core Xeon); the planes, from 287 to 339 and from 379 to 430 (a
// 2-core AMD EPYC with AVX-512 and a 1 MiB L2 a core).
//
// Where the time goes (bench/circles.yaml: 6 circles, 1024 x 1024; one core of the 2-core
// AVX-512 machine; bench/README.md has the figures). Hits only (density), fused path: the
// fused pass (6 inside tests, pcg32, the draw, the inversion, bookkeeping and bin index) about
// 60%, the deposit about 30% (random 4-byte increments over a 4 MiB histogram), resolve and
// fixed costs the rest. Generic path (kernels: generic, or any other map): grouping by map
// about 23%, the deposit 20%, the draw 19%, the 6 inside tests 14%, the bookkeeping 11%, the
// inversions 9%. With colour (map-colour) the deposit grows to about 38% (random 16-byte
// read-modify-writes over a 16 MiB histogram) and the colour update adds 10%.
//
// Precision
// ---------
// `precision: float` (the default) keeps the chains in float lanes: twice the SIMD width of
// double, and plenty for a histogram a few thousand pixels wide over a view of ordinary size.
// `precision: double` is for deep zooms, where float's 24-bit mantissa no longer resolves a
// pixel of the view (roughly when (xmax - xmin) / width < 1e-6 * |x|); it runs the same
// algorithm in 8-lane vectors, with the bookkeeping in the generic loops.
//
// Determinism
// -----------
// A render is a pure function of its recipe, whatever the thread count:
//   - chain i draws from its own stream, fp::chain_stream(seed, i) (pcg32, bit-identical; kept
//     here as SoA state so the draws vectorise), one output per step, those of its own draws
//     again under the rules (only the rejected chains of a vector draw again) and those of
//     its start points, so its path depends on nothing but (seed, i, its own history);
//   - the number of chains and the points per chain are fixed by the recipe (chain i plots
//     points / chains points, one more for i < points % chains), never by the thread count;
//   - all map choices are integer arithmetic; float work is plain IEEE arithmetic compiled
//     without FMA contraction, so every SIMD width gives the same bits;
//   - each worker sums into its own integer histogram; integer sums are exact and
//     independent of order, so merging the workers' histograms gives the same bytes on 1 or N
//     threads (and the block size does not matter either).
// The iteration scheme sees step index n = the block's step count (equal to the chain's step
// count since the render began, restarts included).
//
// Binning: a point plots when x in [xmin, xmax) and y in (ymin, ymax]; column =
// floor((x - xmin) * (width / (xmax - xmin))), row = floor((ymax - y) * (height / (ymax -
// ymin))) (y = ymax is the top row), in the chain precision with the scale factors
// precomputed, clamped to the image in case the product rounds up. Colour sums add
// round(c * fp::colour_scale) per channel (c clamped to [0, 1], NaN to 0; rounded as
// trunc(c * 65535 + 0.5) in float). RenderStats::samples counts the points plotted after
// `skip`, inside the view or not; chains start with the mean colour of the maps.
//
// Last colours (a colourer whose fp::PixelRule is last: flame's `last` and `set-colour`):
// paper 02's Algorithm 2 as written. A chain starts with a random colour (from the stream
// fp::chain_stream(seed + colour_stream_salt, chain), which its draws never touch), update()
// changes it only at the steps where it plots, and each worker keeps per bin the colour of
// its point with the largest (step, chain); the workers' entries merge by the same order, so
// the winner, and the image, are the same on any number of threads. With the map rule
// (set-colour), where a point's colour is its map's, the fused step runs and the renderer
// writes the last colours after each of its steps; the running colour (`last`) takes the
// generic path.
//
// Strips (an image whose histogram and pixels do not fit the memory budget,
// RenderContext::memory_budget: `fixpoint render --memory`, else what the machine has
// available; the host then calls render_rows): the image is cut into strips of rows, and every
// chain runs in full once per strip, binning only the points whose row is in the strip (the
// rest go to the dummy bin), so each strip's bins get exactly the sums one pass would give
// them. The colourer needs the whole histogram's summary (largest hit count, centre of mass,
// per-row extents: fp::HistogramSummary) before it shades any strip, so a first pass counts
// hits only, in strips of its own (4 bytes a bin per worker: usually far fewer strips), and
// adds up the summary; the second pass bins the colours strip by strip, shades each with
// Colourer::resolve_rows and hands its rows to the host, which encodes them into the output
// file as they come (fp::RowSink): neither the histogram nor the image is ever whole. Same
// bytes as one pass; the price is the chains run once per strip of each pass (plan). Ranks
// split every strip's chains as they split a whole render's. (Not with the sets drawn over or
// beside: those draw on the whole picture.)
//
// Errors (ParamError, by parameter): "view": "the view must be [xmin, xmax, ymin, ymax] with
// xmin < xmax" (or "... with ymin < ymax"); "maps": "the list of maps is empty"; "height":
// "the image is too large: width * height must be below 4294967295 pixels".
#include "chaos-game/checkpoint.hpp"
#include "chaos-game/kernels.hpp"
#include "chaos-game/sets.hpp"
#include "chaos-game/state.hpp"
#include "chaos-game/steady.hpp"
#include "fit_view.hpp"
#include "palette.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

// The step's stages (chaos-game/kernels-inl.hpp), compiled once per instruction set of the
// build and dispatched at run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "chaos-game/kernels-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "chaos-game/kernels-inl.hpp"

namespace fp_chaos {
HWY_EXPORT(draw_rules);
HWY_EXPORT(draw_alias);
HWY_EXPORT(group_f);
HWY_EXPORT(group_d);
HWY_EXPORT(scatter_f);
HWY_EXPORT(scatter_d);
HWY_EXPORT(bookkeep_f);
HWY_EXPORT(bookkeep_d);
HWY_EXPORT(fused_f);
HWY_EXPORT(fused_d);
HWY_EXPORT(fused_run_f);
HWY_EXPORT(fused_run_d);
HWY_EXPORT(deposit_colour);

inline void group(const GroupArgs<float>& a) { HWY_DYNAMIC_DISPATCH(group_f)(a); }
inline void group(const GroupArgs<double>& a) { HWY_DYNAMIC_DISPATCH(group_d)(a); }
inline void scatter(const float* gx, const float* gy, const uint32_t* gi, size_t n, float* x, float* y) {
    HWY_DYNAMIC_DISPATCH(scatter_f)(gx, gy, gi, n, x, y);
}
inline void scatter(const double* gx, const double* gy, const uint32_t* gi, size_t n, double* x, double* y) {
    HWY_DYNAMIC_DISPATCH(scatter_d)(gx, gy, gi, n, x, y);
}
inline Counts bookkeep(const BookArgs<float>& a, bool colour) {
    return HWY_DYNAMIC_DISPATCH(bookkeep_f)(a, colour);
}
inline Counts bookkeep(const BookArgs<double>& a, bool colour) {
    return HWY_DYNAMIC_DISPATCH(bookkeep_d)(a, colour);
}
inline Counts fused(const FusedArgs<float>& a) { return HWY_DYNAMIC_DISPATCH(fused_f)(a); }
inline Counts fused(const FusedArgs<double>& a) { return HWY_DYNAMIC_DISPATCH(fused_d)(a); }
inline RunCounts fused_run(const FusedArgs<float>& a, uint64_t steps) {
    return HWY_DYNAMIC_DISPATCH(fused_run_f)(a, steps);
}
inline RunCounts fused_run(const FusedArgs<double>& a, uint64_t steps) {
    return HWY_DYNAMIC_DISPATCH(fused_run_d)(a, steps);
}
} // namespace fp_chaos

namespace {

using std::size_t;
using std::uint32_t;
using std::uint64_t;
// The state, buffers and bookkeeping of chaos_state.hpp and chaos_bookkeep.hpp.
using namespace fp_chaos;

/// v in [0, 1] (not NaN).
inline bool in_unit(float v) { return v >= 0.0f && v <= 1.0f; }

// ---------------------------------------------------------------- the renderer
class ChaosGame final : public fp::Renderer {
public:
    explicit ChaosGame(const fp::ParamBag& p);

    int width() const override { return sets_ == Sets::beside ? 2 * frame_.width : frame_.width; }
    int height() const override { return frame_.height; }
    std::optional<fp::Box> region() const override {
        return frame_.has_region ? std::optional(frame_.region) : std::nullopt;
    }
    uint64_t memory_bytes(unsigned workers) const override;
    bool streams_rows() const override { return sets_ == Sets::none && colourer_->resolves_rows(); }
    uint64_t memory_within(unsigned workers, uint64_t budget) const override;
    void render_rows(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink) const override;
    uint64_t work_units() const override;
    fp::Image render(fp::RenderContext& ctx, fp::RenderStats& stats) const override;
    bool has_vector_output() const override { return sets_ == Sets::only; }
    bool keeps_checkpoints() const override { return sets_ != Sets::only; }
    std::string render_vector(fp::RenderContext& ctx, fp::RenderStats& stats, fp::VectorFormat format,
                              const std::string& recipe) const override;

private:
    /// Rows [row0, row0 + rows) of the histogram into `total` (all rows: the whole render), with
    /// colour sums (and last colours) when `colour`; with `pixels`, the image's buffer is
    /// allocated alongside. Without colour and with `hits_total` (its reader reads hit counts
    /// alone: HistogramSummary, or a colourer whose reads_hits_only() is true), `total` is hit
    /// counts alone (fp::Histogram::hits), except in a checkpointed render, whose checkpoints
    /// hold fp::HistBin bins. stats: this pass's counts.
    template <class T>
    void render_t(fp::RenderContext& ctx, fp::RenderStats& stats, fp::Histogram& total,
                  std::vector<float>* pixels, uint32_t row0, uint32_t rows, bool colour,
                  bool hits_total) const;
    /// The render in strips (Strips, above), each strip's pixels into the sink.
    template <class T>
    void render_strips(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink,
                       uint32_t summary_rows, uint32_t rows) const;

    /// Bytes of the workers' histograms and the total for a strip of `rows` rows, with colour
    /// sums (and last colours) or hits only.
    uint64_t strip_bytes(unsigned workers, uint64_t rows, bool colour, bool hits_total) const;
    /// The workers' block state.
    uint64_t scratch_bytes(unsigned workers) const;
    /// How a render in strips fits `budget`: rows per strip of the summary pass and of the
    /// colour pass, and the memory it then takes; strips of one row when even those do not fit
    /// (then bytes > budget).
    struct Plan {
        uint32_t summary_rows, rows;
        uint64_t bytes;
    };
    Plan plan(unsigned workers, uint64_t budget) const;
    /// Runs task t's chains to their end (true), or, in a checkpointed render (keep), until a
    /// checkpoint is due (false: their state is in t.saved).
    template <class T, bool Rules, bool Colour>
    bool run_block(Task& t, Scratch<T>& s, WorkerHist& hist, fp::RenderContext& ctx, uint32_t row0,
                   uint32_t rows, Keeping* keep) const;
    /// A checkpointed render's state from the payload it resumes from: its tasks, the chains'
    /// final states, the histogram (into total, and last writes into `last`), the stats.
    template <class T>
    void resume(fp::CheckpointSource& in, std::vector<Task>& tasks, Keeping& keep, fp::Histogram& total,
                std::vector<LastWrite>& last, BlockResult& base) const;
    /// Writes the checkpoint: the tasks not done, the final states, the histogram folded into
    /// total and `last`.
    template <class T>
    void save(fp::RenderContext& ctx, const std::vector<Task>& tasks, const Keeping& keep,
              const fp::Histogram& total, const std::vector<LastWrite>& last, const BlockResult& base) const;
    /// The workers' histograms added into total (and their last writes into `last`), then
    /// cleared.
    void fold(fp::RenderContext& ctx, std::vector<WorkerHist>& hists, fp::Histogram& total,
              std::vector<LastWrite>& last, size_t px) const;
    template <class T>
    void choose_rules(Scratch<T>& s, size_t nb) const;
    template <class T>
    void choose_alias(Scratch<T>& s, size_t nb) const;
    template <class T>
    void new_starts(Scratch<T>& s, const uint32_t* list, size_t m) const;
    template <class T>
    void move_chains(Scratch<T>& s, size_t nb, uint64_t n) const;
    /// A block step in kernels-inl.hpp's fused pass: the draw, the maps, the colours and the
    /// bookkeeping (steps 1-5).
    template <class T, bool Colour>
    FusedArgs<T> fused_args(Scratch<T>& s, const BookArgs<T>& bv, uint32_t* hits, const uint32_t* lag,
                            bool steady) const;
    /// The scheme's step at step index n as the fused step's program (into `out`): false when
    /// a map gives none, or the maps give different ones (that step then takes the generic
    /// path).
    template <class T>
    bool lane_program(uint64_t n, LaneProgram<T>& out) const;
    /// The fused step's tables; Colour false: those of a pass that counts hits only.
    template <class T, bool Colour>
    const LaneTables<T>& lane_tables() const {
        if constexpr (std::is_same_v<T, float>)
            return Colour ? *lanes_f_ : *lanes_f_hits_;
        else
            return Colour ? *lanes_d_ : *lanes_d_hits_;
    }

    /// Algorithm 2's "I(x, y) = c" for a block step: each plotted point's colour into its bin
    /// unless the bin holds a later (step, chain).
    void combine_ranks(fp::RenderContext& ctx, fp::RenderStats& stats, fp::Histogram& total,
                       std::vector<LastWrite>& rank_last) const;
    static void write_last(WorkerHist& hist, const uint32_t* idx, const uint64_t* dep, size_t nb, uint64_t n,
                           const uint32_t* chain, uint32_t dummy);

    /// The sets of the maps on the background, as a width x height picture.
    void draw_set_panel(cairo_t* cr) const;

    enum class Sets { none, over, beside, only };
    Sets sets_ = Sets::none;
    SetStyle set_style_;
    std::optional<fp::Box> set_view_; ///< the region of the sets' own picture (beside, only); else the view
    std::vector<SetDrawing> set_drawings_;

    fp::Frame frame_; ///< width, height, view (region), background
    uint64_t points_ = 1000000, seed_ = 1, skip_ = 20, chains_ = 4096;
    bool has_start_ = false;
    fp::Vec2 start_;
    fp::Box start_box_; ///< where random start points are drawn (the view unless start_box)
    bool rules_ = true, double_ = false, colour_ = true;
    bool last_ = false;  ///< the colourer's pixel rule is last (paper 02's Algorithm 2 as written)
    bool fused_ = false; ///< the fused step (kernels-inl.hpp's fused_t) runs the block steps
    /// With fused_: the scheme is not Picard, and the fused step runs its program
    /// (IterationScheme::program) at each step where every map gives the same one.
    bool program_ = false;
    std::shared_ptr<LaneTables<float>> lanes_f_, lanes_f_hits_;
    std::shared_ptr<LaneTables<double>> lanes_d_, lanes_d_hits_;
    /// With fused_ and the map rule on at most tally_maps maps: the workers' bins are tallies
    /// (see "Tallies"); else null.
    std::shared_ptr<const Tallies> tallies_;

    std::vector<std::shared_ptr<const fp::Transform>> maps_;
    std::vector<uint32_t> region_maps_;       ///< indices of the maps with a set
    std::vector<uint32_t> q_;                 ///< integer weights (rules on)
    bool uniform_ = true;                     ///< every weight the same (the rules' draw)
    std::vector<uint32_t> alias_thr_, alias_; ///< Walker's alias table (rules off; on, with unequal weights)
    std::vector<fp::Rgb> colours_;            ///< k + 1 entries (the last one is never used)
    /// The maps' colours as deposits carry them (fp::quantise_colour): the tallies' colours,
    /// and a point's last colour under the map rule on the fused path.
    std::vector<std::array<uint16_t, 3>> map_q_;
    fp::Rgb initial_colour_;
    std::shared_ptr<const fp::IterationScheme> iteration_;
    std::shared_ptr<const fp::Colourer> colourer_;
};

ChaosGame::ChaosGame(const fp::ParamBag& p) {
    frame_ = fp::Frame::read(p);
    points_ = uint64_t(p.integer("points"));
    seed_ = uint64_t(p.integer("seed"));
    skip_ = uint64_t(p.integer("skip"));
    chains_ = uint64_t(p.integer("chains"));
    has_start_ = p.has("start");
    if (has_start_) start_ = p.vec2("start");
    start_box_ = {frame_.region.xmin, frame_.region.xmax, frame_.region.ymin, frame_.region.ymax};
    if (p.has("start_box")) {
        const auto& sb = p.reals("start_box");
        if (!(sb[0] < sb[1]) || !(sb[2] < sb[3]))
            throw fp::ParamError("start_box",
                                 "the start box must be [xmin, xmax, ymin, ymax] with xmin < xmax "
                                 "and ymin < ymax");
        start_box_ = {sb[0], sb[1], sb[2], sb[3]};
    }
    double_ = p.string("precision") == "double";
    iteration_ = p.object<fp::IterationScheme>("iteration");
    colourer_ = p.object<fp::Colourer>("colourer");
    colour_ = colourer_->needs_colour();
    last_ = colourer_->pixel_rule() == fp::PixelRule::last;
    if (last_) colour_ = true;

    const auto& items = p.objects("maps");
    if (items.empty()) throw fp::ParamError("maps", "the list of maps is empty");
    const size_t k = items.size();
    std::vector<double> w(k, 1.0);
    for (size_t j = 0; j < k; ++j) {
        auto m = fp::as<fp::Transform>(items[j]);
        if (!m) throw fp::InternalError("chaos-game: maps[" + std::to_string(j) + "] is not a transform");
        if (const std::string why = m->plane_map_problem(); !why.empty())
            throw fp::ParamError("maps", "maps[" + std::to_string(j) + "]: " + why);
        fp::Rgb c = fp_render::palette_colour(j);
        if (items[j].extras) {
            w[j] = items[j].extras->real("weight");
            if (items[j].extras->has("colour")) c = items[j].extras->colour("colour");
        }
        if (!(w[j] > 0) || !std::isfinite(w[j]))
            throw fp::ParamError("maps", "maps[" + std::to_string(j) + "].weight must be a positive number");
        const bool region = m->has_region();
        if (region) region_maps_.push_back(uint32_t(j));
        maps_.push_back(std::move(m));
        colours_.push_back(c);
    }
    colours_.push_back(fp::Rgb{});
    for (size_t j = 0; j < k; ++j)
        map_q_.push_back({uint16_t(fp::quantise_colour(colours_[j].r)),
                          uint16_t(fp::quantise_colour(colours_[j].g)),
                          uint16_t(fp::quantise_colour(colours_[j].b))});
    initial_colour_ = fp::Rgb{};
    for (size_t j = 0; j < k; ++j) {
        initial_colour_.r += colours_[j].r / float(k);
        initial_colour_.g += colours_[j].g / float(k);
        initial_colour_.b += colours_[j].b / float(k);
    }

    // Schemes whose cost grows with the step index refuse here, before anything runs.
    const uint64_t last_n = skip_ + (points_ + chains_ - 1) / chains_ - 1;
    for (const auto& m : maps_) {
        try {
            iteration_->check_steps(*m, last_n);
        } catch (const fp::ParamError&) {
            throw;
        } catch (const fp::InputError& e) {
            throw fp::ParamError("iteration", e.what());
        }
    }

    const std::string& sets = p.string("sets");
    sets_ = sets == "over"     ? Sets::over
            : sets == "beside" ? Sets::beside
            : sets == "only"   ? Sets::only
                               : Sets::none;
    set_style_ = {p.real("set_line"), p.real("set_fill")};
    if (p.has("set_view")) {
        const auto& v = p.reals("set_view");
        if (!(v[0] < v[1]) || !(v[2] < v[3]))
            throw fp::ParamError(
                "set_view", "the view must be [xmin, xmax, ymin, ymax] with xmin < xmax and ymin < ymax");
        if (sets_ == Sets::over || sets_ == Sets::none)
            throw fp::ParamError("set_view",
                                 "the sets' own view needs sets: beside or sets: only (over the fractal, "
                                 "the sets are drawn in its view)");
        set_view_ = fp::Box{v[0], v[1], v[2], v[3]};
    }
    if (sets_ != Sets::none) {
        for (size_t j = 0; j < k; ++j)
            if (maps_[j]->has_region())
                set_drawings_.push_back(
                    {maps_[j]->region_outline(1024), maps_[j]->region_centre(), colours_[j]});
        if (set_drawings_.empty())
            throw fp::ParamError("sets", "none of the maps has a set to draw (inversions have one)");
        if (sets_ == Sets::beside && uint64_t(2 * frame_.width) * uint64_t(frame_.height) >= 0xffffffffull)
            throw fp::ParamError("sets",
                                 "the image with the sets beside it is too large: 2 * width * height must "
                                 "be below 4294967295 pixels");
    }

    const std::string& rules = p.string("inversion_rules");
    rules_ = rules == "on" || (rules == "auto" && region_maps_.size() == k);

    if (p.boolean("fit_view")) {
        fp_render::FitSetup f;
        f.maps = &maps_;
        f.weights = w;
        f.rules = rules_;
        f.iteration = iteration_.get();
        if (has_start_) f.start = start_;
        f.start_box = start_box_;
        f.seed = seed_, f.skip = skip_, f.chains = chains_, f.points = points_;
        f.width = frame_.width, f.height = frame_.height;
        const fp::Box v = fp_render::fit_view(f);
        frame_.region.xmin = v.xmin, frame_.region.xmax = v.xmax, frame_.region.ymin = v.ymin,
        frame_.region.ymax = v.ymax;
    }

    // Integer weights for the draw among the allowed maps: sum below 2^32, each at least 1.
    double sum = 0;
    for (double x : w) sum += x;
    q_.resize(k);
    for (size_t j = 0; j < k; ++j)
        q_[j] = uint32_t(std::max(1.0, std::floor(w[j] / sum * double(1u << 31) + 0.5)));
    uniform_ = std::all_of(w.begin(), w.end(), [&](double x) { return x == w[0]; });

    fp_chaos::walker_table(w, alias_thr_, alias_);

    // The fused step: every map a known kernel of one kind (Transform::kernel: inversions in
    // circles about their centres, affine maps, Gumowski-Mira maps), a Picard step, at most
    // table_size maps, and a colourer that needs no colour or whose update is a ColourRule;
    // `kernels: generic` turns it off (it gives the same bytes: tests/unit/test_chaos_kernel.cpp).
    const fp::ColourRule crule = colourer_->colour_rule();
    // Last colours (the pixel rule last) with the map rule: paper 01's colouring by set
    // (flame's set-colour, every configs/inversion figure). A point's colour is its map's
    // whatever the chain's history, so the renderer writes the last colours from the maps the
    // fused step took (run_block). The running colour of Algorithm 2 (flame's `last`) changes
    // only where a chain plots, unlike the fused step's: that mode keeps the generic path.
    if (p.string("kernels") == "auto" && k <= fp_chaos::table_size &&
        (!colour_ || crule != fp::ColourRule::none) && (!last_ || crule == fp::ColourRule::map)) {
        std::vector<fp::KnownKernel> kk;
        for (const auto& m : maps_) kk.push_back(m->kernel());
        const auto kind = kk[0].kind;
        fused_ = kind != fp::KnownKernel::Kind::none;
        for (const auto& x : kk) fused_ = fused_ && x.kind == kind;
        // A scheme other than Picard fuses when it gives the same program for every map at the
        // first step (IterationScheme::program: paper 02's schemes on fp::SchemeBase do); each
        // step's program is asked for again as the step runs.
        program_ = fused_ && !iteration_->is_picard();
        if (program_) {
            LaneProgram<double> ld;
            LaneProgram<float> lf;
            fused_ = program_ = double_ ? lane_program(0, ld) : lane_program(0, lf);
        }
        if (fused_) {
            lanes_f_ = std::make_shared<LaneTables<float>>();
            lanes_d_ = std::make_shared<LaneTables<double>>();
            auto fill = [&](auto& t) {
                using T = std::remove_reference_t<decltype(t.p[0][0])>;
                using U = typename std::remove_reference_t<decltype(t)>::U;
                t.k = uint32_t(k);
                t.rules = rules_;
                t.uniform = uniform_;
                t.kind = kind == fp::KnownKernel::Kind::circle_inversion ? LaneKind::circle
                         : kind == fp::KnownKernel::Kind::affine         ? LaneKind::affine
                                                                         : LaneKind::gumowski_mira;
                t.colour = !colour_                       ? LaneColour::none
                           : crule == fp::ColourRule::map ? LaneColour::map
                                                          : LaneColour::average;
                for (size_t j = 0; j < k; ++j) {
                    if (kind == fp::KnownKernel::Kind::circle_inversion) {
                        t.p[0][j] = T(kk[j].cx), t.p[1][j] = T(kk[j].cy), t.p[2][j] = T(kk[j].r2);
                    } else {
                        for (int i = 0; i < 6; ++i) t.p[i][j] = T(kk[j].c[i]);
                    }
                    t.q[j] = q_[j];
                    t.thr[j] = U(alias_thr_[j]);
                    t.alias[j] = U(alias_[j]);
                    t.cr[j] = colours_[j].r, t.cg[j] = colours_[j].g, t.cb[j] = colours_[j].b;
                }
                t.colours_in_range = std::all_of(colours_.begin(), colours_.end(), [](const fp::Rgb& c) {
                    return in_unit(c.r) && in_unit(c.g) && in_unit(c.b);
                });
                t.repeat_wide();
            };
            fill(*lanes_f_);
            fill(*lanes_d_);
            // (The fused step indexes the counters by map * plane + bin in 32 bits.)
            if (colour_ && crule == fp::ColourRule::map && k <= fp_chaos::tally_maps &&
                (uint64_t(frame_.width) * uint64_t(frame_.height) + 1) * k <= 0xffffffffull) {
                auto t = std::make_shared<Tallies>();
                t->k = uint32_t(k);
                for (size_t j = 0; j < k; ++j)
                    for (int c = 0; c < 3; ++c) t->q[j][c] = map_q_[j][c];
                tallies_ = t;
                lanes_f_->colour = lanes_d_->colour = LaneColour::tally;
            }
            // The hits-only copies, for the pass of a render in strips that counts hits alone.
            lanes_f_hits_ = std::make_shared<LaneTables<float>>(*lanes_f_);
            lanes_d_hits_ = std::make_shared<LaneTables<double>>(*lanes_d_);
            lanes_f_hits_->colour = lanes_d_hits_->colour = LaneColour::none;
        }
    } else {
        (void)p.string("kernels");
    }
}

uint64_t ChaosGame::work_units() const {
    if (sets_ == Sets::only) return 1;
    const uint64_t live = std::min(chains_, points_); // chains with at least one point
    return live * skip_ + points_;
}

uint64_t ChaosGame::strip_bytes(unsigned workers, uint64_t rows, bool colour, bool hits_total) const {
    const uint64_t px = uint64_t(frame_.width) * rows;
    // The workers' 32-bit histograms, the total, the spill lists (at most one entry per
    // 65536 points); hits only: 32-bit counters, and 64-bit ones once a worker could
    // have deposited hits_flush points, and a total of hit counts alone with hits_total.
    const uint64_t deposits = points_ + std::min(chains_, points_) * skip_;
    const uint64_t bins = tallies_ ? tally_bins(tallies_->k, px) : px + 1;
    const uint64_t hist =
        colour ? uint64_t(workers) * (bins * sizeof(Cnt4) + (2u << 20)) + px * sizeof(fp::HistBin) +
                     (points_ / spill_hits + uint64_t(workers) * 256) * 48
               : uint64_t(workers) * ((px + 1) * 4 + (2u << 20) + (deposits >= hits_flush ? px * 8 : 0)) +
                     px * (hits_total ? sizeof(uint64_t) : sizeof(fp::HistBin));
    // Last colours: the workers' last writes and the total's colours.
    const uint64_t last = colour && last_ ? uint64_t(workers) * ((px + 1) * sizeof(LastWrite) + (2u << 20)) +
                                                px * sizeof(fp::LastColour)
                                          : 0;
    return hist + last;
}

uint64_t ChaosGame::scratch_bytes(unsigned workers) const {
    return uint64_t(workers) *
           (double_ ? Scratch<double>::bytes(maps_.size()) : Scratch<float>::bytes(maps_.size()));
}

uint64_t ChaosGame::memory_bytes(unsigned workers) const {
    const uint64_t px = uint64_t(frame_.width) * uint64_t(frame_.height);
    // (The sets beside: a second picture of the same size, and the two side by side.)
    const uint64_t image = px * 3 * sizeof(float) * (sets_ == Sets::beside ? 3 : 1);
    // (A whole render's total counted as fp::HistBin bins even where it is hit counts alone: a
    // checkpointed render keeps the bins.)
    return strip_bytes(workers, uint64_t(frame_.height), colour_, false) + image + scratch_bytes(workers);
}

ChaosGame::Plan ChaosGame::plan(unsigned workers, uint64_t budget) const {
    const uint32_t H = uint32_t(frame_.height);
    // The block state and the summary (two 32-bit columns per row) stay; the strips' bytes grow
    // linearly with their rows, in the colour pass with the strip's pixels (3 floats each).
    const uint64_t fixed = scratch_bytes(workers) + uint64_t(H) * 8;
    const uint64_t pixel_row = uint64_t(frame_.width) * 3 * sizeof(float);
    // The pass that counts hits (the summary) and the pass that shades (colour sums when the
    // colourer needs them, and the strip's pixels).
    auto bytes = [&](uint64_t rows, bool shading) {
        return shading ? strip_bytes(workers, rows, colour_, colourer_->reads_hits_only()) + rows * pixel_row
                       : strip_bytes(workers, rows, false, true);
    };
    auto rows_within = [&](bool shading) -> uint32_t {
        const uint64_t one = bytes(1, shading), per_row = bytes(2, shading) - one;
        if (budget < fixed + one) return 0;
        return uint32_t(std::min<uint64_t>(H, 1 + (budget - fixed - one) / per_row));
    };
    const uint32_t summary_rows = rows_within(false), rows = rows_within(true);
    if (summary_rows == 0 || rows == 0) return {1, 1, fixed + std::max(bytes(1, false), bytes(1, true))};
    return {summary_rows, rows, fixed + std::max(bytes(summary_rows, false), bytes(rows, true))};
}

uint64_t ChaosGame::memory_within(unsigned workers, uint64_t budget) const {
    return streams_rows() ? plan(workers, budget).bytes : memory_bytes(workers);
}

void ChaosGame::draw_set_panel(cairo_t* cr) const {
    cairo_set_source_rgb(cr, frame_.background.r, frame_.background.g, frame_.background.b);
    cairo_paint(cr);
    // (The view once fit_view has fitted it.)
    draw_sets(cr, set_drawings_, set_view_.value_or(frame_.region), frame_.width, frame_.height, set_style_);
}

std::string ChaosGame::render_vector(fp::RenderContext& ctx, fp::RenderStats& stats, fp::VectorFormat format,
                                     const std::string& recipe) const {
    if (sets_ != Sets::only) return fp::Renderer::render_vector(ctx, stats, format, recipe);
    stats = fp::RenderStats{};
    stats.samples = set_drawings_.size();
    stats.unit = "sets";
    std::string doc = fp_render::cairo_document(frame_.width, frame_.height, format == fp::VectorFormat::Pdf,
                                                recipe, &ctx, [&](cairo_t* cr) { draw_set_panel(cr); });
    if (doc.empty()) throw fp::InternalError("chaos-game: Cairo could not write the sets");
    ctx.progress(1);
    return doc;
}

fp::Image ChaosGame::render(fp::RenderContext& ctx, fp::RenderStats& stats) const {
    stats = fp::RenderStats{};
    if (sets_ == Sets::only) {
        // The sets alone: no chain runs.
        stats.samples = set_drawings_.size();
        stats.unit = "sets";
        fp::Image img;
        img.width = frame_.width;
        img.height = frame_.height;
        img.pixels =
            fp_render::cairo_raster(frame_.width, frame_.height, [&](cairo_t* cr) { draw_set_panel(cr); });
        ctx.progress(1);
        return img;
    }
    fp::Image img;
    img.width = frame_.width;
    img.height = frame_.height;
    img.channels = 3;
    const uint32_t H = uint32_t(frame_.height);
    fp::Histogram total;
    if (double_)
        render_t<double>(ctx, stats, total, &img.pixels, 0, H, colour_, colourer_->reads_hits_only());
    else
        render_t<float>(ctx, stats, total, &img.pixels, 0, H, colour_, colourer_->reads_hits_only());
    if (ctx.cancelled()) throw fp::Cancelled();
    if (ctx.rank() != 0) return img; // its share is in rank 0's histogram, which rank 0 resolves
    colourer_->resolve_parallel(total, frame_.background, img.pixels.data(), ctx);
    auto draw = [&](cairo_t* cr) {
        draw_sets(cr, set_drawings_, frame_.region, frame_.width, frame_.height, set_style_);
    };
    if (sets_ == Sets::over) fp_render::cairo_over(frame_.width, frame_.height, img.pixels.data(), draw);
    if (sets_ == Sets::beside) {
        // The sets on the left, the fractal's own pixels (unchanged) on the right.
        const std::vector<float> left =
            fp_render::cairo_raster(frame_.width, frame_.height, [&](cairo_t* cr) { draw_set_panel(cr); });
        const size_t row = size_t(frame_.width) * 3;
        std::vector<float> both(2 * row * size_t(frame_.height));
        for (size_t r = 0; r < size_t(frame_.height); ++r) {
            std::copy_n(left.data() + r * row, row, both.data() + 2 * r * row);
            std::copy_n(img.pixels.data() + r * row, row, both.data() + (2 * r + 1) * row);
        }
        img.pixels = std::move(both);
        img.width = 2 * frame_.width;
    }
    return img;
}

namespace {
/// A pass of a render in strips as seen by its renderer: everything as the host's context, but
/// the progress scaled down by the number of passes, so that the bar runs once over all of them.
class PassOfStrips final : public fp::RenderContext {
public:
    PassOfStrips(fp::RenderContext& base, uint64_t passes)
        : base_(base), passes_(std::max<uint64_t>(passes, 1)) {}
    unsigned workers() const override { return base_.workers(); }
    void parallel_for(size_t n, const std::function<void(size_t, unsigned)>& task) override {
        base_.parallel_for(n, task);
    }
    void progress(uint64_t units) override {
        const uint64_t want = (in_.fetch_add(units, std::memory_order_relaxed) + units) / passes_;
        uint64_t had = out_.load(std::memory_order_relaxed);
        while (want > had && !out_.compare_exchange_weak(had, want, std::memory_order_relaxed)) {
        }
        if (want > had) base_.progress(want - had);
    }
    bool cancelled() const override { return base_.cancelled(); }
    unsigned rank() const override { return base_.rank(); }
    unsigned ranks() const override { return base_.ranks(); }
    void combine(void* data, size_t bytes, size_t record,
                 const std::function<void(const void*, void*, size_t)>& fold, bool everywhere) override {
        base_.combine(data, bytes, record, fold, everywhere);
    }
    uint64_t memory_budget() const override { return base_.memory_budget(); }

private:
    fp::RenderContext& base_;
    uint64_t passes_;
    std::atomic<uint64_t> in_{0}, out_{0};
};
} // namespace

void ChaosGame::render_rows(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink) const {
    if (!streams_rows()) return fp::Renderer::render_rows(ctx, stats, sink);
    stats = fp::RenderStats{};
    const Plan pl = plan(std::max(1u, ctx.workers()), ctx.memory_budget());
    // (The host checked the budget; a caller that did not learns it here, before any work.)
    if (pl.bytes > ctx.memory_budget())
        throw fp::InputError("a " + std::to_string(frame_.width) + "x" + std::to_string(frame_.height) +
                             " render needs at least " + std::to_string(pl.bytes) +
                             " bytes of memory in strips of one row; the budget is " +
                             std::to_string(ctx.memory_budget()));
    if (double_)
        render_strips<double>(ctx, stats, sink, pl.summary_rows, pl.rows);
    else
        render_strips<float>(ctx, stats, sink, pl.summary_rows, pl.rows);
}

template <class T>
void ChaosGame::render_strips(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink,
                              uint32_t summary_rows, uint32_t rows) const {
    const uint32_t W = uint32_t(frame_.width), H = uint32_t(frame_.height);
    PassOfStrips pass(ctx, (H + summary_rows - 1) / summary_rows + (H + rows - 1) / rows);
    // Rank 0 adds up the summary, shades the strips and hands their rows on; the others lend
    // their chains to each strip.
    const bool root = ctx.rank() == 0;
    std::vector<float> pixels;
    fp::HistogramSummary whole;
    whole.begin(int(W), int(H));
    for (uint32_t r0 = 0; r0 < H; r0 += summary_rows) {
        fp::Histogram part;
        fp::RenderStats st;
        render_t<T>(pass, st, part, nullptr, r0, std::min(summary_rows, H - r0), false, true);
        if (ctx.cancelled()) throw fp::Cancelled();
        if (root) whole.add(part, int(r0), &ctx);
    }
    for (uint32_t r0 = 0; r0 < H; r0 += rows) {
        fp::Histogram part;
        fp::RenderStats st;
        render_t<T>(pass, st, part, nullptr, r0, std::min(rows, H - r0), colour_,
                    colourer_->reads_hits_only());
        // Every strip runs every chain: the counts of one, and the points drawn of all.
        const uint64_t drawn = r0 == 0 ? 0 : stats.drawn;
        if (r0 == 0) stats = st;
        stats.drawn = drawn + st.drawn;
        if (ctx.cancelled()) throw fp::Cancelled();
        if (!root) continue;
        pixels.resize(size_t(part.height) * W * 3);
        colourer_->resolve_rows(part, int(r0), whole, frame_.background, pixels.data(), ctx);
        sink.rows(int(r0), part.height, pixels.data());
    }
    const uint32_t strips = (H + rows - 1) / rows, counts = (H + summary_rows - 1) / summary_rows;
    stats.how = "in " + std::to_string(strips) + " strips of " + std::to_string(rows) +
                (rows == 1 ? " row" : " rows") + " after " + std::to_string(counts) + " pass" +
                (counts == 1 ? "" : "es") + " counting hits";
}

template <class T>
void ChaosGame::render_t(fp::RenderContext& ctx, fp::RenderStats& stats, fp::Histogram& total,
                         std::vector<float>* pixels, uint32_t row0, uint32_t rows, bool colour,
                         bool hits_total) const {
    const unsigned workers = std::max(1u, ctx.workers());
    const size_t px = size_t(frame_.width) * size_t(rows);
    const bool last = colour && last_;
    // Over several ranks (MPI), the blocks are cut the same way on every rank whatever its
    // thread count (as for 2 workers a rank), and rank r runs blocks r, r + N, r + 2N, ...;
    // each chain runs on exactly one rank, with its own stream, so the sums are the same.
    const unsigned rank = ctx.rank(), ranks = std::max(1u, ctx.ranks());
    std::vector<Span> spans = block_spans(chains_, ranks > 1 ? 2 * ranks : workers);
    if (ranks > 1) {
        std::vector<Span> mine;
        for (size_t b = rank; b < spans.size(); b += ranks) mine.push_back(spans[b]);
        spans = std::move(mine);
    }
    // A checkpointed render (`--checkpoint`, `--resume`; whole renders on one process: the host
    // refuses the rest) keeps the chains' final states and stops for each checkpoint.
    std::unique_ptr<Keeping> keeping;
    if (ctx.checkpointing() || ctx.resume_from()) {
        if (ranks > 1 || row0 != 0 || rows != uint32_t(frame_.height))
            throw fp::InputError("checkpoints are kept of a whole render on one process (not in strips, not "
                                 "over MPI ranks)");
        keeping = std::make_unique<Keeping>();
        keeping->finals.assign(chains_, ChainRec{0, 0, 0, 0, not_final, 0, 0, 0, 0, 0, 0, 0, 0});
    }
    Keeping* keep = keeping.get();
    // The total as hit counts alone (8 bytes a bin, not 32): a quarter of the memory to fault
    // in, fold, summarise and shade.
    const bool hits8 = hits_total && !colour && !keep;
    std::vector<Task> work;
    // The bins' last writes a checkpoint has folded (pixel rule last), and the stats of the
    // work it holds.
    std::vector<LastWrite> folded_last;
    BlockResult base;
    const auto poll = [&ctx] {
        if (ctx.cancelled()) throw fp::Cancelled();
    };
    if (keep) {
        // The histogram first (a resumed one is read into it).
        total.width = frame_.width;
        total.height = int(rows);
        assign_huge(total.bins, px, poll);
        if (last) {
            assign_huge(total.last, px, poll);
            folded_last.assign(px, LastWrite{0, 0, 0, 0, 0, 0});
        }
    }
    if (fp::CheckpointSource* in = ctx.resume_from()) {
        resume<T>(*in, work, *keep, total, folded_last, base);
        ctx.progress(keep->progress.load());
    } else {
        for (const Span& sp : spans) {
            Task t;
            t.c0 = sp.c0;
            t.nb = sp.nb;
            work.push_back(std::move(t));
        }
    }
    // Per worker: its block state and its histogram (one extra bin that takes the points not
    // plotted), both made by the worker itself on its first task (first touch).
    std::vector<std::unique_ptr<Scratch<T>>> scratch(workers);
    std::vector<WorkerHist> hists(workers);

    // One task per worker; each takes the next item of the work list until none is left, in
    // order: item 0 allocates the total histogram, item 1 the image (tens of MiB of fresh
    // pages: page faults and zeroing, serial work that would otherwise follow the chains on
    // one thread; first, so that two workers take one each), then the blocks, the large ones
    // first. Which worker runs which block does not change the image (exact merge). A
    // checkpointed render goes in rounds: when a checkpoint is due, each worker stops its block
    // at the next poll and takes no other; the workers' histograms are folded into the total,
    // the checkpoint written, and the next round continues the blocks where they stopped.
    for (bool first = true;; first = false) {
        std::atomic<size_t> next{0};
        const size_t head = first ? 2 : 0, items = work.size() + head;
        if (keep) keep->stop.store(false);
        ctx.parallel_for(workers, [&](size_t, unsigned w) {
            if (w >= workers) throw fp::InternalError("chaos-game: worker index out of range");
            for (size_t it; (it = next.fetch_add(1, std::memory_order_relaxed)) < items;) {
                if (ctx.cancelled()) throw fp::Cancelled();
                if (it == 0 && head) {
                    if (keep) continue; // (made above)
                    total.width = frame_.width;
                    total.height = int(rows);
                    if (hits8)
                        assign_huge(total.hits, px, poll);
                    else
                        assign_huge(total.bins, px, poll);
                    if (last) assign_huge(total.last, px, poll);
                    continue;
                }
                if (it == 1 && head) {
                    if (pixels) assign_huge(*pixels, size_t(frame_.width) * size_t(frame_.height) * 3, poll);
                    continue;
                }
                if (keep && keep->stop.load(std::memory_order_relaxed)) return;
                Task& t = work[it - head];
                if (t.done) continue;
                if (!scratch[w]) scratch[w] = std::make_unique<Scratch<T>>(maps_.size());
                if (!hists[w].bins.get() && !hists[w].hits.get())
                    hists[w].alloc(px, colour, last, tallies_.get(), poll);
                if (rules_ && colour)
                    t.done = run_block<T, true, true>(t, *scratch[w], hists[w], ctx, row0, rows, keep);
                else if (rules_)
                    t.done = run_block<T, true, false>(t, *scratch[w], hists[w], ctx, row0, rows, keep);
                else if (colour)
                    t.done = run_block<T, false, true>(t, *scratch[w], hists[w], ctx, row0, rows, keep);
                else
                    t.done = run_block<T, false, false>(t, *scratch[w], hists[w], ctx, row0, rows, keep);
                if (!t.done) return; // stopped for a checkpoint
            }
        });
        if (!keep) break;
        // Every task done: the last checkpoint holds the finished render (to continue to more
        // points); else the one that is due.
        fold(ctx, hists, total, folded_last, px);
        const bool finished = std::all_of(work.begin(), work.end(), [](const Task& t) { return t.done; });
        save<T>(ctx, work, *keep, total, folded_last, base);
        if (finished) break;
    }
    scratch.clear();

    stats.samples = base.plotted;
    stats.restarts = base.restarts;
    stats.bad_values = base.bad;
    for (const auto& t : work) {
        stats.samples += t.res.plotted;
        stats.restarts += t.res.restarts;
        stats.bad_values += t.res.bad;
    }
    stats.unit = "points";

    // (A checkpointed render folded them into the total for its last checkpoint.)
    if (keep) hists.clear();
    // Sum the workers' histograms (exact integer sums; rows in parallel).
    const size_t rows_per_task = 16;
    const size_t tasks = (size_t(rows) + rows_per_task - 1) / rows_per_task;
    // The hits of each task's rows, summed here rather than in a serial pass over the 32 MiB
    // of the total afterwards (part of the fixed cost that limits the speed-up on 2 threads).
    std::vector<uint64_t> drawn(tasks, 0);
    // Over several ranks with last colours: this rank's winning (step, chain) per bin, for the
    // ranks' merge by the same order.
    std::vector<LastWrite> rank_last(ranks > 1 && last ? px : 0);
    ctx.parallel_for(tasks, [&](size_t t, unsigned) {
        poll();
        const size_t b0 = t * rows_per_task * size_t(frame_.width);
        const size_t b1 = std::min(px, b0 + rows_per_task * size_t(frame_.width));
        if (hits8) {
            uint64_t* out = total.hits.data();
            for (auto& h : hists) h.add_hits_to(out, b0, b1);
            uint64_t d = 0;
            for (size_t i = b0; i < b1; ++i) d += out[i];
            drawn[t] = d;
            return;
        }
        fp::HistBin* out = total.bins.data();
        for (auto& h : hists) h.add_to(out, b0, b1, false);
        if (last) {
            // Each bin's last colour: the workers' entry with the largest (step, chain).
            for (size_t i = b0; i < b1; ++i) {
                LastWrite best = folded_last.empty() ? LastWrite{0, 0, 0, 0, 0, 0} : folded_last[i];
                for (const auto& h : hists) {
                    const LastWrite* lw = h.last.get();
                    if (!lw) continue;
                    const LastWrite& e = lw[i];
                    if (later(e, best)) best = e;
                }
                total.last[i] = fp::LastColour{best.r, best.g, best.b};
                if (!rank_last.empty()) rank_last[i] = best;
            }
        }
        uint64_t d = 0;
        for (size_t i = b0; i < b1; ++i) d += out[i].hits;
        drawn[t] = d;
    });
    // The histogram holds exactly the points that landed in the image.
    stats.drawn = 0;
    for (uint64_t d : drawn) stats.drawn += d;
    for (const auto& h : hists) {
        for (const auto& [i, v] : h.spills) {
            fp::HistBin& o = total.bins[i];
            o.hits += v[0];
            stats.drawn += v[0];
            o.r += v[1];
            o.g += v[2];
            o.b += v[3];
        }
    }
    if (ranks > 1) combine_ranks(ctx, stats, total, rank_last);
}

// ---------------------------------------------------------------- checkpoints
void ChaosGame::fold(fp::RenderContext& ctx, std::vector<WorkerHist>& hists, fp::Histogram& total,
                     std::vector<LastWrite>& last, size_t px) const {
    // Rows of bins in parallel, as the final sum; the spills and the flushed hits after.
    const size_t per = size_t(1) << 16;
    ctx.parallel_for((px + per - 1) / per, [&](size_t t, unsigned) {
        const size_t b0 = t * per, b1 = std::min(px, b0 + per);
        for (auto& h : hists) {
            h.add_to(total.bins.data(), b0, b1, true);
            if (LastWrite* lw = h.last.get()) {
                for (size_t i = b0; i < b1; ++i) {
                    if (later(lw[i], last[i])) last[i] = lw[i];
                    lw[i] = LastWrite{0, 0, 0, 0, 0, 0};
                }
            }
        }
    });
    for (auto& h : hists) {
        for (const auto& [i, v] : h.spills) {
            fp::HistBin& o = total.bins[i];
            o.hits += v[0];
            o.r += v[1];
            o.g += v[2];
            o.b += v[3];
        }
        h.spills.clear();
        h.clear_dummy();
        h.since = 0;
    }
}

template <class T>
void ChaosGame::save(fp::RenderContext& ctx, const std::vector<Task>& tasks, const Keeping& keep,
                     const fp::Histogram& total, const std::vector<LastWrite>& last,
                     const BlockResult& base) const {
    PayloadHead head;
    head.precision = uint32_t(sizeof(T));
    head.points = points_, head.chains = chains_;
    head.width = uint32_t(frame_.width), head.rows = uint32_t(total.height);
    head.colour = colour_ ? 1 : 0, head.last = last.empty() ? 0 : 1;
    head.samples = base.plotted, head.restarts = base.restarts, head.bad = base.bad;
    for (const Task& t : tasks) {
        head.samples += t.res.plotted, head.restarts += t.res.restarts, head.bad += t.res.bad;
        if (!t.done) ++head.tasks;
    }
    head.progress = keep.progress.load();
    for (const ChainRec& c : keep.finals) head.finals += c.step != not_final ? 1 : 0;
    ctx.write_checkpoint([&](fp::CheckpointSink& out) {
        out.write(&head, sizeof head);
        for (const Task& t : tasks) {
            if (t.done) continue;
            // Saved chains (stopped mid-way), or fresh ones (never started: their ids).
            const uint64_t kind = t.saved.empty() ? 0 : 1, n = t.size();
            out.write(&kind, 8);
            out.write(&n, 8);
            if (kind == 1) {
                out.write(t.saved.data(), n * sizeof(ChainRec));
            } else {
                std::vector<uint32_t> ids(n);
                for (size_t i = 0; i < n; ++i) ids[i] = t.chain(i);
                out.write(ids.data(), n * sizeof(uint32_t));
            }
        }
        for (const ChainRec& c : keep.finals)
            if (c.step != not_final) out.write(&c, sizeof c);
        out.write(total.bins.data(), total.bins.size() * sizeof(fp::HistBin));
        if (!last.empty()) out.write(last.data(), last.size() * sizeof(LastWrite));
    });
}

template <class T>
void ChaosGame::resume(fp::CheckpointSource& in, std::vector<Task>& tasks, Keeping& keep,
                       fp::Histogram& total, std::vector<LastWrite>& last, BlockResult& base) const {
    PayloadHead head;
    in.read(&head, sizeof head);
    // The envelope matched the recipe (but points): these only fail for a damaged payload.
    if (head.version != PayloadHead{}.version || head.precision != sizeof(T) || head.chains != chains_ ||
        head.width != uint32_t(frame_.width) || head.rows != uint32_t(total.height) ||
        head.colour != (colour_ ? 1u : 0u) || head.last != (last.empty() ? 0u : 1u) ||
        head.points > points_ || head.tasks > chains_ || head.finals > chains_)
        throw fp::InputError("the checkpoint's payload does not fit this render (damaged?)");
    base.plotted = head.samples, base.restarts = head.restarts, base.bad = head.bad;
    keep.progress.store(head.progress);
    // The points each chain gains over the checkpoint's.
    const auto more = [&](uint64_t chain) {
        return points_of(chain, points_, chains_) - points_of(chain, head.points, chains_);
    };
    // Every field bounded by the recipe: a forged payload (its CRC recomputed) must not make a
    // resume run longer than the render it claims to continue, nor read out of its arrays.
    // Each chain is in the payload once: pending (fresh, or suspended and running) or final.
    std::vector<uint8_t> seen(chains_, 0);
    const auto check_chain = [&](uint64_t chain) {
        if (chain >= chains_)
            throw fp::InputError("the checkpoint's payload names a chain that does not exist");
        if (seen[chain]++) throw fp::InputError("the checkpoint's payload names a chain twice (damaged?)");
    };
    const auto check_state = [&](const ChainRec& c) {
        if (c.left > points_of(c.chain, head.points, chains_) || c.prev > maps_.size() || c.active > 1)
            throw fp::InputError(
                "the checkpoint's payload holds a chain state this render cannot have (damaged?)");
    };
    std::vector<uint32_t> fresh;
    for (uint64_t t = 0; t < head.tasks; ++t) {
        uint64_t kind = 0, n = 0;
        in.read(&kind, 8);
        in.read(&n, 8);
        if (kind > 1 || n > block_size) throw fp::InputError("the checkpoint's payload is damaged");
        if (kind == 0) {
            std::vector<uint32_t> ids(n);
            in.read(ids.data(), n * sizeof(uint32_t));
            for (uint32_t c : ids) check_chain(c), fresh.push_back(c);
            continue;
        }
        Task task;
        task.saved.resize(n);
        in.read(task.saved.data(), n * sizeof(ChainRec));
        // The lanes still running, with the points they gain; those that finished are in the
        // final states.
        std::vector<ChainRec> running;
        for (ChainRec c : task.saved) {
            if (c.chain >= chains_)
                throw fp::InputError("the checkpoint's payload names a chain that does not exist");
            check_state(c);
            if (!c.active) continue; // (recorded again among the final states)
            check_chain(c.chain);
            c.left += more(c.chain);
            running.push_back(c);
        }
        task.saved = std::move(running);
        if (!task.saved.empty()) tasks.push_back(std::move(task));
    }
    // Finished chains: final, or, with more points now, running on from their next step, in
    // blocks of chains at the same step (a chain that never had a point starts fresh).
    std::vector<ChainRec> again;
    for (uint64_t f = 0; f < head.finals; ++f) {
        ChainRec c;
        in.read(&c, sizeof c);
        check_chain(c.chain);
        check_state(c);
        const uint64_t gain = c.idle > max_idle_restarts ? 0 : more(c.chain);
        if (gain == 0) {
            keep.finals[c.chain] = c;
        } else if (c.step == 0) {
            fresh.push_back(c.chain);
        } else {
            c.left = gain;
            c.active = 1;
            again.push_back(c);
        }
    }
    std::stable_sort(again.begin(), again.end(),
                     [](const ChainRec& a, const ChainRec& b) { return a.step < b.step; });
    for (size_t i = 0; i < again.size();) {
        Task task;
        const uint64_t step = again[i].step;
        while (i < again.size() && again[i].step == step && task.saved.size() < block_size)
            task.saved.push_back(again[i++]);
        tasks.push_back(std::move(task));
    }
    for (size_t i = 0; i < fresh.size(); i += block_size) {
        Task task;
        task.ids.assign(fresh.begin() + std::ptrdiff_t(i),
                        fresh.begin() + std::ptrdiff_t(std::min(fresh.size(), i + block_size)));
        tasks.push_back(std::move(task));
    }
    if (std::find(seen.begin(), seen.end(), uint8_t(0)) != seen.end())
        throw fp::InputError("the checkpoint's payload leaves a chain out (damaged?)");
    in.read(total.bins.data(), total.bins.size() * sizeof(fp::HistBin));
    if (!last.empty()) in.read(last.data(), last.size() * sizeof(LastWrite));
    if (in.left() != 0) throw fp::InputError("the checkpoint's payload is longer than this render's state");
}

// The ranks' shares folded into rank 0's (RenderContext::combine): exact sums of the bins and
// the stats, and each bin's last colour from the rank with the largest (step, chain).
void ChaosGame::combine_ranks(fp::RenderContext& ctx, fp::RenderStats& stats, fp::Histogram& total,
                              std::vector<LastWrite>& rank_last) const {
    uint64_t counts[4] = {stats.samples, stats.restarts, stats.bad_values, stats.drawn};
    ctx.combine(counts, sizeof counts, sizeof(uint64_t), fp::fold::sum<uint64_t>, false);
    stats.samples = counts[0], stats.restarts = counts[1], stats.bad_values = counts[2],
    stats.drawn = counts[3];
    // (Folded as plain 64-bit counters: a sum does not care where a bin starts.)
    if (!total.hits.empty())
        ctx.combine(total.hits.data(), total.hits.size() * sizeof(uint64_t), sizeof(uint64_t),
                    fp::fold::sum<uint64_t>, false);
    else
        ctx.combine(total.bins.data(), total.bins.size() * sizeof(fp::HistBin), sizeof(uint64_t),
                    fp::fold::sum<uint64_t>, false);
    if (rank_last.empty()) return;
    ctx.combine(
        rank_last.data(), rank_last.size() * sizeof(LastWrite), sizeof(LastWrite),
        [](const void* in, void* inout, size_t n) {
            const auto* a = static_cast<const LastWrite*>(in);
            auto* b = static_cast<LastWrite*>(inout);
            for (size_t i = 0; i < n; ++i)
                if (later(a[i], b[i])) b[i] = a[i];
        },
        false);
    for (size_t i = 0; i < rank_last.size(); ++i)
        total.last[i] = fp::LastColour{rank_last[i].r, rank_last[i].g, rank_last[i].b};
}

// ---------------------------------------------------------------- map choice
// Rules on: chosen[i] = the map drawn among those allowed for chain i (not its previous map,
// not a map whose set holds its point) with probability q_j / (sum of allowed q); k when none
// is allowed or the chain is inactive; restart[i] = 1 for active chains with none allowed.
// One Transform::contains call per map with a set on the whole block, then the draw
// (kernels-inl.hpp's draw_rules and draw_paper: paper 01's loop, reading the drawn map's test
// from those rows; after rejection_draws rejections the direct draw: one more pcg32 output r,
// u = floor(r * total / 2^32) in [0, total), chosen = #{j : cum_j <= u}, the first map whose
// cumulative weight passes u).
template <class T>
void ChaosGame::choose_rules(Scratch<T>& s, size_t nb) const {
    const fp::Points<const T> pts{s.x.get(), s.y.get(), nb};
    unsigned char* inside = s.inside.get();
    for (uint32_t j : region_maps_) maps_[j]->contains(pts, inside + size_t(j) * block_size);
    DrawArgs a{
        s.rs.get(),     s.ri.get(),      s.prev.get(), s.active.get(),         inside,    block_size,
        s.chosen.get(), s.restart.get(), nb,           uint32_t(maps_.size()), q_.data(), alias_thr_.data(),
        alias_.data(),  uniform_};
    HWY_DYNAMIC_DISPATCH(draw_rules)(a);
}

// Rules off: Walker's alias table, one pcg32 output per chain.
template <class T>
void ChaosGame::choose_alias(Scratch<T>& s, size_t nb) const {
    DrawArgs a{
        s.rs.get(),     s.ri.get(),      s.prev.get(), s.active.get(),         nullptr, 0,
        s.chosen.get(), s.restart.get(), nb,           uint32_t(maps_.size()), nullptr, alias_thr_.data(),
        alias_.data()};
    HWY_DYNAMIC_DISPATCH(draw_alias)(a);
}

// ---------------------------------------------------------------- grouping by map
// Group the chains by chosen map (chains with chosen = k stay), call the iteration scheme
// once per map on its points, and put the new points back.
template <class T>
void ChaosGame::move_chains(Scratch<T>& s, size_t nb, uint64_t n) const {
    const size_t k = maps_.size();
    T* __restrict x = s.x.get();
    T* __restrict y = s.y.get();
    T* __restrict gx = s.gx.get();
    T* __restrict gy = s.gy.get();
    const uint32_t* __restrict chosen = s.chosen.get();
    uint32_t* __restrict cnt = s.cnt.get();
    if (k <= max_compress_maps) {
        // Each map's points compressed into its own segment with their chains' indices
        // (kernels-inl.hpp's group_t), one step call per map, then scattered back.
        const uint32_t* __restrict gi = s.gi.get();
        fp_chaos::group(GroupArgs<T>{x, y, chosen, gx, gy, s.gi.get(), cnt, seg_stride, nb, uint32_t(k)});
        for (size_t j = 0; j < k; ++j) {
            const size_t at = j * seg_stride, len = cnt[j];
            if (!len) continue;
            iteration_->step(*maps_[j], fp::Points<T>{gx + at, gy + at, len}, nullptr, n);
            fp_chaos::scatter(gx + at, gy + at, gi + at, len, x, y);
        }
        return;
    }
    // Counting sort into contiguous segments; perm remembers where each point came from.
    uint32_t* __restrict perm = s.perm.get();
    for (size_t j = 0; j <= k; ++j) cnt[j] = 0;
    for (size_t i = 0; i < nb; ++i) ++cnt[chosen[i]];
    uint32_t start = 0;
    for (size_t j = 0; j <= k; ++j) {
        const uint32_t c = cnt[j];
        cnt[j] = start;
        start += c;
    }
    for (size_t i = 0; i < nb; ++i) {
        const uint32_t t = cnt[chosen[i]]++;
        perm[t] = uint32_t(i);
        gx[t] = x[i];
        gy[t] = y[i];
    }
    // cnt[j] is now the end of map j's segment.
    for (size_t j = 0; j < k; ++j) {
        const size_t beg = j == 0 ? 0 : cnt[j - 1], len = cnt[j] - beg;
        if (len) iteration_->step(*maps_[j], fp::Points<T>{gx + beg, gy + beg, len}, nullptr, n);
    }
    const size_t movers = cnt[k - 1];
    for (size_t t = 0; t < movers; ++t) {
        x[perm[t]] = gx[t];
        y[perm[t]] = gy[t];
    }
}

// ---------------------------------------------------------------- start points
// For the m chains list[0..m): a start point. With `start` given, that point; else a uniform
// point of the start box (the view unless `start_box`) outside every map's set, drawn from
// the chain's own stream (at most start_tries candidates, the last one taken whatever it is).
// Batched: one contains call per map with a set per round, over all pending chains.
template <class T>
void ChaosGame::new_starts(Scratch<T>& s, const uint32_t* list, size_t m) const {
    T* x = s.x.get();
    T* y = s.y.get();
    if (has_start_) {
        for (size_t t = 0; t < m; ++t) x[list[t]] = T(start_.x), y[list[t]] = T(start_.y);
        return;
    }
    uint32_t* pend = s.pend.get();
    std::copy(list, list + m, pend);
    size_t np = m;
    T* sx = s.sx.get();
    T* sy = s.sy.get();
    unsigned char* hit = s.hit.get();
    unsigned char* any = s.any.get();
    for (unsigned tr = 0; tr < start_tries && np > 0; ++tr) {
        for (size_t t = 0; t < np; ++t) {
            const uint32_t i = pend[t];
            const double ux = pcg_uniform(s.rs.get()[i], s.ri.get()[i]);
            const double uy = pcg_uniform(s.rs.get()[i], s.ri.get()[i]);
            sx[t] = T(start_box_.xmin + (start_box_.xmax - start_box_.xmin) * ux);
            sy[t] = T(start_box_.ymin + (start_box_.ymax - start_box_.ymin) * uy);
            any[t] = 0;
        }
        if (tr + 1 < start_tries) {
            const fp::Points<const T> cand{sx, sy, np};
            for (uint32_t j : region_maps_) {
                maps_[j]->contains(cand, hit);
                for (size_t t = 0; t < np; ++t) any[t] |= hit[t];
            }
        }
        size_t keep = 0;
        for (size_t t = 0; t < np; ++t) {
            const uint32_t i = pend[t];
            if (any[t]) {
                pend[keep++] = i;
            } else {
                x[i] = sx[t];
                y[i] = sy[t];
            }
        }
        np = keep;
    }
}

// ---------------------------------------------------------------- the fused step
template <class T, bool Colour>
FusedArgs<T> ChaosGame::fused_args(Scratch<T>& s, const BookArgs<T>& bv, uint32_t* hits, const uint32_t* lag,
                                   bool steady) const {
    FusedArgs<T> f;
    f.tables = &lane_tables<T, Colour>();
    f.draw = DrawArgs{s.rs.get(), s.ri.get(),     s.prev.get(),    s.active.get(), nullptr,
                      0,          s.chosen.get(), s.restart.get(), bv.nb,          uint32_t(maps_.size()),
                      nullptr,    nullptr,        nullptr};
    f.book = bv;
    f.hits = hits;
    f.lag = lag;
    f.steady = steady;
    return f;
}

static_assert(uint32_t(ProgOp::map) == uint32_t(fp::SchemeProgram::Op::map) &&
              uint32_t(ProgOp::copy) == uint32_t(fp::SchemeProgram::Op::copy) &&
              uint32_t(ProgOp::lin2) == uint32_t(fp::SchemeProgram::Op::lin2) &&
              uint32_t(ProgOp::lin3) == uint32_t(fp::SchemeProgram::Op::lin3));

template <class T>
bool ChaosGame::lane_program(uint64_t n, LaneProgram<T>& out) const {
    // (Asked at every block step: a program is a few dozen bytes to record and compare, and a
    // kernel is recorded, not run.)
    fp::SchemeProgram first, other;
    const bool dbl = std::is_same_v<T, double>;
    if (!iteration_->program(*maps_[0], n, dbl, first)) return false;
    for (size_t j = 1; j < maps_.size(); ++j)
        if (!iteration_->program(*maps_[j], n, dbl, other) || !other.same_as(first)) return false;
    out.size = first.size;
    out.regs = first.regs;
    for (uint32_t i = 0; i < first.size; ++i) {
        const fp::SchemeProgram::Instr& a = first.code[i];
        auto& b = out.code[i];
        b.op = ProgOp(uint32_t(a.op));
        b.dst = a.dst, b.u = a.u, b.v = a.v, b.w = a.w;
        for (size_t j = 0; j < fp::SchemeProgram::coefficients(a.op); ++j) b.k[j] = T(a.k[j]);
    }
    return true;
}

// ---------------------------------------------------------------- last colours
void ChaosGame::write_last(WorkerHist& hist, const uint32_t* idx, const uint64_t* dep, size_t nb, uint64_t n,
                           const uint32_t* chain_of, uint32_t dummy) {
    write_last_colours(hist.last.get(), idx, nb, n, chain_of, dummy, [&](size_t i) {
        const uint64_t v = dep[i]; // {1, r, g, b} in 16 bits each
        return std::array<uint16_t, 3>{uint16_t(v >> 16), uint16_t(v >> 32), uint16_t(v >> 48)};
    });
}

// ---------------------------------------------------------------- one block of chains
template <class T, bool Rules, bool Colour>
bool ChaosGame::run_block(Task& t, Scratch<T>& s, WorkerHist& hist, fp::RenderContext& ctx, uint32_t row0,
                          uint32_t rows, Keeping* keep) const {
    const size_t k = maps_.size();
    const size_t nb = t.size();
    BlockResult& res = t.res;
    const uint32_t none = uint32_t(k);
    // A lane's state as a checkpoint records it, `step` the step it runs next.
    const auto record = [&](size_t i, uint64_t step) {
        return ChainRec{
            double(s.x.get()[i]), double(s.y.get()[i]), s.rs.get()[i],  s.left.get()[i], step,
            s.chain.get()[i],     s.prev.get()[i],      s.age.get()[i], s.idle.get()[i], s.active.get()[i],
            s.cr.get()[i],        s.cg.get()[i],        s.cb.get()[i]};
    };

    // Initial state: fresh chains at step 0, or where a checkpoint left them.
    uint64_t nominal = 0; // steps of this block without restarts, for progress
    size_t nlive = 0;
    uint64_t n0 = 0;
    uint32_t* list = s.perm.get();
    for (size_t i = 0; i < nb; ++i) {
        const uint64_t chain = t.chain(i);
        s.chain.get()[i] = uint32_t(chain);
        s.fin.get()[i] = 0;
        if (!t.saved.empty()) {
            const ChainRec& c = t.saved[i];
            s.rs.get()[i] = c.rs;
            s.ri.get()[i] = (chain << 1) | 1u;
            s.left.get()[i] = c.left;
            s.active.get()[i] = c.active;
            s.prev.get()[i] = c.prev;
            s.age.get()[i] = c.age;
            s.idle.get()[i] = c.idle;
            s.cr.get()[i] = c.cr, s.cg.get()[i] = c.cg, s.cb.get()[i] = c.cb;
            s.x.get()[i] = T(c.x);
            s.y.get()[i] = T(c.y);
            n0 = c.step;
            // (A lane that finished before the stop has its final state recorded already.)
            s.fin.get()[i] = c.active ? 0 : 1;
            if (c.active) {
                nominal += (c.age < skip_ ? skip_ - c.age : 0) + c.left;
                ++nlive;
            }
            continue;
        }
        pcg_seed(seed_, chain, s.rs.get()[i], s.ri.get()[i]);
        const uint64_t left = points_of(chain, points_, chains_);
        s.left.get()[i] = left;
        s.active.get()[i] = left > 0 ? 1u : 0u;
        s.prev.get()[i] = none;
        s.age.get()[i] = 0;
        s.idle.get()[i] = 0;
        if (last_) {
            // Algorithm 2, line 4: "c = random colour", from a stream of the chain's own that
            // its draws do not use.
            fp::Rng r = fp::chain_stream(seed_ + colour_stream_salt, chain);
            s.cr.get()[i] = fp::uniform_float(r);
            s.cg.get()[i] = fp::uniform_float(r);
            s.cb.get()[i] = fp::uniform_float(r);
        } else {
            s.cr.get()[i] = initial_colour_.r;
            s.cg.get()[i] = initial_colour_.g;
            s.cb.get()[i] = initial_colour_.b;
        }
        s.x.get()[i] = T(0);
        s.y.get()[i] = T(0);
        if (left > 0) {
            nominal += skip_ + left;
            list[nlive++] = uint32_t(i);
        } else if (keep) {
            // No points: final before it starts (step 0 says so to a continued render).
            keep->finals[chain] = record(i, 0);
            s.fin.get()[i] = 1;
        }
    }
    // The lanes past the last chain, up to the block's end, inactive: the fused step reads
    // whole vectors and takes `active` alone for the lanes that step.
    std::fill(s.active.get() + nb, s.active.get() + block_size, 0u);
    // Whether every chain's colour starts in [0, 1] (FusedArgs::colours_in_range): the fused
    // step keeps them there; a colourer's own update ends the promise for the block.
    bool colours_in_range = true;
    for (size_t i = 0; i < nb; ++i)
        colours_in_range =
            colours_in_range && in_unit(s.cr.get()[i]) && in_unit(s.cg.get()[i]) && in_unit(s.cb.get()[i]);
    if (t.saved.empty()) new_starts(s, list, nlive);
    const auto report = [&](uint64_t units) {
        ctx.progress(units);
        if (keep) keep->progress.fetch_add(units, std::memory_order_relaxed);
    };

    // The bookkeeping's arrays and the constants of the deposit.
    BookArgs<T> bv{s.x.get(),   s.y.get(),    s.chosen.get(),  s.prev.get(),
                   s.age.get(), s.idle.get(), s.restart.get(), s.plotf.get(),
                   s.idx.get(), s.left.get(), s.active.get(),  s.cr.get(),
                   s.cg.get(),  s.cb.get(),   s.dep.get(),     nb};
    bv.xmin = T(frame_.region.xmin), bv.xmax = T(frame_.region.xmax), bv.ymin = T(frame_.region.ymin),
    bv.ymax = T(frame_.region.ymax);
    bv.scx = T(double(frame_.width) / (frame_.region.xmax - frame_.region.xmin)),
    bv.scy = T(double(frame_.height) / (frame_.region.ymax - frame_.region.ymin));
    bv.W = uint32_t(frame_.width), bv.H = uint32_t(frame_.height);
    bv.row0 = row0, bv.rows = rows;
    bv.dummy = uint32_t(size_t(frame_.width) * size_t(rows));
    bv.skip = uint32_t(std::min<uint64_t>(skip_, 0xffffffffu));
    bv.none = none;

    uint32_t* __restrict chosen = s.chosen.get();
    uint32_t* __restrict prev = s.prev.get();
    uint32_t* __restrict age = s.age.get();
    uint32_t* __restrict idle = s.idle.get();
    const uint32_t* __restrict idx = s.idx.get();
    uint32_t* __restrict restart = s.restart.get();
    const uint64_t* __restrict dep = s.dep.get();
    Cnt4* const bins = hist.bins.get();
    uint32_t* const hits = hist.hits.get();
    uint64_t* __restrict left = s.left.get();
    uint32_t* __restrict active = s.active.get();
    unsigned char* __restrict moved = s.moved.get();
    float* __restrict cr = s.cr.get();
    float* __restrict cg = s.cg.get();
    float* __restrict cb = s.cb.get();

    // The fused step with hits only deposits each step's bins during the next step's pass (the
    // increments' cache misses then overlap its arithmetic instead of following it): `out`
    // takes this step's bins, `lag` holds the previous step's, deposited by the pass.
    // With colour, the packed colours go the same way: `dep_out` and `lag_dep`.
    uint32_t* out = s.idx.get();
    uint32_t* lag = nullptr;
    uint64_t* dep_out = s.dep.get();
    const uint64_t* lag_dep = nullptr;
    uint32_t nfull = 0;
    // The fused step's steady runs (fused_t with Steady): steps the block may still run that
    // way (0: not in one) and the steps run since the run began.
    uint64_t steady_left = 0, steady_steps = 0, steady_wait = 0;
    // A block of few chains counting hits only runs lean (kernels-inl.hpp's fused_run_t): the
    // fused steps up to the next poll in one call, each depositing its own bins.
    // (Not with a scheme's program, which may change from step to step.)
    const bool lean = fused_ && !program_ && !Colour && nb <= lean_chains;

    // The fused step's lagged deposits made now (at the block's end, or where it stops for a
    // checkpoint).
    const auto deposit_lag = [&] {
        if (lag && Colour && hist.tallies) {
            for (size_t i = 0; i < nb; ++i) {
                i = hist.tally(reinterpret_cast<const uint32_t*>(lag_dep), i, nb);
                if (i < nb) hist.spill(lag[i]);
            }
        } else if (lag && Colour) {
            uint32_t* const b32 = reinterpret_cast<uint32_t*>(bins);
            for (size_t i = 0; i < nb; ++i) {
                i = HWY_DYNAMIC_DISPATCH(deposit_colour)(b32, lag, lag_dep, i, nb, spill_hits);
                if (i < nb) hist.spill(lag[i]);
            }
        } else if (lag) {
            for (size_t i = 0; i < nb; ++i) ++hits[lag[i]];
        }
        lag = nullptr;
        lag_dep = nullptr;
    };

    // The end of a steady run before it ran its course (a checkpoint, or a step the fused step
    // cannot take): the state the step-by-step bookkeeping would hold, as at its end; the last
    // step's restarts, none, are cleared for settle_steady.
    const auto end_steady = [&] {
        if (steady_steps > 0) {
            const LaneTables<T>& lt = lane_tables<T, Colour>();
            if (lt.k == 1 && !lt.rules) pcg_jump(s.rs.get(), s.ri.get(), nb, steady_steps);
            std::memset(static_cast<void*>(restart), 0, nb * sizeof(uint32_t));
            res.plotted += settle_steady(s, nb, steady_steps);
        }
        steady_left = steady_steps = 0;
    };

    uint64_t reported = 0;
    size_t live = nlive;
    for (uint64_t n = n0; live > 0; ++n) {
        if (n % poll_steps == 0 && n > n0) {
            if (ctx.cancelled()) throw fp::Cancelled();
            const uint64_t done = std::min(nominal, (n - n0) * uint64_t(nlive));
            report(done - reported);
            reported = done;
            if (keep && (keep->stop.load(std::memory_order_relaxed) || ctx.checkpoint_due())) {
                // A checkpoint: stop here, with the state the step-by-step bookkeeping would
                // hold (a steady run settled, as at its end; the last step's restarts, none, are
                // cleared for settle_steady), the lagged deposits made, and save every lane.
                keep->stop.store(true, std::memory_order_relaxed);
                end_steady();
                deposit_lag();
                t.saved.resize(nb);
                for (size_t i = 0; i < nb; ++i) t.saved[i] = record(i, n);
                return false;
            }
        }
        const size_t live_before = live;

        // 1-5 in one fused pass (the maps known kernels of one kind), or: 1-3. choose a map
        // per chain (k = does not move this step), group the chains by map, one step call per
        // map, back in place; 4. colours (not when the colourer needs none); 5. bookkeeping,
        // bin indices and colour values, branch-free over the block.
        Counts sc;
        uint64_t steps_run = 1;
        // With a scheme's program: this step's, else (rare: no program at this n, or the maps'
        // differ) the generic step, after the fused step's pending work is settled.
        bool fz = fused_;
        if (program_) {
            fz = lane_program(n, s.program);
            if (!fz) {
                end_steady();
                steady_wait = 0;
                deposit_lag();
                bv.idx = s.idx.get();
                bv.dep = s.dep.get();
            }
        }
        if (fz) {
            if (steady_left == 0) {
                if (steady_wait > 0) {
                    --steady_wait;
                } else {
                    const SteadyCheck c = steady_budget(s, nb, bv.skip);
                    steady_left = c.budget;
                    steady_wait = c.wait;
                }
            }
            const bool steady = steady_left > 0;
            uint64_t ran = 1;
            if (lean) {
                // Up to the next poll (or the end of the steady run) in one call.
                const uint64_t m = steady ? std::min(steady_left, poll_steps - n % poll_steps) : 1;
                const RunCounts rc =
                    fp_chaos::fused_run(fused_args<T, Colour>(s, bv, hits, nullptr, steady), m);
                sc = rc.last;
                sc.plotted = rc.plotted;
                ran = rc.steps;
                n += ran - 1;
            } else {
                bv.idx = out;
                bv.dep = dep_out;
                FusedArgs<T> f = fused_args<T, Colour>(s, bv, hits, lag, steady);
                if (program_) f.program = &s.program;
                if constexpr (Colour) {
                    f.bins = reinterpret_cast<uint32_t*>(bins);
                    f.lag_dep = lag_dep;
                    f.full = s.full.get();
                    f.nfull = &nfull;
                    f.spill_at = hist.tallies ? tally_lagged : spill_lagged;
                    f.plane = uint32_t(hist.plane);
                    f.colours_in_range = colours_in_range;
                }
                sc = fp_chaos::fused(f);
                // Last colours: the step's plotted points (the dummy bin holds the others), each
                // the colour of its map, which the step left in `prev` (map rule only: see the
                // constructor).
                if (Colour && last_)
                    write_last_colours(hist.last.get(), out, nb, n, s.chain.get(), bv.dummy,
                                       [&](size_t i) { return map_q_[std::min(prev[i], none - 1)]; });
            }
            steps_run = ran;
            if (steady) {
                sc.still = uint32_t(live);
                steady_steps += ran;
                steady_left -= ran;
                // The end of a steady run: a restart (its chain must wait out its skip again),
                // or as many steps as the block's fewest points left, less one.
                if (steady_left == 0 || sc.restarts) {
                    // One map without the rules: the kernels left the streams where the run
                    // began (see fused_t); they move on by its length now, before any restart
                    // draws from them.
                    const LaneTables<T>& lt = lane_tables<T, Colour>();
                    if (lt.k == 1 && !lt.rules) pcg_jump(s.rs.get(), s.ri.get(), nb, steady_steps);
                    sc.plotted = settle_steady(s, nb, steady_steps);
                    steady_left = steady_steps = 0;
                }
            }
        } else {
            if constexpr (Rules)
                choose_rules(s, nb);
            else
                choose_alias(s, nb);
            move_chains(s, nb, n);
            if constexpr (Colour) {
                if (last_) {
                    // Algorithm 2: the colour changes with the points plotted only (line 16
                    // under "if i > 20"): the chains that move and are past their skip.
                    FP_IVDEP
                    for (size_t i = 0; i < nb; ++i) moved[i] = chosen[i] < none && age[i] >= bv.skip ? 1 : 0;
                } else {
                    FP_IVDEP
                    for (size_t i = 0; i < nb; ++i) moved[i] = chosen[i] < none ? 1 : 0;
                }
                colourer_->update(chosen, fp::ColourState{cr, cg, cb, nb}, colours_.data(), moved);
                colours_in_range = false; // (a colourer's rule: no promise of its range)
            }
            sc = fp_chaos::bookkeep(bv, Colour);
            if (Colour && last_) write_last(hist, idx, dep, nb, n, s.chain.get(), bv.dummy);
        }

        // 6. Deposit: one 4 x 32-bit add per chain, or one 32-bit increment when counting
        // hits only (the unplotted land in the last bin).
        if constexpr (Colour) {
            if (fz) {
                // Deposited by the next pass (the last one's after the loop); the bins it
                // found full spilled now.
                for (uint32_t t = 0; t < nfull; ++t)
                    if (hist.due(s.full.get()[t])) hist.spill(s.full.get()[t]);
                nfull = 0;
                lag = out;
                lag_dep = dep_out;
                out = out == s.idx.get() ? s.idx2.get() : s.idx.get();
                dep_out = dep_out == s.dep.get() ? s.dep2.get() : s.dep.get();
            } else if (hist.tallies) {
                // (The plotted points' maps are their colours.)
                for (size_t i = 0; i < nb; ++i) {
                    i = hist.tally(idx, chosen, i, nb);
                    if (i < nb) hist.spill(idx[i]);
                }
            } else {
                uint32_t* const b32 = reinterpret_cast<uint32_t*>(bins);
                for (size_t i = 0; i < nb; ++i) {
                    i = HWY_DYNAMIC_DISPATCH(deposit_colour)(b32, idx, dep, i, nb, spill_hits);
                    if (i < nb) hist.spill(idx[i]);
                }
            }
        } else {
            if (lean) {
                // (deposited by the lean run itself)
            } else if (fz) {
                lag = out;
                out = out == s.idx.get() ? s.idx2.get() : s.idx.get();
            } else {
                for (size_t i = 0; i < nb; ++i) ++hits[idx[i]];
            }
            hist.since += nb * steps_run;
            if (__builtin_expect(hist.since >= hits_flush, 0)) hist.flush();
        }

        res.plotted += sc.plotted;
        res.bad += sc.bad;
        live = sc.still;

        // 7. Restarts (rare): a fresh start point, or retirement after too many in a row.
        if (sc.restarts) {
            size_t m = 0;
            for (size_t i = 0; i < nb; ++i) {
                if (!restart[i]) continue;
                ++res.restarts;
                if (++idle[i] > max_idle_restarts) {
                    if (active[i]) --live;
                    active[i] = 0;
                    left[i] = 0;
                    continue;
                }
                if (!active[i]) continue; // finished with its last point (cannot happen: bad)
                prev[i] = none;
                age[i] = 0;
                list[m++] = uint32_t(i);
            }
            new_starts(s, list, m);
        }
        // 8. A checkpointed render records each chain's final state as it finishes or retires
        // (for a render continued to more points).
        if (keep && live < live_before) {
            for (size_t i = 0; i < nb; ++i) {
                if (active[i] || s.fin.get()[i]) continue;
                keep->finals[s.chain.get()[i]] = record(i, n + 1);
                s.fin.get()[i] = 1;
            }
        }
    }
    deposit_lag();
    report(nominal - std::min(nominal, reported));
    return true;
}

// ---------------------------------------------------------------- schema
constexpr fp::ParamSpec map_item_params[] = {
    fp::param::real("weight", "relative probability of choosing the map").def("1").above(0),
    fp::param::colour("colour",
                      "colour of the points the map produces (default: a built-in palette by index)")
        .opt(),
};

constexpr fp::ParamSpec params[] = {
    fp::param::integer("width", "image width in pixels").def("512").min(1).max(65536),
    fp::param::integer("height", "image height in pixels").def("512").min(1).max(65536),
    fp::param::reals("view", "the plotted region [xmin, xmax, ymin, ymax]")
        .def("[-1.5, 1.5, -1.5, 1.5]")
        .len(4),
    fp::param::integer("points", "total number of points plotted over all chains")
        .def("1000000")
        .min(1)
        .max(1e15)
        .as(fp::ParamRole::work),
    fp::param::integer("seed", "seed of the random streams (chain i uses stream (seed, i))").def("1").min(0),
    fp::param::integer("skip", "points not plotted at the start of each chain and after each restart")
        .def("20")
        .min(0)
        .max(1e9),
    fp::param::vec2("start",
                    "start point of every chain (default: a random point of the start box outside every set)")
        .opt(),
    fp::param::reals("start_box",
                     "where random start points are drawn [xmin, xmax, ymin, ymax] (default: the view)")
        .len(4)
        .opt(),
    fp::param::boolean("fit_view",
                       "fit the view to the orbits with a short pre-run (0.1%-99.9% quantiles, 5% margin, "
                       "square pixels); `view` is then ignored")
        .def("false"),
    fp::param::integer("chains", "independent chains (fixed whatever the thread count)")
        .def("4096")
        .min(1)
        .max(16777216),
    fp::param::objects("maps", fp::Kind::Transform,
                       "the maps of the chaos game, each with a weight and a colour")
        .min_len(1)
        .items(map_item_params),
    fp::param::object("iteration", fp::Kind::IterationScheme, "iteration process applied with the chosen map")
        .def("{type: picard}"),
    fp::param::object("colourer", fp::Kind::Colourer, "how points are coloured and the histogram tone-mapped")
        .def("{type: flame}"),
    fp::param::string("inversion_rules",
                      "paper 01's rules (not the previous map, not a map whose set holds the "
                      "point): auto = on when every map has a set")
        .def("auto")
        .one_of("auto|on|off"),
    fp::param::string("precision",
                      "arithmetic of the chains: float (twice the SIMD width) or double (deep zooms)")
        .def("float")
        .one_of("float|double"),
    fp::param::colour("background", "colour of pixels no point reached").def("[0, 0, 0]"),
    fp::param::string(
        "sets", "draw the sets of the maps with their centres (paper 01's left panels): over the fractal, "
                "beside it (an image twice as wide: the sets left, the fractal right), or only the sets "
                "(no chaos game; .svg and .pdf as well)")
        .def("none")
        .one_of("none|over|beside|only"),
    fp::param::reals("set_view",
                     "the region the sets are drawn in, beside the fractal or alone [xmin, xmax, ymin, ymax] "
                     "(default: the fractal's view)")
        .len(4)
        .opt(),
    fp::param::real("set_line", "width of the sets' outlines in pixels").def("2").above(0).max(100),
    fp::param::real("set_fill", "opacity of the sets' fill (0: outlines only)").def("0.3").min(0).max(1),
    fp::param::string("kernels",
                      "auto: run maps that describe themselves as known kernels (inversions in circles "
                      "about their centres, affine and Gumowski-Mira maps, with the Picard step or a scheme "
                      "written on fp::SchemeBase) in one fused vectorised pass; "
                      "generic: always through the plugins' batch calls. Same image either way")
        .def("auto")
        .one_of("auto|generic"),
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<ChaosGame>(fp::Kind::Renderer, "chaos-game",
                            "random inversion algorithm (paper 01) and general chaos games", params)
        .with_example("{maps: [{type: inversion, shape: {type: circle, centre: [1, 0], radius: 0.8}}, "
                      "{type: inversion, shape: {type: circle, centre: [-0.5, 0.866], radius: 0.8}}, "
                      "{type: inversion, shape: {type: circle, centre: [-0.5, -0.866], radius: 0.8}}], "
                      "width: 32, height: 32, points: 20000, chains: 64}")
        .with_abilities(fp::ability::weighted_maps))
