// flame — the running-average colouring of paper 02, Sec. 5 (Algorithm 2, eq. (28)), a
// simplified fractal-flame colouring.
//
// update: each chain carries a colour c; after a step by map j, c = (c + c_j) / 2, so the
// colour remembers the recent maps with weights 1/2, 1/4, ... and varies continuously
// across the fractal (unlike map-colour).
// resolve: pixel = brightness * mean colour of the bin * (log2(1 + H) / log2(1 + max H))^(1/gamma),
// clamped to [0, 1]; empty bins take the background.
//
// Departure from the paper: Algorithm 2 sets the pixel to the last colour written to it. We
// use the mean colour of all the hits of the bin instead (the histogram holds colour sums),
// so the image does not depend on the order in which chains and workers are merged, and the
// same recipe gives the same bytes on any number of threads.
#include "tone_map.hpp"

// update() once per instruction set (update-inl.hpp), dispatched at run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "update-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "update-inl.hpp"

namespace fp_colourers {
HWY_EXPORT(update_average);
} // namespace fp_colourers

namespace {
// (HWY_DYNAMIC_DISPATCH names the kernels unqualified; a build with static dispatch only
// resolves them as N_<target>::name from here.)
using namespace fp_colourers;

constexpr fp::ParamSpec params[] = {
    fp::param::real("gamma", "gamma of the log-density shading, eq. (28)").def("2.2").above(0),
    fp::param::real("brightness", "factor on the final colour (clamped to [0, 1] afterwards)")
        .def("1")
        .above(0),
};

class Flame final : public fp_colourers::Resolving<Flame> {
public:
    explicit Flame(const fp::ParamBag& p) : gamma_(p.real("gamma")), brightness_(p.real("brightness")) {}

    void update(const std::uint32_t* map, fp::ColourState s, const fp::Rgb* map_colours,
                const unsigned char* mask) const override {
        HWY_DYNAMIC_DISPATCH(update_average)(map, s, map_colours, mask);
    }

    fp::ColourRule colour_rule() const override { return fp::ColourRule::average; }

    /// The work of resolve() and resolve_parallel() (tone_map.hpp's Resolving); ctx null: serial.
    void run(const fp::Histogram& h, fp::Rgb background, float* rgb, fp::RenderContext* ctx) const {
        fp_colourers::tone_map(h, background, rgb, true, gamma_, brightness_, ctx);
    }

private:
    double gamma_, brightness_;
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<Flame>(fp::Kind::Colourer, "flame",
                        "running-average colour c = (c + c_j)/2 with log-density shading (paper 02)", params))
