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
// Probabilities
// -------------
// Each list must have one entry per IFS (ifs_probabilities) or per buffer
// (buffer_probabilities); absent, the probabilities are equal. Entries must be >= 0 (the
// schema's range) and sum to 1 within 1e-6; otherwise the recipe is refused, not normalised:
// the paper requires p_1 + p_2 = 1, and a plugin cannot warn, so a silent normalisation would
// hide a missing or mistyped entry. Sums within the tolerance are divided by their sum. An
// entry of 0 is allowed: that IFS or buffer is never chosen.
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
// Colour stealing (Barnsley, "Superfractals", 2006; "Ergodic theory, fractal tops and colour
// stealing", 2003; paper 03, Sec. V, proposes it for GM superfractals but gives no details)
// ------------------------------------------------------------------------------------------
// With `picture`, a second IFS, the colour IFS, runs in lockstep with the fractal: each map
// f_j has a colour map g_j on the picture square [0, 1]^2 (its `colour_map`, affine
// [a, b, c, d, e, f]: u' = a u + b v + e, v' = c u + d v + f), and each buffer point carries
// a colour point (u, v) beside (x, y). When a share of a new buffer is f_j of source points,
// its colour points are g_j of the same source points' colour points: the same IFS, map and
// source buffer choices, the same source point. A child's point thus inherits its colour
// point from the parent point it came from, and after the steps (u, v) is the colour IFS's
// point with the fractal point's address. The child is deposited with the colour of the
// picture at (u, v) (nearest pixel; the square clamped to the picture), and the colourer only
// resolves the histogram: each pixel shows the mean colour of its points, shaded as the
// colourer says; its update() is not called. Colour points start at (1/2, 1/2) (a contraction
// forgets it; a colour map that keeps v, as the default, reads the picture's middle row).
// The default colour map of map t (from 0) of an IFS of m maps is ((u + t) / m, v): u is the
// point's address as a base-m fraction, Barnsley's "fractal homeomorphism" onto an interval;
// for curves made of just-touching pieces (F and G of paper 03, eq. (2)) the colour then runs
// continuously along every child. `picture` is `hues` (built in, 512 x 512: the hue wheel along
// u, deep to light along v) or a PNG file, relative to the working folder and read with Cairo
// (the image's recipe names the file, not its pixels). The colour IFS draws nothing from the
// random streams: a render with a picture has the geometry of the render without, pixel for
// pixel, and colour points are copied with their points when bad values are repaired.
// Barnsley's colour-stealing pictures colour each pixel by the point of the highest address
// through it (the "fractal top"); the histogram gives the mean of the colours of the points
// that fall in the pixel instead, which differs only where pieces overlap.
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
//     the working folder, or hues)" (or "it cannot be opened", "it is not a PNG file", "Cairo
//     cannot decode it (...)"); "colour stealing needs a colourer that shows the points'
//     colours (map-colour or flame); this one shows only where they fall";
//   "maps": "maps[1]: a colour_map is used only by colour stealing: give the renderer a
//     picture (hues, or a PNG file)".
// The schema refuses the rest before the plugin sees it, with the element's position: an
// empty list of maps ("the list of transforms is empty"), a negative probability
// ("ifs_probabilities[1]: must be >= 0, got -0.5"), zero buffers ("buffers: must be in
// [1, 65536], got 0"), a colour map of the wrong length ("maps[0].colour_map: expected 6
// numbers, got 5").
#include "cairo_out.hpp"
#include "palette.hpp"
#include "uninitialised.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace {

using std::size_t;
using std::uint32_t;
using std::uint64_t;

/// Points per task: a few hundred microseconds of work for cheap maps, few tasks per buffer.
constexpr size_t chunk_points = 16384;
/// Points per map call inside a task: gathered, mapped, coloured and checked while in L1.
constexpr size_t batch_points = 512;
/// Tolerance on the sum of the probabilities.
constexpr double sum_tolerance = 1e-6;

/// Shortest decimal that reads back as v (for messages).
std::string real_text(double v) {
    char buf[32];
    for (int prec = 1; prec <= 17; ++prec) {
        std::snprintf(buf, sizeof buf, "%.*g", prec, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

/// The probabilities `name` (one per item, `what` naming the items), checked and divided by
/// their sum; equal when absent. Returned as cumulative sums.
std::vector<double> cumulative_probabilities(const fp::ParamBag& p, const char* name, size_t n,
                                             const char* what) {
    std::vector<double> v(n, 1.0 / double(n));
    if (p.has(name)) {
        v = p.reals(name);
        if (v.size() != n)
            throw fp::ParamError(name, "expected " + std::to_string(n) +
                                           (n == 1 ? " probability" : " probabilities") + " (one per " +
                                           what + "), got " + std::to_string(v.size()));
        double sum = 0;
        for (double x : v) sum += x;
        if (!(std::fabs(sum - 1.0) <= sum_tolerance))
            throw fp::ParamError(name,
                                 "the probabilities sum to " + real_text(sum) +
                                     ", not 1: give probabilities that sum to 1 (they are not normalised)");
        for (double& x : v) x /= sum;
    }
    std::vector<double> cum(n);
    double acc = 0;
    for (size_t k = 0; k < n; ++k) cum[k] = acc += v[k];
    return cum;
}

/// Index k drawn with probability cum[k] - cum[k - 1]: the first k with u < cum[k] (a binary
/// search: thousands of buffers are fine). An entry of probability 0 is never drawn;
/// `fallback` (the last entry of positive probability) takes the case u >= cum.back() that
/// rounding could leave.
uint32_t draw(fp::Rng& rng, const std::vector<double>& cum, uint32_t fallback) {
    const double u = fp::uniform_double(rng);
    const auto it = std::upper_bound(cum.begin(), cum.end(), u);
    return it == cum.end() ? fallback : uint32_t(it - cum.begin());
}

uint32_t last_positive(const std::vector<double>& cum) {
    for (size_t k = cum.size(); k-- > 0;)
        if (cum[k] > (k ? cum[k - 1] : 0.0)) return uint32_t(k);
    return uint32_t(cum.size() - 1);
}

/// One generation of buffers: B * N points, buffer b at [b * N, (b + 1) * N).
struct Generation {
    // Not zeroed: the start tasks or a step write every element before it is read.
    fp_render::Buffer<double> x, y;
    fp_render::Buffer<float> r, g, b; ///< empty when the colourer needs no colour or colours are stolen
    fp_render::Buffer<double> u, v;   ///< the colour IFS's points; empty without colour stealing
};

/// The picture colours are stolen from: 8-bit RGB, top row first. The point (u, v) of the
/// picture square [0, 1]^2 (v up) reads the pixel of column min(floor(u w), w - 1), row
/// min(floor((1 - v) h), h - 1), u and v clamped to [0, 1] first (NaN to 0).
struct Picture {
    int w = 0, h = 0;
    std::vector<unsigned char> rgb;

    fp::Rgb at(double u, double v) const {
        const double uc = u > 0.0 ? (u < 1.0 ? u : 1.0) : 0.0, vc = v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0;
        const int col = std::min(int(uc * double(w)), w - 1),
                  row = std::min(int((1.0 - vc) * double(h)), h - 1);
        const unsigned char* p = rgb.data() + 3 * (size_t(row) * size_t(w) + size_t(col));
        return fp::Rgb{float(p[0]) / 255.0f, float(p[1]) / 255.0f, float(p[2]) / 255.0f};
    }
};

/// The built-in picture `hues`, 512 x 512: the hue wheel along u (red at u = 0 and 1, then
/// yellow, green, cyan, blue, magenta), from deep (v = 0: value 0.45, saturation 1) to light
/// (v = 1: value 1, saturation 0.55).
Picture hues_picture() {
    Picture pic;
    pic.w = pic.h = 512;
    pic.rgb.resize(size_t(pic.w) * size_t(pic.h) * 3);
    for (int row = 0; row < pic.h; ++row) {
        const double v = 1.0 - (double(row) + 0.5) / double(pic.h);
        const double val = 0.45 + 0.55 * v, sat = 1.0 - 0.45 * v;
        for (int col = 0; col < pic.w; ++col) {
            const double h6 = 6.0 * (double(col) + 0.5) / double(pic.w);
            const int sector = std::min(int(h6), 5);
            const double f = h6 - double(sector);
            const double p = val * (1 - sat), q = val * (1 - sat * f), t = val * (1 - sat * (1 - f));
            double c[3];
            switch (sector) {
            case 0: c[0] = val, c[1] = t, c[2] = p; break;
            case 1: c[0] = q, c[1] = val, c[2] = p; break;
            case 2: c[0] = p, c[1] = val, c[2] = t; break;
            case 3: c[0] = p, c[1] = q, c[2] = val; break;
            case 4: c[0] = t, c[1] = p, c[2] = val; break;
            default: c[0] = val, c[1] = p, c[2] = q; break;
            }
            unsigned char* out = pic.rgb.data() + 3 * (size_t(row) * size_t(pic.w) + size_t(col));
            for (int k = 0; k < 3; ++k) out[k] = (unsigned char)(std::lround(c[k] * 255.0));
        }
    }
    return pic;
}

/// A PNG file read with Cairo, composited over black (its alpha, if any, is dropped so).
Picture png_picture(const std::string& file) {
    using fp_render::CairoContext;
    using fp_render::CairoSurface;
    auto refuse = [&](const std::string& why) {
        throw fp::ParamError("picture", "cannot read the picture \"" + fp::excerpt(file, 200) + "\": " + why +
                                            " (give a PNG file, relative to the working folder, or hues)");
    };
    {
        // Cairo tells a missing file apart, but reports any file that is not a PNG as "out of
        // memory": look at the signature first.
        // A FIFO or a device would block the open (or the read) for ever: a picture is a file.
        std::error_code ec;
        const auto st = std::filesystem::status(file, ec);
        if (!std::filesystem::exists(st)) refuse("no such file");
        if (!std::filesystem::is_regular_file(st)) refuse("it is not a regular file");
        std::ifstream in(file, std::ios::binary);
        if (!in) refuse("it cannot be opened");
        char sig[8] = {};
        in.read(sig, 8);
        if (in.gcount() != 8 || std::memcmp(sig, "\x89PNG\r\n\x1a\n", 8) != 0) refuse("it is not a PNG file");
    }
    const CairoSurface png(cairo_image_surface_create_from_png(file.c_str()));
    if (const cairo_status_t st = cairo_surface_status(png.get()); st != CAIRO_STATUS_SUCCESS)
        refuse(std::string("Cairo cannot decode it (") + cairo_status_to_string(st) + ")");
    Picture pic;
    pic.w = cairo_image_surface_get_width(png.get());
    pic.h = cairo_image_surface_get_height(png.get());
    const CairoSurface rgb(cairo_image_surface_create(CAIRO_FORMAT_RGB24, pic.w, pic.h));
    {
        const CairoContext cr(cairo_create(rgb.get()));
        cairo_set_source_rgb(cr.get(), 0, 0, 0);
        cairo_paint(cr.get());
        cairo_set_source_surface(cr.get(), png.get(), 0, 0);
        cairo_paint(cr.get());
    }
    cairo_surface_flush(rgb.get());
    const unsigned char* data = cairo_image_surface_get_data(rgb.get());
    const int stride = cairo_image_surface_get_stride(rgb.get());
    pic.rgb.resize(size_t(pic.w) * size_t(pic.h) * 3);
    for (int r = 0; r < pic.h; ++r) {
        const auto* row = reinterpret_cast<const std::uint32_t*>(data + size_t(r) * size_t(stride));
        for (int c = 0; c < pic.w; ++c) {
            unsigned char* out = pic.rgb.data() + 3 * (size_t(r) * size_t(pic.w) + size_t(c));
            out[0] = (unsigned char)((row[c] >> 16) & 0xff);
            out[1] = (unsigned char)((row[c] >> 8) & 0xff);
            out[2] = (unsigned char)(row[c] & 0xff);
        }
    }
    return pic;
}

class Superfractal final : public fp::Renderer {
public:
    explicit Superfractal(const fp::ParamBag& p);

    int width() const override { return frame_.width; }
    int height() const override { return frame_.height; }
    std::optional<fp::Box> region() const override {
        return frame_.has_region ? std::optional(frame_.region) : std::nullopt;
    }
    uint64_t memory_bytes(unsigned workers) const override;
    uint64_t work_units() const override { return (steps_ + 1) * buffers_ * points_; }
    fp::Image render(fp::RenderContext& ctx, fp::RenderStats& stats) const override;

private:
    void fill_start(Generation& g, size_t b, size_t begin, size_t end, uint64_t stream) const;
    uint64_t step_chunk(const Generation& cur, Generation& next, size_t b, size_t begin, size_t end,
                        uint32_t ifs, const uint32_t* src) const;
    uint64_t repair(Generation& g, size_t b, uint64_t stream) const;

    fp::Frame frame_;                                      ///< width, height, view (region), background
    double sxmin_ = 0, sxmax_ = 1, symin_ = 0, symax_ = 1; ///< start box
    uint64_t seed_ = 1, steps_ = 30, points_ = 100000, buffers_ = 2, child_ = 0;
    bool colour_ = true; ///< the colourer reads the colour sums
    bool steal_ = false; ///< colour stealing: points carry (u, v) of the colour IFS, not a colour
    bool rgb_ = true;    ///< points carry a colour (colour_ and not steal_)
    fp::Rgb initial_colour_;
    Picture picture_;
    std::vector<std::array<double, 6>> colour_maps_; ///< per map: [a, b, c, d, e, f] of its colour map

    std::vector<std::shared_ptr<const fp::Transform>> maps_;
    std::vector<fp::Rgb> colours_;
    std::vector<std::vector<uint32_t>> ifs_; ///< IFS i: indices in maps_ of its maps, in order
    size_t max_maps_ = 1;                    ///< most maps in one IFS
    std::vector<double> ifs_cum_, buffer_cum_;
    uint32_t ifs_fallback_ = 0, buffer_fallback_ = 0;
    std::shared_ptr<const fp::Colourer> colourer_;
};

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
    if (p.has("picture")) {
        steal_ = true;
        if (!colour_)
            throw fp::ParamError("picture", "colour stealing needs a colourer that shows the points' colours "
                                            "(map-colour or flame); this one shows only where they fall");
        const std::string& name = p.string("picture");
        picture_ = name == "hues" ? hues_picture() : png_picture(name);
    }
    rgb_ = colour_ && !steal_;

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
        if (items[j].extras) {
            ifs_of[j] = uint32_t(items[j].extras->integer("ifs"));
            if (items[j].extras->has("colour")) c = items[j].extras->colour("colour");
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
    const uint64_t px = uint64_t(frame_.width) * uint64_t(frame_.height);
    const uint64_t per_point =
        2 * sizeof(double) + (rgb_ ? 3 * sizeof(float) : 0) + (steal_ ? 2 * sizeof(double) : 0);
    const uint64_t buffers = 2 * buffers_ * points_ * per_point; // two generations
    // (Hit counts alone, 8 bytes a bin, for a colourer that reads no more: as the child is plotted.)
    const uint64_t hist = px * (colourer_->reads_hits_only() ? sizeof(uint64_t) : sizeof(fp::HistBin));
    const uint64_t image = px * 3 * sizeof(float);
    // No per-worker state: a task's scratch is on the stack.
    return buffers + hist + image + picture_.rgb.size();
}

void Superfractal::fill_start(Generation& g, size_t b, size_t begin, size_t end, uint64_t stream) const {
    fp::Rng rng = fp::chain_stream(seed_, stream);
    const size_t base = b * size_t(points_);
    for (size_t i = begin; i < end; ++i) {
        const double u = fp::uniform_double(rng), w = fp::uniform_double(rng);
        g.x[base + i] = sxmin_ + (sxmax_ - sxmin_) * u;
        g.y[base + i] = symin_ + (symax_ - symin_) * w;
    }
    if (steal_) {
        std::fill(g.u.begin() + std::ptrdiff_t(base + begin), g.u.begin() + std::ptrdiff_t(base + end), 0.5);
        std::fill(g.v.begin() + std::ptrdiff_t(base + begin), g.v.begin() + std::ptrdiff_t(base + end), 0.5);
    }
    if (rgb_) {
        std::fill(g.r.begin() + std::ptrdiff_t(base + begin), g.r.begin() + std::ptrdiff_t(base + end),
                  initial_colour_.r);
        std::fill(g.g.begin() + std::ptrdiff_t(base + begin), g.g.begin() + std::ptrdiff_t(base + end),
                  initial_colour_.g);
        std::fill(g.b.begin() + std::ptrdiff_t(base + begin), g.b.begin() + std::ptrdiff_t(base + end),
                  initial_colour_.b);
    }
}

// New buffer b, points [begin, end): for each share j of IFS `ifs` overlapping the range, the
// source points j + m t of buffer src[j], in batches of batch_points that stay in L1: gather,
// one Transform::apply call, the colours and one Colourer::update call, the finiteness count.
// Returns the number of non-finite points made.
uint64_t Superfractal::step_chunk(const Generation& cur, Generation& next, size_t b, size_t begin, size_t end,
                                  uint32_t ifs, const uint32_t* src) const {
    const std::vector<uint32_t>& maps = ifs_[ifs];
    const size_t n = size_t(points_), m = maps.size();
    const size_t q = n / m, rem = n % m;
    const size_t base = b * n;
    uint32_t map_index[batch_points];
    uint64_t bad = 0;
    for (size_t j = 0; j < m; ++j) {
        const size_t off = j * q + std::min(j, rem), nj = q + (j < rem ? 1 : 0);
        const size_t lo = std::max(begin, off), hi = std::min(end, off + nj);
        if (lo >= hi) continue;
        const size_t sbase = size_t(src[j]) * n;
        std::fill(map_index, map_index + batch_points, maps[j]);
        for (size_t b0 = lo; b0 < hi; b0 += batch_points) {
            const size_t b1 = std::min(hi, b0 + batch_points), len = b1 - b0;
            double* __restrict x = next.x.data() + base + b0;
            double* __restrict y = next.y.data() + base + b0;
            const double* __restrict cx = cur.x.data();
            const double* __restrict cy = cur.y.data();
            const size_t s0 = sbase + j + m * (b0 - off); // source of point b0 + i: s0 + m i
            for (size_t i = 0; i < len; ++i) {
                const size_t s = s0 + m * i;
                x[i] = cx[s];
                y[i] = cy[s];
            }
            maps_[maps[j]]->apply(fp::Points<double>{x, y, len}, nullptr);
            if (steal_) {
                // The colour IFS in lockstep: the same map number, the same source point.
                const std::array<double, 6>& cm = colour_maps_[maps[j]];
                double* __restrict u = next.u.data() + base + b0;
                double* __restrict v = next.v.data() + base + b0;
                const double* __restrict cu = cur.u.data();
                const double* __restrict cv = cur.v.data();
                for (size_t i = 0; i < len; ++i) {
                    const size_t s = s0 + m * i;
                    const double u0 = cu[s], v0 = cv[s];
                    u[i] = cm[0] * u0 + cm[1] * v0 + cm[4];
                    v[i] = cm[2] * u0 + cm[3] * v0 + cm[5];
                }
            }
            if (rgb_) {
                float* __restrict r = next.r.data() + base + b0;
                float* __restrict g = next.g.data() + base + b0;
                float* __restrict bl = next.b.data() + base + b0;
                for (size_t i = 0; i < len; ++i) {
                    const size_t s = s0 + m * i;
                    r[i] = cur.r[s];
                    g[i] = cur.g[s];
                    bl[i] = cur.b[s];
                }
                colourer_->update(map_index, fp::ColourState{r, g, bl, len}, colours_.data(), nullptr);
            }
            for (size_t i = 0; i < len; ++i) bad += (std::isfinite(x[i]) && std::isfinite(y[i])) ? 0u : 1u;
        }
    }
    return bad;
}

// Replace the non-finite points of buffer b by the previous finite point (the first finite
// one for those before it); redraw the whole buffer from the start box when none is finite.
// Returns the points redrawn.
uint64_t Superfractal::repair(Generation& g, size_t b, uint64_t stream) const {
    const size_t n = size_t(points_), base = b * n;
    auto finite = [&](size_t i) { return std::isfinite(g.x[base + i]) && std::isfinite(g.y[base + i]); };
    size_t first = 0;
    while (first < n && !finite(first)) ++first;
    if (first == n) {
        fill_start(g, b, 0, n, stream);
        return n;
    }
    auto copy = [&](size_t to, size_t from) {
        g.x[base + to] = g.x[base + from];
        g.y[base + to] = g.y[base + from];
        if (steal_) {
            g.u[base + to] = g.u[base + from];
            g.v[base + to] = g.v[base + from];
        }
        if (rgb_) {
            g.r[base + to] = g.r[base + from];
            g.g[base + to] = g.g[base + from];
            g.b[base + to] = g.b[base + from];
        }
    };
    for (size_t i = 0; i < first; ++i) copy(i, first);
    for (size_t i = first + 1; i < n; ++i)
        if (!finite(i)) copy(i, i - 1);
    return 0;
}

fp::Image Superfractal::render(fp::RenderContext& ctx, fp::RenderStats& stats) const {
    stats = fp::RenderStats{};
    const size_t n = size_t(points_), nb = size_t(buffers_);
    const size_t chunks = (n + chunk_points - 1) / chunk_points;
    const size_t tasks = nb * chunks;

    Generation gen[2];
    for (auto& g : gen) {
        g.x.resize(nb * n);
        g.y.resize(nb * n);
        if (rgb_) {
            g.r.resize(nb * n);
            g.g.resize(nb * n);
            g.b.resize(nb * n);
        }
        if (steal_) {
            g.u.resize(nb * n);
            g.v.resize(nb * n);
        }
    }

    // Over several ranks (MPI), rank r computes tasks r, r + N, ... of every generation, the
    // rest of it left +0 (all bits zero), and every rank gets the whole generation back by a
    // bitwise or (RenderContext::combine) before the next step reads it. Each task's points
    // depend on the recipe alone, so the generations are the same bytes on any rank count.
    const size_t rank = ctx.rank(), ranks = std::max(1u, ctx.ranks());
    const size_t mine = tasks > rank ? (tasks - rank + ranks - 1) / ranks : 0;
    const auto clear = [&](Generation& g) {
        if (ranks == 1) return;
        for (auto* a : {&g.x, &g.y, &g.u, &g.v}) std::fill(a->begin(), a->end(), 0.0);
        for (auto* a : {&g.r, &g.g, &g.b}) std::fill(a->begin(), a->end(), 0.0f);
    };
    const auto share = [&](Generation& g) {
        if (ranks == 1) return;
        for (auto* a : {&g.x, &g.y, &g.u, &g.v})
            ctx.combine(a->data(), a->size() * sizeof(double), sizeof(uint64_t), fp::fold::bit_or<uint64_t>,
                        true);
        for (auto* a : {&g.r, &g.g, &g.b})
            ctx.combine(a->data(), a->size() * sizeof(float), sizeof(uint32_t), fp::fold::bit_or<uint32_t>,
                        true);
    };
    static_assert(sizeof(double) == sizeof(uint64_t) && sizeof(float) == sizeof(uint32_t));

    // Start sets: random points of the start box.
    clear(gen[0]);
    ctx.parallel_for(mine, [&](size_t i, unsigned) {
        if (ctx.cancelled()) throw fp::Cancelled();
        const size_t t = rank + i * ranks;
        const size_t b = t / chunks, c = t % chunks;
        const size_t begin = c * chunk_points, end = std::min(n, begin + chunk_points);
        fill_start(gen[0], b, begin, end, 1 + t);
        ctx.progress(end - begin);
    });
    share(gen[0]);

    fp::Rng choices = fp::chain_stream(seed_, 0);
    std::vector<uint32_t> ifs_choice(nb), src(nb * max_maps_);
    std::vector<uint64_t> bad(tasks);
    std::vector<uint64_t> redrawn(nb);
    for (uint64_t s = 0; s < steps_; ++s) {
        if (ctx.cancelled()) throw fp::Cancelled();
        const Generation& cur = gen[s % 2];
        Generation& next = gen[(s + 1) % 2];
        for (size_t b = 0; b < nb; ++b) {
            ifs_choice[b] = draw(choices, ifs_cum_, ifs_fallback_);
            for (size_t j = 0; j < ifs_[ifs_choice[b]].size(); ++j)
                src[b * max_maps_ + j] = draw(choices, buffer_cum_, buffer_fallback_);
        }
        clear(next);
        std::fill(bad.begin(), bad.end(), 0);
        ctx.parallel_for(mine, [&](size_t i, unsigned) {
            if (ctx.cancelled()) throw fp::Cancelled();
            const size_t t = rank + i * ranks;
            const size_t b = t / chunks, c = t % chunks;
            const size_t begin = c * chunk_points, end = std::min(n, begin + chunk_points);
            bad[t] = step_chunk(cur, next, b, begin, end, ifs_choice[b], src.data() + b * max_maps_);
            ctx.progress(end - begin);
        });
        share(next);
        if (ranks > 1) ctx.combine(bad.data(), bad.size() * 8, 8, fp::fold::sum<uint64_t>, true);
        uint64_t bad_step = 0;
        for (uint64_t x : bad) bad_step += x;
        if (bad_step == 0) continue;
        stats.bad_values += bad_step;
        std::fill(redrawn.begin(), redrawn.end(), 0);
        ctx.parallel_for(nb, [&](size_t b, unsigned) {
            if (ctx.cancelled()) throw fp::Cancelled();
            uint64_t any = 0;
            for (size_t c = 0; c < chunks; ++c) any += bad[b * chunks + c];
            if (any) redrawn[b] = repair(next, b, 1 + tasks + s * nb + b);
        });
        for (uint64_t x : redrawn) stats.restarts += x;
    }
    if (ctx.cancelled()) throw fp::Cancelled();
    // (Every rank holds the last generation; rank 0 plots it, a small part of the work.)
    if (rank != 0) return fp::Image{};

    // The child: buffer `child` of the last generation, into one integer histogram.
    const Generation& last = gen[steps_ % 2];
    // A colourer that reads hit counts alone gets them alone (fp::Histogram::hits): a quarter
    // of the memory, and of the work of filling, summarising and shading the bins.
    const bool hits_only = colourer_->reads_hits_only();
    fp::Histogram hist;
    if (hits_only) {
        hist.width = frame_.width;
        hist.height = frame_.height;
        hist.hits.assign(size_t(frame_.width) * size_t(frame_.height), 0);
    } else {
        hist.resize(frame_.width, frame_.height);
    }
    const double scx = double(frame_.width) / (frame_.region.xmax - frame_.region.xmin),
                 scy = double(frame_.height) / (frame_.region.ymax - frame_.region.ymin);
    const size_t base = size_t(child_) * n;
    const auto quant = fp::quantise_colour;
    uint64_t drawn = 0;
    for (size_t i = 0; i < n; ++i) {
        if (i % (size_t(1) << 20) == 0 && ctx.cancelled()) throw fp::Cancelled();
        const double x = last.x[base + i], y = last.y[base + i];
        if (!(x >= frame_.region.xmin && x < frame_.region.xmax && y > frame_.region.ymin &&
              y <= frame_.region.ymax))
            continue;
        const auto ix = std::min(uint32_t((x - frame_.region.xmin) * scx), uint32_t(frame_.width - 1));
        const auto iy = std::min(uint32_t((frame_.region.ymax - y) * scy), uint32_t(frame_.height - 1));
        const size_t at = size_t(iy) * size_t(frame_.width) + ix;
        ++drawn;
        if (hits_only) {
            ++hist.hits[at];
            continue;
        }
        fp::HistBin& bin = hist.bins[at];
        ++bin.hits;
        if (steal_) {
            const fp::Rgb c = picture_.at(last.u[base + i], last.v[base + i]);
            bin.r += quant(c.r);
            bin.g += quant(c.g);
            bin.b += quant(c.b);
        } else if (colour_) {
            bin.r += quant(last.r[base + i]);
            bin.g += quant(last.g[base + i]);
            bin.b += quant(last.b[base + i]);
        }
    }
    stats.samples = n;
    stats.drawn = drawn;
    stats.unit = "points";

    fp::Image img;
    img.width = frame_.width;
    img.height = frame_.height;
    img.channels = 3;
    img.pixels.assign(size_t(frame_.width) * size_t(frame_.height) * 3, 0.0f);
    colourer_->resolve_parallel(hist, frame_.background, img.pixels.data(), ctx);
    return img;
}

// ---------------------------------------------------------------- schema
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
    fp::param::string("picture", "colour stealing (Barnsley): each point takes the colour of this picture at "
                                 "the point of the colour IFS (the maps' colour_map) run with the same "
                                 "choices; hues (built in) or a PNG file relative to the working folder")
        .opt()
        .reads_file("hues"),
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<Superfractal>(
        fp::Kind::Renderer, "superfractal",
        "Barnsley's V-variable superfractal algorithm with buffers (paper 03, Sec. III)", params)
        .with_example("{maps: [{type: affine, coefficients: [0.5, 0.375, 0.5, -0.375, -0.0625, 0.5625]}, "
                      "{type: affine, coefficients: [0.5, -0.375, -0.5, -0.375, 0.5625, 1.0625]}, "
                      "{type: affine, coefficients: [0.5, 0.375, -0.5, 0.375, -0.0625, 0.4375], ifs: 1}, "
                      "{type: affine, coefficients: [0.5, -0.375, 0.5, 0.375, 0.5625, -0.0625], ifs: 1}], "
                      "width: 64, height: 64, points_per_buffer: 4000, steps: 20}"))
