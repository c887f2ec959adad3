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
// none is left. (chaos-game/renderer.hpp lists the files: a block's chains and steady runs in
// chaos-game/chains.hpp, the histograms in histogram.hpp, a block's steps in block.cpp, the
// vectorised stages and the fused step in the -inl headers listed by kernels-inl.hpp, compiled
// per SIMD target.)
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
// grouping (chaos-game/fused-inl.hpp's fused_t), with the maps' formulas of the SDK
// (fixpoint/kernels-inl.hpp), the transform plugins' own. A scheme's program is asked for at each
// block step (its coefficients change with n) and must be the same for every map; a step
// where it is not (Schu composing T more often than a program holds) takes the generic path,
// the fused step's pending work settled first. It computes the same draws and the same operations
// in the same order, so the image is the same bytes; `kernels: generic` turns it off
// (tests/unit/test_chaos_kernel.cpp renders recipes both ways). While every chain of a block is
// past its skip and far from its last point, the block runs steady (chaos-game/chains.hpp):
// the pass leaves age, idle, points left and activity alone, and they are settled at the run's
// end, with colour or without.
// So a step costs 2k + 1 virtual calls per block (k maps), none per point; nothing is
// allocated, looked up, thrown or logged per point. Block buffers are allocated once per
// worker and stay in L1/L2 (about 100 bytes per chain, k more for the tests, 8 k for the
// staging segments).
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
// Errors (ParamError, by parameter): "view": "the view must be [xmin, xmax, ymin, ymax] with
// xmin < xmax" (or "... with ymin < ymax"); "maps": "the list of maps is empty"; "height":
// "the image is too large: width * height must be below 4294967295 pixels".
#include "chaos-game/chains.hpp"
#include "chaos-game/kernels.hpp"
#include "chaos-game/renderer.hpp"
#include "fit_view.hpp"
#include "palette.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace fp_chaos {

ChaosGame::ChaosGame(const fp::ParamBag& p) {
    frame_ = fp::Frame::read(p);
    points_ = uint64_t(p.integer("points"));
    seed_ = uint64_t(p.integer("seed"));
    skip_ = uint64_t(p.integer("skip"));
    escape_ = p.has("escape") ? p.real("escape") : 0.0;
    if (p.has("restart_skip")) {
        const uint64_t rs = uint64_t(p.integer("restart_skip"));
        if (rs > skip_) throw fp::ParamError("restart_skip", "at most skip (" + std::to_string(skip_) + ")");
        restart_age_ = uint32_t(std::min<uint64_t>(skip_ - rs, 0xffffffffu));
    }
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
    palette_ = colourer_->palette_index();
    if (p.has("picture")) {
        steal_ = true;
        if (!colour_)
            throw fp::ParamError("picture", "colour stealing needs a colourer that shows the points' colours "
                                            "(map-colour or flame); this one shows only where they fall");
        if (palette_)
            throw fp::ParamError("picture",
                                 "colour stealing takes the points' colours from the picture: not with "
                                 "a colourer's palette (leave out the picture, or the palette)");
        const std::string& name = p.string("picture");
        picture_ = name == "hues" ? fp_render::hues_picture() : fp_render::png_picture(name);
    }

    const auto& items = p.objects("maps");
    if (items.empty()) throw fp::ParamError("maps", "the list of maps is empty");
    const size_t k = items.size();
    std::vector<double> w(k, 1.0);
    visible_.assign(k + 1, 1.0);
    // flam3's xaos: chaos[i k + j] the factor on map j's weight after map i (1 where not given).
    std::vector<double> chaos(k * k, 1.0);
    for (size_t j = 0; j < k; ++j) {
        auto m = fp::as<fp::Transform>(items[j]);
        if (!m) throw fp::InternalError("chaos-game: maps[" + std::to_string(j) + "] is not a transform");
        if (const std::string why = m->plane_map_problem(); !why.empty())
            throw fp::ParamError("maps", "maps[" + std::to_string(j) + "]: " + why);
        fp::Rgb c = fp_render::palette_colour(j);
        // flam3's palette index of the map: its `color`, else the maps spread over the palette.
        float index = k > 1 ? float(double(j) / double(k - 1)) : 0.0f, speed = 0.5f;
        // Colour stealing's default colour map: ((u + j) / k, v), the chain's address in base k
        // along u (picture.hpp).
        colour_maps_.push_back({1.0 / double(k), 0.0, 0.0, 1.0, double(j) / double(k), 0.0});
        if (items[j].extras) {
            w[j] = items[j].extras->real("weight");
            fp_render::read_item_colour(*items[j].extras, "maps", j, palette_, c, index, speed);
            // flam3's visibility: opacity^(log2 10) (flam3.c's adjust_percentage), the weight of
            // each of its points, drawn as the chance of plotting one (the sums stay integers).
            if (items[j].extras->has("chaos")) {
                const auto& c = items[j].extras->reals("chaos");
                if (c.size() > k)
                    throw fp::ParamError("maps", "maps[" + std::to_string(j) +
                                                     "].chaos: " + std::to_string(c.size()) +
                                                     " entries for " + std::to_string(k) + " maps");
                for (size_t i = 0; i < c.size(); ++i) {
                    if (!(c[i] >= 0) || !std::isfinite(c[i]))
                        throw fp::ParamError("maps", "maps[" + std::to_string(j) + "].chaos[" +
                                                         std::to_string(i) + "] must be a number >= 0");
                    chaos[j * k + i] = c[i];
                    has_xaos_ = has_xaos_ || c[i] != 1;
                }
            }
            if (items[j].extras->has("colour_map")) {
                if (!steal_)
                    throw fp::ParamError("maps", "maps[" + std::to_string(j) +
                                                     "]: a colour_map is used only by colour stealing: give "
                                                     "the renderer a picture (hues, or a PNG file)");
                const auto& v = items[j].extras->reals("colour_map");
                colour_maps_.back() = {v[0], v[1], v[2], v[3], v[4], v[5]};
            }
            const double o = items[j].extras->real("opacity");
            if (o < 1) {
                has_opacity_ = true;
                visible_[j] = o > 0 ? std::pow(o, std::log2(10.0)) : 0.0;
            }
        }
        map_index_.push_back(index);
        map_speed_.push_back(speed);
        if (!(w[j] > 0) || !std::isfinite(w[j]))
            throw fp::ParamError("maps", "maps[" + std::to_string(j) + "].weight must be a positive number");
        random_maps_ = random_maps_ || m->uses_random();
        const bool region = m->has_region();
        if (region) region_maps_.push_back(uint32_t(j));
        maps_.push_back(std::move(m));
        colours_.push_back(c);
    }
    // The final maps (flam3's finalxform): the plotted points only, each with its colour as a
    // map's (its `color` and `color_speed` under a palette).
    static const std::vector<fp::ObjectItem> none;
    const auto& fin = p.has("final") ? p.objects("final") : none;
    for (size_t j = 0; j < fin.size(); ++j) {
        auto m = fp::as<fp::Transform>(fin[j]);
        if (!m) throw fp::InternalError("chaos-game: final[" + std::to_string(j) + "] is not a transform");
        if (const std::string why = m->plane_map_problem(); !why.empty())
            throw fp::ParamError("final", "final[" + std::to_string(j) + "]: " + why);
        fp::Rgb c = fp_render::palette_colour(k + j);
        float index = 0.0f, speed = 0.5f;
        double opacity = 1;
        if (fin[j].extras) {
            fp_render::read_item_colour(*fin[j].extras, "final", j, palette_, c, index, speed);
            opacity = fin[j].extras->real("opacity");
        }
        random_final_ = random_final_ || m->uses_random();
        final_.push_back(std::move(m));
        final_colours_.push_back(c);
        final_index_.push_back(index);
        final_speed_.push_back(speed);
        final_opacity_.push_back(opacity);
    }
    const double rot = p.real("rotate");
    rotate_ = rot != 0;
    cam_[0] = std::cos(rot * (3.14159265358979323846 / 180.0));
    cam_[1] = std::sin(rot * (3.14159265358979323846 / 180.0));
    y_down_ = p.string("y_axis") == "down";
    has_finals_ = !final_.empty() || rotate_ || y_down_;
    colours_.push_back(fp::Rgb{});
    map_index_.push_back(0.0f), map_speed_.push_back(0.0f); // (the k-th: never used)
    colour_maps_.push_back({1, 0, 0, 1, 0, 0});
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
        // The panel of the sets, beside the fractal or alone, shows them whole by default: the
        // fractal's view, which the sets' inversions fill, cuts off the outer ones in most of
        // paper 01's figures.
        if (!set_view_ && (sets_ == Sets::beside || sets_ == Sets::only)) {
            fp::Box b{HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL};
            auto take = [&](fp::Vec2 q) {
                b.xmin = std::min(b.xmin, q.x), b.xmax = std::max(b.xmax, q.x);
                b.ymin = std::min(b.ymin, q.y), b.ymax = std::max(b.ymax, q.y);
            };
            for (const auto& d : set_drawings_) {
                for (const auto& q : d.outline) take(q);
                if (d.centre) take(*d.centre);
            }
            set_view_ = fp_render::framed(b, frame_.width, frame_.height);
        }
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

    // The finishing stage (fixpoint/finish.hpp): the histogram is N times the image in each
    // direction (hist_), finished down to it.
    finish_ = fp::FinishSpec::read(p);
    hist_ = frame_;
    if (finish_.active()) {
        if (!colourer_->finishes())
            throw fp::ParamError("colourer",
                                 "this colourer cannot finish a supersampled, filtered or estimated "
                                 "histogram (supersample, filter, estimator_radius)");
        if (sets_ == Sets::only)
            throw fp::ParamError("supersample", "sets: only draws no histogram to finish");
        const int N = finish_.supersample;
        if (uint64_t(frame_.width) * uint64_t(N) * uint64_t(frame_.height) * uint64_t(N) >= 0xffffffffull)
            throw fp::ParamError("supersample", "the supersampled histogram is too large: width * height * "
                                                "supersample^2 must be below 4294967295 bins");
        hist_.width *= N;
        hist_.height *= N;
    }

    // Integer weights for the draw among the allowed maps: sum below 2^32, each at least 1.
    double sum = 0;
    for (double x : w) sum += x;
    q_.resize(k);
    for (size_t j = 0; j < k; ++j)
        q_[j] = uint32_t(std::max(1.0, std::floor(w[j] / sum * double(1u << 31) + 0.5)));
    uniform_ = std::all_of(w.begin(), w.end(), [&](double x) { return x == w[0]; });

    fp_chaos::walker_table(w, alias_thr_, alias_);
    if (has_xaos_) xaos_tables(w, chaos);

    // The fused step: every map a known kernel of one kind (Transform::kernel: inversions in
    // circles about their centres, affine maps, Gumowski-Mira maps), a Picard step, at most
    // table_size maps, and a colourer that needs no colour or whose update is a ColourRule;
    // `kernels: generic` turns it off (it gives the same bytes: tests/unit/test_chaos_kernel.cpp).
    const fp::ColourRule crule = colourer_->colour_rule();
    // Last colours (the pixel rule last) with the map rule: paper 01's colouring by set
    // (flame's set-colour, every configs/inversion figure). A point's colour is its map's
    // whatever the chain's history, so the renderer writes the last colours from the maps the
    // fused step took (chaos-game/block.cpp). The running colour of Algorithm 2 (flame's `last`) changes
    // only where a chain plots, unlike the fused step's: that mode keeps the generic path.
    if (p.string("kernels") == "auto" && k <= fp_chaos::table_size && !has_finals_ && !has_opacity_ &&
        !has_xaos_ && escape_ == 0 && !steal_ && (!colour_ || crule != fp::ColourRule::none) &&
        (!last_ || crule == fp::ColourRule::map)) {
        std::vector<fp::KnownKernel> kk;
        for (const auto& m : maps_) kk.push_back(m->kernel());
        setup_fused(kk, crule);
    }

    // fit_view refined by the render's own chains, now that they can run (chaos-game/fit.cpp).
    if (p.boolean("fit_view") && probe_fits()) fit_by_probe();
}

// The fused step's tables (chaos-game/fused-inl.hpp): when every map is a known kernel of one
// kind and the scheme is Picard or gives a program at the first step.
void ChaosGame::setup_fused(const std::vector<fp::KnownKernel>& kk, fp::ColourRule crule) {
    const size_t k = maps_.size();
    const auto in_unit = [](float v) { return v >= 0.0f && v <= 1.0f; }; // (not NaN)
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
            t.colours_in_range = std::all_of(colours_.begin(), colours_.end(), [&](const fp::Rgb& c) {
                return in_unit(c.r) && in_unit(c.g) && in_unit(c.b);
            });
            t.repeat_wide();
        };
        fill(*lanes_f_);
        fill(*lanes_d_);
        // (The fused step indexes the counters by map * plane + bin in 32 bits.)
        if (colour_ && crule == fp::ColourRule::map && k <= fp_chaos::tally_maps &&
            (uint64_t(hist_.width) * uint64_t(hist_.height) + 1) * k <= 0xffffffffull) {
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
}

} // namespace fp_chaos

namespace {

constexpr fp::ParamSpec map_item_params[] = {
    fp::param::real("weight", "relative probability of choosing the map").def("1").above(0),
    fp::param::colour("colour",
                      "colour of the points the map produces (default: a built-in palette by index)")
        .opt(),
    fp_render::map_color_param,
    fp_render::map_color_speed_param,
    fp::param::reals("chaos",
                     "flam3's xaos: after this map, map j's weight is multiplied by chaos[j] (1 where "
                     "the list ends); with inversion_rules, it replaces the rule 'not the previous map' "
                     "(a 0 at the map's own place is that rule)")
        .opt(),
    fp::param::real("opacity",
                    "flam3's opacity: each point of the map is plotted with the chance opacity^log2(10) "
                    "(flam3's weight of it); the chain goes on either way")
        .def("1")
        .min(0)
        .max(1),
    fp::param::reals("colour_map",
                     "colour stealing: the map of the colour IFS on the picture square run with this map, "
                     "affine coefficients [a, b, c, d, e, f] (u' = a u + b v + e, v' = c u + d v + f); "
                     "default ((u + j) / k, v) for map j of k")
        .len(6)
        .opt(),
};

constexpr fp::ParamSpec final_item_params[] = {
    fp::param::colour("colour", "colour the final map blends the plotted point's toward (as a map's)").opt(),
    fp::param::real("color", "flam3's color of the final xform: its index into the colourer's palette")
        .min(0)
        .max(1)
        .opt(),
    fp::param::real("color_speed", "flam3's color_speed of the final xform (the plotted colour only)")
        .def("0.5")
        .min(0)
        .max(1),
    fp::param::real("opacity", "flam3's opacity of the final xform: the chance that a plotted point goes "
                               "through it (else it is plotted as the maps left it)")
        .def("1")
        .min(0)
        .max(1),
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
    fp::param::real("escape",
                    "a point with |x| or |y| above this is bad, as one that is not finite: its chain "
                    "restarts (flam3's is 1e10); default: none")
        .above(0)
        .opt(),
    fp::param::integer("restart_skip",
                       "points not plotted after a restart (a point that is not finite): default skip; 0 is "
                       "flam3's (a bad point is replaced and the chain goes on)")
        .min(0)
        .max(1e9)
        .opt(),
    fp::param::vec2("start",
                    "start point of every chain (default: a random point of the start box outside every set)")
        .opt(),
    fp::param::reals("start_box",
                     "where random start points are drawn [xmin, xmax, ymin, ymax] (default: the view)")
        .len(4)
        .opt(),
    fp::param::boolean("fit_view",
                       "fit the view to the orbits: the first points of the render's own chains (at most "
                       "2^22), their 0.1%-99.9% quantiles, 5% margin, square pixels; `view` is then ignored")
        .def("false"),
    fp::param::integer("chains", "independent chains (fixed whatever the thread count)")
        .def("4096")
        .min(1)
        .max(16777216),
    fp::param::objects("maps", fp::Kind::Transform,
                       "the maps of the chaos game, each with a weight and a colour")
        .min_len(1)
        .items(map_item_params),
    fp::param::objects("final", fp::Kind::Transform,
                       "maps applied, in order, to the plotted points only (flam3's finalxform): the "
                       "chains go on from their own points; each with a colour as the maps")
        .opt()
        .items(final_item_params),
    fp::param::real("rotate",
                    "flam3's rotate: the plotted points turned about the view's centre by this many "
                    "degrees (after the final maps)")
        .def("0"),
    fp::param::string("y_axis", "up: the view's ymax is the top row; down: its ymin (flam3's camera)")
        .def("up")
        .one_of("up|down"),
    fp::param::object("iteration", fp::Kind::IterationScheme, "iteration process applied with the chosen map")
        .def("{type: picard}"),
    fp::param::object("colourer", fp::Kind::Colourer, "how points are coloured and the histogram tone-mapped")
        .def("{type: flame}"),
    fp::param::string("picture", "colour stealing (Barnsley): each point takes the colour of this picture at "
                                 "the chain's point of the colour IFS (the maps' colour_map), run with the "
                                 "chain's own choices; hues (built in) or a PNG file relative to the config")
        .opt()
        .reads_file("hues"),
    fp::param::string("inversion_rules",
                      "paper 01's rules (not the previous map, not a map whose set holds the "
                      "point): auto = on when every map has a set")
        .def("auto")
        .one_of("auto|on|off"),
    fp::param::string("precision",
                      "arithmetic of the chains: float (twice the SIMD width) or double (deep zooms)")
        .def("float")
        .one_of("float|double"),
    fp::param::colour("background", "colour of pixels no point reached")
        .def("[0, 0, 0]")
        .as(fp::ParamRole::finish),
    fp::supersample_param,
    fp::filter_param,
    fp::estimator_radius_param,
    fp::estimator_minimum_param,
    fp::estimator_curve_param,
    fp::estimator_quality_param,
    fp::param::string(
        "sets", "draw the sets of the maps with their centres (paper 01's left panels): over the fractal, "
                "beside it (an image twice as wide: the sets left, the fractal right), or only the sets "
                "(no chaos game; .svg and .pdf as well)")
        .def("none")
        .one_of("none|over|beside|only"),
    fp::param::reals("set_view",
                     "the region the sets are drawn in, beside the fractal or alone [xmin, xmax, ymin, ymax] "
                     "(default: the sets and their centres whole, with a margin of 5%)")
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
    fp::describe<fp_chaos::ChaosGame>(fp::Kind::Renderer, "chaos-game",
                                      "random inversion algorithm (paper 01) and general chaos games", params)
        .with_example("{maps: [{type: inversion, shape: {type: circle, centre: [1, 0], radius: 0.8}}, "
                      "{type: inversion, shape: {type: circle, centre: [-0.5, 0.866], radius: 0.8}}, "
                      "{type: inversion, shape: {type: circle, centre: [-0.5, -0.866], radius: 0.8}}], "
                      "width: 32, height: 32, points: 20000, chains: 64}")
        .with_abilities(fp::ability::weighted_maps))
