// flame — the running-average colouring of paper 02, Sec. 5 (Algorithm 2, eq. (28)), a
// simplified fractal-flame colouring, and paper 01's colouring by set.
//
// update: each chain carries a colour c; after a step by map j, c = (c + c_j) / 2, so the
// colour remembers the recent maps with weights 1/2, 1/4, ... and varies continuously
// across the fractal (unlike map-colour).
// resolve: pixel = brightness * colour of the bin * (log2(1 + H) / log2(1 + max H))^(1/gamma),
// clamped to [0, 1]; empty bins take the background. With `density: flam3`, flam3's tone
// instead: the density the log of the points per unit of area (finishing.hpp's Flam3Density).
//
// `mode` says which colour of the bin:
//   mean        the mean colour of all the bin's hits (the histogram's colour sums), the
//               default: it does not depend on which chain came last, and the running colour
//               is carried from the chain's first step (chains start from the mean map colour);
//   last        Algorithm 2 as written: the pixel keeps the colour written last (line 17,
//               I(x, y) = c), each chain's colour starts random (line 4) and is updated only
//               with the points it plots (line 16 sits under "if i > 20"). With many chains,
//               "last" is the largest (step, chain): the paper's single orbit writes in that
//               order, and no thread count changes it (fp::PixelRule::last);
//   set-colour  paper 01, Sec. 4: "the points of the fractal are coloured with the colour of
//               the set that was used to obtain the point": c = c_j, the pixel the colour of
//               the set that produced its last point, shaded like the others.
// `last` and `set-colour` need a renderer that keeps the last colours (chaos-game; the
// superfractal renderer refuses them); `last` runs chaos-game's generic path.
#include "finishing.hpp"
#include "tone_map.hpp"

#include <fixpoint/palette.hpp>

// update() once per instruction set (update-inl.hpp), dispatched at run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "update-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "update-inl.hpp"

namespace fp_colourers {
HWY_EXPORT(update_average);
HWY_EXPORT(update_map);
} // namespace fp_colourers

namespace {
// (HWY_DYNAMIC_DISPATCH names the kernels unqualified; a build with static dispatch only
// resolves them as N_<target>::name from here.)
using namespace fp_colourers;

constexpr fp::ParamSpec params[] = {
    fp::param::real("gamma", "gamma of the log-density shading, eq. (28)")
        .def("2.2")
        .above(0)
        .as(fp::ParamRole::finish),
    fp::param::real("brightness", "factor on the final colour (clamped to [0, 1] afterwards)")
        .def("1")
        .above(0)
        .as(fp::ParamRole::finish),
    fp::param::string("mode", "which colour a pixel shows: mean (of its hits), last (written, eq. (28) as "
                              "written: random start colour) or set-colour (paper 01: the colour of the set "
                              "that produced its last point)")
        .def("mean")
        .one_of("mean|last|set-colour"),
    fp::param::real("vibrancy",
                    "flam3's vibrancy: 1 applies gamma to the density alone (saturated colours), 0 "
                    "to each channel (paler)")
        .def("1")
        .min(0)
        .max(1)
        .as(fp::ParamRole::finish),
    fp::param::real("highlight_power",
                    "flam3's highlight_power: where a colour saturates, >= 0 turns it towards "
                    "white by that power, -1 clips each channel")
        .def("-1")
        .min(-1)
        .max(16)
        .as(fp::ParamRole::finish),
    fp::param::real("gamma_threshold",
                    "flam3's gamma_threshold: below this density the gamma curve is blended "
                    "with a line, so sparse pixels are not lifted (0: none)")
        .def("0")
        .min(0)
        .max(1)
        .as(fp::ParamRole::finish),
    fp::param::string("density",
                      "how a bin's hits become its density: log (eq. (28): relative to the brightest bin) "
                      "or flam3 (flam3's: the log of the points per unit of area, with its brightness and "
                      "contrast; the picture does not depend on the points drawn)")
        .def("log")
        .one_of("log|flam3")
        .as(fp::ParamRole::finish),
    fp::param::real("contrast", "flam3's contrast, with density flam3: the density's scale inside its log")
        .def("1")
        .above(0)
        .as(fp::ParamRole::finish),
    fp::palette_param,
    fp::palette_stops_param,
    fp::palette_mode_param,
};

class Flame final : public fp_colourers::Resolving<Flame> {
public:
    explicit Flame(const fp::ParamBag& p)
        : gamma_(p.real("gamma")), brightness_(p.real("brightness")),
          mode_(p.string("mode") == "last"         ? Mode::last
                : p.string("mode") == "set-colour" ? Mode::set_colour
                                                   : Mode::mean) {
        tone_.gamma = gamma_, tone_.brightness = brightness_, tone_.vibrancy = p.real("vibrancy");
        tone_.highlight_power = p.real("highlight_power"), tone_.gamma_threshold = p.real("gamma_threshold");
        flam3_ = p.string("density") == "flam3";
        contrast_ = p.real("contrast");
        if (!flam3_ && contrast_ != 1)
            throw fp::ParamError("contrast", "contrast is flam3's: it needs density flam3");
        if (flam3_) {
            // brightness is inside the density (Flam3Density); flam3 scales to 256 where white is
            // 255, blends the background by alpha and truncates to its 8 bits.
            tone_.brightness = 256.0 / 255.0;
            tone_.alpha_background = true;
            tone_.truncates = true;
        }
        has_palette_ = fp::palette_of(p, palette_);
        // flam3's index blends per point into the mean of a pixel's colours: mode mean alone.
        if (has_palette_ && mode_ != Mode::mean)
            throw fp::ParamError("mode",
                                 "a palette colours each point by flam3's index, whose pixels show the "
                                 "mean: mode mean, not " +
                                     p.string("mode"));
    }

    void update(const std::uint32_t* map, fp::ColourState s, const fp::Rgb* map_colours,
                const unsigned char* mask) const override {
        if (has_palette_) return update_index(map, s, mask);
        if (mode_ == Mode::set_colour)
            HWY_DYNAMIC_DISPATCH(update_map)(map, s, map_colours, mask);
        else
            HWY_DYNAMIC_DISPATCH(update_average)(map, s, map_colours, mask);
    }

    fp::ColourRule colour_rule() const override {
        if (has_palette_) return fp::ColourRule::none; // (a rule of its own: update_index)
        return mode_ == Mode::set_colour ? fp::ColourRule::map : fp::ColourRule::average;
    }
    bool palette_index() const override { return has_palette_; }
    fp::PixelRule pixel_rule() const override {
        return mode_ == Mode::mean ? fp::PixelRule::mean : fp::PixelRule::last;
    }

    /// The work of resolve() and resolve_parallel() (tone_map.hpp's Resolving); ctx null: serial.
    void run(const fp::Histogram& h, int, const fp::HistogramSummary& whole, fp::Rgb background, float* rgb,
             fp::RenderContext* ctx) const {
        const bool last = mode_ != Mode::mean;
        if (tone_.plain())
            return fp_colourers::tone_map(h, whole, background, rgb, true, gamma_, brightness_, last, ctx);
        if (flam3_)
            return run_tone(h, fp_colourers::Flam3Density(whole, brightness_, contrast_), background, rgb,
                            ctx);
        return run_tone(h, fp_colourers::LinearDensity(whole.max_hits, 1.0), background, rgb, ctx);
    }

    /// flam3's tone on each bin as a pixel of its own (coverage 1), as display() on a finished one.
    template <class Density>
    void run_tone(const fp::Histogram& h, const Density& density, fp::Rgb background, float* rgb,
                  fp::RenderContext* ctx) const {
        const bool last = mode_ != Mode::mean;
        if (last && h.last.size() != h.bins.size())
            throw fp::InternalError(
                "the renderer gave no last colours for a colourer whose pixel rule is last");
        fp_colourers::for_rows(ctx, h, [&](std::size_t i0, std::size_t i1) {
            for (std::size_t i = i0; i < i1; ++i) {
                const std::uint64_t hits = h.hits_at(i);
                float* px = rgb + 3 * i;
                if (hits == 0) {
                    px[0] = background.r, px[1] = background.g, px[2] = background.b;
                    continue;
                }
                const fp::Rgb c = fp_colourers::bin_colour(h, i, hits, last);
                const float p[5] = {density(hits), c.r, c.g, c.b, 1.0f};
                tone_.pixel(p, background, px);
            }
        });
    }

    bool finishes() const override { return true; }
    void linear(const fp::Histogram& h, int, const fp::HistogramSummary& whole, double scale, std::size_t i0,
                std::size_t i1, float* out) const override {
        const bool last = mode_ != Mode::mean;
        auto colour = [&](std::size_t i, std::uint64_t hits) {
            return fp_colourers::bin_colour(h, i, hits, last);
        };
        // (flam3's density is per unit of area: the bins' own hits, whatever the supersampling.)
        if (flam3_)
            return fp_colourers::density_bins(
                h, i0, i1, out, fp_colourers::Flam3Density(whole, brightness_, contrast_), colour);
        fp_colourers::linear_bins(h, whole, scale, true, i0, i1, out, colour);
    }
    void display(const float* in, std::size_t n, fp::Rgb background, float* rgb) const override {
        if (tone_.plain())
            return fp_colourers::display_shaded(in, n, background, rgb, true, gamma_, brightness_);
        for (std::size_t i = 0; i < n; ++i) tone_.pixel(in + 5 * i, background, rgb + 3 * i);
    }

private:
    /// flam3's rule (variations.c): i' = s c_j + (1 - s) i with the map's color c_j and
    /// color_speed s, then the chain's colour the palette's at i' (rect.c's lookup).
    void update_index(const std::uint32_t* map, fp::ColourState s, const unsigned char* mask) const {
        if (!s.index || !s.map_index || !s.map_speed)
            throw fp::InternalError("flame: a palette, but the renderer gave no palette indices");
        for (std::size_t i = 0; i < s.n; ++i) {
            if (mask && !mask[i]) continue;
            const std::uint32_t j = map[i];
            const float sp = s.map_speed[j];
            const float t = sp * s.map_index[j] + (1.0f - sp) * s.index[i];
            s.index[i] = t;
            const fp::Rgb c = palette_.at(t);
            s.r[i] = c.r, s.g[i] = c.g, s.b[i] = c.b;
        }
    }

    enum class Mode { mean, last, set_colour };
    double gamma_, brightness_, contrast_ = 1;
    Mode mode_;
    bool flam3_ = false;
    fp_colourers::Flam3Tone tone_;
    bool has_palette_ = false;
    fp::Palette palette_;
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<Flame>(fp::Kind::Colourer, "flame",
                        "running-average colour c = (c + c_j)/2 with log-density shading (paper 02)", params))
