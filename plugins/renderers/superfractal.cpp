// superfractal: Barnsley's V-variable algorithm with buffers (paper 03, Sec. III; Barnsley,
// "Superfractals", 2006).
//
// What it computes
// ----------------
// K IFSs (each a list of maps: any transform plugin, affine or gumowski-mira alike) and B
// buffers, each holding a set of `points_per_buffer` points. The buffers start as random
// points of `start_box` (default: the view). One step makes B new buffers from the old ones:
// for each new buffer b',
//   1. choose an IFS i with probabilities `ifs_probabilities`;
//   2. for each map f_j of IFS i (m maps), choose a source buffer s_j with probabilities
//      `buffer_probabilities` (a buffer may be chosen for several maps);
//   3. b' is the union of f_j(share j of s_j), j = 1..m.
// This is the paper's L/R experiment (two IFSs F, G, two buffers, all probabilities 1/2) for
// any K, any number of maps per IFS, any B >= 1 and any probabilities. After `steps` steps
// each buffer holds one V-variable fractal, a "child" of the superfractal collection; the
// buffer `child` is rendered, as a histogram through the colourer like chaos-game. A buffer
// changes completely with every step, so only the last step's buffer is plotted: for a
// denser image raise points_per_buffer. With one IFS and one buffer this is the deterministic
// IFS algorithm on a fixed number of points, and the child is the IFS's attractor.
//
// Fixed-size buffers: the shares
// ------------------------------
// A buffer has N points. The new buffer b' is cut into m contiguous shares; share j has
// n_j = N / m points, one more for j < N % m, and takes the source points of index
// j, j + m, j + 2m, ... of its source buffer (the residue class j mod m, which has exactly
// n_j members). So the shares together take every source index exactly once: when all maps
// read the same buffer, the new buffer is the image of every old point under exactly one
// map, no point is duplicated or lost, and each share samples its source evenly (the source's
// own shares are contiguous). With one IFS of two maps and N = 2^k points, the point at index
// i has followed the maps given by the bits of i, rotated each step: the deterministic
// algorithm at depth k. Source points are taken deterministically; the RNG only chooses IFSs
// and buffers, and draws the start points.
//
//
// Bad values
// ----------
// A point that becomes NaN or infinite (a map that is not a contraction: GM orbits can run
// away) is counted (RenderStats::bad_values) and replaced by a copy of a finite point of the
// same new buffer, with its colour: the previous one by index, or the first finite one for
// the points before it. When no point of a new buffer is finite, the whole buffer is redrawn
// from start_box (counted as RenderStats::restarts, one per point) from its own stream.
// Never a crash, never an empty buffer.
//
// Colour
// ------
// Every point carries a colour; after each map the colourer's update() sees the map's index
// (in `maps`) and its `colour` (default: the built-in palette by index), so with map-colour a
// point shows the colour of the last map applied and with flame the running mean along its
// history. Points start with the mean colour of the maps. A child's point takes its parent
// point's colour into the update, so with flame colours pass from parents to children.
//
//
// Colour stealing (`picture`): picture.hpp.
//
// Buffers: point samples, not sets
// --------------------------------
// The paper's buffers hold sets ("in superfractal algorithm rather sets, not single points are
// transformed"): L' = f_1(L or R) union f_2(L or R), each image of the whole source set. Here a
// buffer is N points, and share j of the new buffer is f_j of the source points j, j + m, ...:
// every point of a new buffer is the image of exactly one point, and the N points are a sample
// of the set, not the set. What this changes: (a) the drawing is the set only when N is large
// enough to hit each of its pixels (a thin buffer shows a dotted curve, where a set cannot be
// thin); (b) density: each point has one address, so the histogram counts show the child's
// V-variable measure (each map weighing 1/m), which log shading shows, where a set has no
// density; (c) colour: one colour per point and the mean per pixel, where a set of pixels must
// choose one colour per pixel (the top). The set form, done literally on pixel bitmaps with the
// same choices (a study script, F and G at 128 x 128 and 256 x 256, 30 steps, 100 000 and
// 300 000 points), gives the same lit pixels within one pixel everywhere (no lit pixel of
// either form is more than one pixel from a lit pixel of the other; 4-11% of the pixels differ
// by that one pixel, as the bitmap rounds every image to pixel centres at every step); with 5 000
// points at 256 x 256 the samples miss 20% of the set's pixels. So with points_per_buffer well
// above the child's pixel count (the configs use 2-3 million for a megapixel) the set form
// shows no visible difference, and it is not offered.
//
// Determinism
// -----------
// A render is a pure function of its recipe, whatever the thread count:
//   - the choices (IFS per new buffer, source buffer per map) are drawn in a fixed order
//     (step by step, buffer by buffer, map by map) from the stream fp::chain_stream(seed, 0),
//     one fp::uniform_double per choice;
//   - start points: buffer b, chunk c draws from stream (seed, 1 + b * C + c), C the number of
//     chunks of a buffer; a redrawn buffer b at step s from stream (seed, 1 + B * C + s * B + b);
//   - a step is cut into B * C tasks (buffer, chunk of 16384 points), fixed by the recipe;
//     each task writes only its own range of the new generation, reads only the old one, and
//     calls the maps on its contiguous sub-ranges; the repair of bad values runs afterwards,
//     one task per buffer, in index order;
//   - points are double; float work is plain IEEE arithmetic built without FMA contraction;
//   - the child is deposited into one integer fp::Histogram in index order.
// Progress: one unit per point made (start points and every step), reported per task;
// ctx.cancelled() is polled at every task and step (fp::Cancelled).
//
// Binning (as chaos-game): a point plots when x in [xmin, xmax) and y in (ymin, ymax];
// column = floor((x - xmin) * (width / (xmax - xmin))), row = floor((ymax - y) * (height /
// (ymax - ymin))), clamped to the image. Colour sums add round(c * fp::colour_scale) per
// channel (c clamped to [0, 1], NaN to 0). RenderStats::samples counts the child's points,
// ::drawn those inside the view.
//
// Errors (ParamError, by parameter):
//   "view": "the view must be [xmin, xmax, ymin, ymax] with xmin < xmax" (or ymin < ymax);
//   "start_box": "the start box must be [xmin, xmax, ymin, ymax] with xmin <= xmax" (or ymin
//     <= ymax; a box of zero width or height is allowed);
//   "height": "the image is too large: width * height must be below 4294967295 pixels";
//   "maps": "IFS 1 has no maps: the maps' ifs indices must cover 0 to 2 (each IFS needs at
//     least one map)";
//   "ifs_probabilities": "expected 2 probabilities (one per IFS), got 3"; "the probabilities
//     sum to 0.9, not 1: give probabilities that sum to 1 (they are not normalised)";
//   "buffer_probabilities": the same with "(one per buffer)";
//   "child": "child 2 does not exist: there are 2 buffers, numbered from 0";
//   "picture": "cannot read the picture \"p.png\": no such file (give a PNG file, relative to
//     the config, or hues)" (or "it cannot be opened", "it is not a PNG file", "Cairo
//     cannot decode it (...)"); "colour stealing needs a colourer that shows the points'
//     colours (map-colour or flame); this one shows only where they fall";
//   "maps": "maps[1]: a colour_map is used only by colour stealing: give the renderer a
//     picture (hues, or a PNG file)".
// The schema refuses the rest before the plugin sees it, with the element's position: an
// empty list of maps ("the list of transforms is empty"), a negative probability
// ("ifs_probabilities[1]: must be >= 0, got -0.5"), zero buffers ("buffers: must be in
// [1, 65536], got 0"), a colour map of the wrong length ("maps[0].colour_map: expected 6
// numbers, got 5").
#include "palette.hpp"
#include "picture.hpp"
#include "superfractal/choices.hpp"
#include "superfractal/renderer.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace fp_superfractal {

Superfractal::Superfractal(const fp::ParamBag& p) {
    frame_ = fp::Frame::read(p);
    sxmin_ = frame_.region.xmin, sxmax_ = frame_.region.xmax, symin_ = frame_.region.ymin,
    symax_ = frame_.region.ymax;
    if (p.has("start_box")) {
        const auto& s = p.reals("start_box");
        sxmin_ = s[0], sxmax_ = s[1], symin_ = s[2], symax_ = s[3];
        if (!(sxmin_ <= sxmax_))
            throw fp::ParamError("start_box",
                                 "the start box must be [xmin, xmax, ymin, ymax] with xmin <= xmax");
        if (!(symin_ <= symax_))
            throw fp::ParamError("start_box",
                                 "the start box must be [xmin, xmax, ymin, ymax] with ymin <= ymax");
    }
    seed_ = uint64_t(p.integer("seed"));
    steps_ = uint64_t(p.integer("steps"));
    points_ = uint64_t(p.integer("points_per_buffer"));
    buffers_ = uint64_t(p.integer("buffers"));
    child_ = uint64_t(p.integer("child"));
    if (child_ >= buffers_)
        throw fp::ParamError(
            "child", "child " + std::to_string(child_) + " does not exist: there " +
                         (buffers_ == 1 ? "is 1 buffer" : "are " + std::to_string(buffers_) + " buffers") +
                         ", numbered from 0");
    colourer_ = p.object<fp::Colourer>("colourer");
    colour_ = colourer_->needs_colour();
    // A point has no step order across buffers: there is no "last" colour to keep.
    if (colourer_->pixel_rule() == fp::PixelRule::last)
        throw fp::ParamError("colourer",
                             "the superfractal renderer keeps the mean colour of a pixel's points: "
                             "this colourer's mode needs the last one (chaos-game keeps it)");
    finish_ = fp::FinishSpec::read(p);
    if (finish_.active() && !colourer_->finishes())
        throw fp::ParamError("colourer", "this colourer cannot finish a supersampled, filtered or estimated "
                                         "histogram (supersample, filter, estimator_radius)");
    if (uint64_t(frame_.width) * uint64_t(frame_.height) *
            uint64_t(finish_.supersample * finish_.supersample) >=
        0xffffffffull)
        throw fp::ParamError("supersample", "the supersampled histogram is too large: width * height * "
                                            "supersample^2 must be below 4294967295 bins");
    if (p.has("picture")) {
        steal_ = true;
        if (!colour_)
            throw fp::ParamError("picture", "colour stealing needs a colourer that shows the points' colours "
                                            "(map-colour or flame); this one shows only where they fall");
        const std::string& name = p.string("picture");
        picture_ = name == "hues" ? fp_render::hues_picture() : fp_render::png_picture(name);
    }
    rgb_ = colour_ && !steal_;
    palette_ = colourer_->palette_index();
    if (palette_ && steal_)
        throw fp::ParamError("picture",
                             "colour stealing takes the points' colours from the picture: not with "
                             "a colourer's palette (leave out the picture, or the palette)");

    const auto& items = p.objects("maps");
    if (items.empty()) throw fp::ParamError("maps", "the list of maps is empty");
    std::vector<uint32_t> ifs_of(items.size(), 0);
    std::vector<bool> has_colour_map;
    uint32_t k = 0;
    for (size_t j = 0; j < items.size(); ++j) {
        auto m = fp::as<fp::Transform>(items[j]);
        if (!m) throw fp::InternalError("superfractal: maps[" + std::to_string(j) + "] is not a transform");
        if (const std::string why = m->plane_map_problem(); !why.empty())
            throw fp::ParamError("maps", "maps[" + std::to_string(j) + "]: " + why);
        fp::Rgb c = fp_render::palette_colour(j);
        std::array<double, 6> cm{};
        bool has_cm = false;
        // flam3's palette index of the map: its `color`, else the maps spread over the palette.
        float index = items.size() > 1 ? float(double(j) / double(items.size() - 1)) : 0.0f, speed = 0.5f;
        if (items[j].extras) {
            ifs_of[j] = uint32_t(items[j].extras->integer("ifs"));
            fp_render::read_item_colour(*items[j].extras, "maps", j, palette_, c, index, speed);
            if (items[j].extras->has("colour_map")) {
                const auto& v = items[j].extras->reals("colour_map");
                std::copy(v.begin(), v.end(), cm.begin());
                has_cm = true;
                if (!steal_)
                    throw fp::ParamError("maps", "maps[" + std::to_string(j) +
                                                     "]: a colour_map is used only by colour stealing: give "
                                                     "the renderer a picture (hues, or a PNG file)");
            }
        }
        colour_maps_.push_back(cm);
        has_colour_map.push_back(has_cm);
        map_index_.push_back(index);
        map_speed_.push_back(speed);
        k = std::max(k, ifs_of[j] + 1);
        maps_.push_back(std::move(m));
        colours_.push_back(c);
    }
    ifs_.resize(k);
    for (size_t j = 0; j < items.size(); ++j) ifs_[ifs_of[j]].push_back(uint32_t(j));
    for (uint32_t i = 0; i < k; ++i) {
        if (ifs_[i].empty())
            throw fp::ParamError("maps", "IFS " + std::to_string(i) +
                                             " has no maps: the maps' ifs indices must cover 0 to " +
                                             std::to_string(k - 1) + " (each IFS needs at least one map)");
        max_maps_ = std::max(max_maps_, ifs_[i].size());
    }
    // The default colour map of map number t (from 0) of an IFS of m maps: (u, v) -> ((u + t) / m,
    // v), the address of the point in base m along u (the picture's row v = 1/2).
    for (uint32_t i = 0; i < k; ++i)
        for (size_t t = 0; t < ifs_[i].size(); ++t)
            if (!has_colour_map[ifs_[i][t]]) {
                const double m = double(ifs_[i].size());
                colour_maps_[ifs_[i][t]] = {1.0 / m, 0.0, 0.0, 1.0, double(t) / m, 0.0};
            }
    initial_colour_ = fp::Rgb{};
    for (const auto& c : colours_) {
        initial_colour_.r += c.r / float(colours_.size());
        initial_colour_.g += c.g / float(colours_.size());
        initial_colour_.b += c.b / float(colours_.size());
    }

    ifs_cum_ = cumulative_probabilities(p, "ifs_probabilities", k, "IFS");
    buffer_cum_ = cumulative_probabilities(p, "buffer_probabilities", size_t(buffers_), "buffer");
    ifs_fallback_ = last_positive(ifs_cum_);
    buffer_fallback_ = last_positive(buffer_cum_);
}

uint64_t Superfractal::memory_bytes(unsigned) const {
    const uint64_t N = uint64_t(finish_.supersample);
    const uint64_t px = uint64_t(frame_.width) * uint64_t(frame_.height) * N * N;
    const uint64_t per_point = 2 * sizeof(double) + (rgb_ ? 3 * sizeof(float) : 0) +
                               (steal_ ? 2 * sizeof(double) : 0) + (palette_ ? sizeof(float) : 0);
    const uint64_t buffers = 2 * buffers_ * points_ * per_point; // two generations
    // (Hit counts alone, 8 bytes a bin, for a colourer that reads no more: as the child is plotted.)
    const uint64_t hist = px * (colourer_->reads_hits_only() ? sizeof(uint64_t) : sizeof(fp::HistBin));
    const uint64_t image = uint64_t(frame_.width) * uint64_t(frame_.height) * 3 * sizeof(float) +
                           (finish_.active() ? finish_.bytes(frame_.width, frame_.height) : 0);
    // No per-worker state: a task's scratch is on the stack.
    return buffers + hist + image + picture_.rgb.size();
}

} // namespace fp_superfractal

namespace {

constexpr fp::ParamSpec map_item_params[] = {
    fp::param::integer("ifs", "the IFS the map belongs to (0, 1, ...; the IFSs are the distinct indices, "
                              "each needs at least one map)")
        .def("0")
        .min(0)
        .max(65535),
    fp::param::colour("colour",
                      "colour of the points the map produces (default: a built-in palette by index; "
                      "not used with a picture)")
        .opt(),
    fp_render::map_color_param,
    fp_render::map_color_speed_param,
    fp::param::reals("colour_map",
                     "colour stealing: the map of the colour IFS on the picture square "
                     "run with this map, affine coefficients [a, b, c, d, e, f] (u' = a u + b v "
                     "+ e, v' = c u + d v + f); default ((u + t) / m, v) for map t of m in its IFS")
        .len(6)
        .opt(),
};

constexpr fp::ParamSpec params[] = {
    fp::param::integer("width", "image width in pixels").def("512").min(1).max(65536),
    fp::param::integer("height", "image height in pixels").def("512").min(1).max(65536),
    fp::param::reals("view", "the plotted region [xmin, xmax, ymin, ymax]").def("[0, 1, 0, 1]").len(4),
    fp::param::integer("seed", "seed of the random choices of IFSs and buffers and of the start points")
        .def("1")
        .min(0),
    fp::param::integer("steps", "steps of the buffer algorithm (each makes every buffer anew)")
        .def("30")
        .min(0)
        .max(1000000),
    fp::param::integer("points_per_buffer",
                       "points in each buffer (the child is drawn with this many points)")
        .def("100000")
        .min(1)
        .max(1e10)
        .as(fp::ParamRole::work),
    fp::param::integer("buffers", "number of buffers (V of V-variable; the paper's L and R are 2)")
        .def("2")
        .min(1)
        .max(65536),
    fp::param::objects("maps", fp::Kind::Transform,
                       "the maps of all IFSs, each with the index of its IFS (`ifs`) and a colour")
        .min_len(1)
        .items(map_item_params),
    fp::param::reals("ifs_probabilities", "probability of choosing each IFS, one per IFS, summing to 1 "
                                          "(refused otherwise, not normalised; default: equal)")
        .min(0)
        .opt(),
    fp::param::reals("buffer_probabilities",
                     "probability of choosing each buffer as a source, one per buffer, "
                     "summing to 1 (refused otherwise, not normalised; default: equal)")
        .min(0)
        .opt(),
    fp::param::integer("child", "the buffer rendered (0 to buffers - 1)").def("0").min(0),
    fp::param::reals("start_box", "[xmin, xmax, ymin, ymax]: the start points are random points of this box "
                                  "(default: the view)")
        .len(4)
        .opt(),
    fp::param::object("colourer", fp::Kind::Colourer, "how points are coloured and the histogram tone-mapped")
        .def("{type: map-colour}"),
    fp::param::colour("background", "colour of pixels no point reached").def("[0, 0, 0]"),
    fp::supersample_param,
    fp::filter_param,
    fp::estimator_radius_param,
    fp::estimator_minimum_param,
    fp::estimator_curve_param,
    fp::estimator_quality_param,
    fp::param::string("picture", "colour stealing (Barnsley): each point takes the colour of this picture at "
                                 "the point of the colour IFS (the maps' colour_map) run with the same "
                                 "choices; hues (built in) or a PNG file relative to the config")
        .opt()
        .reads_file("hues"),
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<fp_superfractal::Superfractal>(
        fp::Kind::Renderer, "superfractal",
        "Barnsley's V-variable superfractal algorithm with buffers (paper 03, Sec. III)", params)
        .with_example("{maps: [{type: affine, coefficients: [0.5, 0.375, 0.5, -0.375, -0.0625, 0.5625]}, "
                      "{type: affine, coefficients: [0.5, -0.375, -0.5, -0.375, 0.5625, 1.0625]}, "
                      "{type: affine, coefficients: [0.5, 0.375, -0.5, 0.375, -0.0625, 0.4375], ifs: 1}, "
                      "{type: affine, coefficients: [0.5, -0.375, 0.5, 0.375, 0.5625, -0.0625], ifs: 1}], "
                      "width: 64, height: 64, points_per_buffer: 4000, steps: 20}"))
