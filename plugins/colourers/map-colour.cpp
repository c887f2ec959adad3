// map-colour — each point takes the colour of the map that produced it (paper 01, Sec. 4:
// "the points of the fractal are coloured with the colour of the set that was used to
// obtain the point").
//
// update: c_i = map_colours[map[i]].
// resolve: each bin with hits shows the mean colour of its hits (colour sum / hits /
// colour_scale), so a pixel hit by several maps shows their mix in proportion; with
// density `log` it is darkened by (log2(1 + h) / log2(1 + max h))^(1/gamma) as in paper 02,
// eq. (28), which brings out the structure of sparse regions; with `flat` every hit pixel
// shows its full colour, like the paper 01 figures. Empty bins take the background.
#include "finishing.hpp"
#include "tone_map.hpp"

#include <string>

// update() once per instruction set (update-inl.hpp), dispatched at run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "update-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "update-inl.hpp"

namespace fp_colourers {
HWY_EXPORT(update_map);
} // namespace fp_colourers

namespace {
// (HWY_DYNAMIC_DISPATCH names the kernels unqualified; a build with static dispatch only
// resolves them as N_<target>::name from here.)
using namespace fp_colourers;

constexpr fp::ParamSpec params[] = {
    fp_colourers::density_param,
    fp_colourers::gamma_param,
};

class MapColour final : public fp_colourers::Resolving<MapColour> {
public:
    explicit MapColour(const fp::ParamBag& p) : log_(p.string("density") == "log"), gamma_(p.real("gamma")) {}

    void update(const std::uint32_t* map, fp::ColourState s, const fp::Rgb* map_colours,
                const unsigned char* mask) const override {
        HWY_DYNAMIC_DISPATCH(update_map)(map, s, map_colours, mask);
    }

    fp::ColourRule colour_rule() const override { return fp::ColourRule::map; }

    /// The work of resolve() and resolve_parallel() (tone_map.hpp's Resolving); ctx null: serial.
    void run(const fp::Histogram& h, int, const fp::HistogramSummary& whole, fp::Rgb background, float* rgb,
             fp::RenderContext* ctx) const {
        fp_colourers::tone_map(h, whole, background, rgb, log_, gamma_, 1.0, false, ctx);
    }

    bool finishes() const override { return true; }
    void linear(const fp::Histogram& h, int, const fp::HistogramSummary& whole, double scale, std::size_t i0,
                std::size_t i1, float* out) const override {
        fp_colourers::linear_bins(h, whole, scale, log_, i0, i1, out, [&](std::size_t i, std::uint64_t hits) {
            return fp_colourers::bin_colour(h, i, hits, false);
        });
    }
    void display(const float* in, std::size_t n, fp::Rgb background, float* rgb) const override {
        fp_colourers::display_shaded(in, n, background, rgb, log_, gamma_, 1.0);
    }

private:
    bool log_;
    double gamma_;
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<MapColour>(fp::Kind::Colourer, "map-colour",
                                        "each point takes the colour of the map that produced it", params))
