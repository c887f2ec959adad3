// density — one colour shaded by the log-density of hits (paper 02, eq. (28), without the
// per-map colour): the plain histogram image of a chaos game.
//
// update: nothing (a chain carries no colour).
// resolve: pixel = colour * (log2(1 + H) / log2(1 + max H))^(1/gamma), H the bin's hits;
// empty bins take the background.
//
// It reads only the hit counts (needs_colour() is false), so a renderer may skip the colour
// state and the colour sums and deposit hit counts alone: the cheapest histogram, the same
// work as the reference kernels.
#include "finishing.hpp"
#include "tone_map.hpp"

#include <array>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace {

constexpr fp::ParamSpec params[] = {
    fp::param::colour("colour", "colour of the densest bins").def("[1, 1, 1]").as(fp::ParamRole::finish),
    fp::param::real("gamma", "gamma of the log-density shading, eq. (28)")
        .def("2.2")
        .above(0)
        .as(fp::ParamRole::finish),
};

class Density final : public fp_colourers::Resolving<Density> {
public:
    explicit Density(const fp::ParamBag& p) : colour_(p.colour("colour")), gamma_(p.real("gamma")) {}

    void update(const std::uint32_t*, fp::ColourState, const fp::Rgb*, const unsigned char*) const override {}

    bool needs_colour() const override { return false; }
    bool reads_hits_only() const override { return true; }

    /// The work of resolve() and resolve_parallel() (tone_map.hpp's Resolving): without ctx
    /// serial, with it on the host's workers; the same code per bin, the same bytes.
    void run(const fp::Histogram& h, int, const fp::HistogramSummary& whole, fp::Rgb background, float* rgb,
             fp::RenderContext* ctx) const {
        const fp_colourers::LogDensity density(whole.max_hits, gamma_, ctx);
        fp_colourers::shade_bins(ctx, h, background, rgb, [&](std::size_t, std::uint64_t hits) {
            const double k = density(hits);
            return std::array<double, 3>{double(colour_.r) * k, double(colour_.g) * k, double(colour_.b) * k};
        });
    }

    bool finishes() const override { return true; }
    void linear(const fp::Histogram& h, int, const fp::HistogramSummary& whole, double scale, std::size_t i0,
                std::size_t i1, float* out) const override {
        fp_colourers::linear_bins(h, whole, scale, true, i0, i1, out,
                                  [&](std::size_t, std::uint64_t) { return colour_; });
    }
    void display(const float* in, std::size_t n, fp::Rgb background, float* rgb) const override {
        fp_colourers::display_shaded(in, n, background, rgb, true, gamma_, 1.0);
    }

private:
    fp::Rgb colour_;
    double gamma_;
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Density>(fp::Kind::Colourer, "density",
                                      "one colour shaded by the log-density of hits (no colour per point)",
                                      params))
