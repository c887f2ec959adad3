// centroid-distance — each pixel coloured by its distance from the pattern's centre of mass
// (paper 03, Sec. V and Fig. 6: "points of fractals can be easily coloured by a colour
// depending e.g. on their distance from a chosen point of fractal (centre of its mass)").
//
// resolve:
//   centroid  c = sum_i H_i p_i / sum_i H_i over the bins, p_i the bin's pixel centre and H_i
//             its hits: the hit-weighted mean position, the centre of mass of the plotted
//             points to within a pixel. The sums are integers (128-bit), so the centroid is
//             exact and independent of the order in which the histogram was filled.
//   distance  t_i = |p_i - c| / max_j |p_j - c|, the maximum over the bins with hits, so t
//             runs over [0, 1] on every pattern whatever its size (t = 0 when all hits fall
//             in one bin).
//   colour    inner at t = 0, outer at t = 1, linear in RGB between them; with `middle`
//             given, inner -> middle on [0, 1/2] and middle -> outer on [1/2, 1].
//   pixel     clamp(colour * brightness * (log2(1 + H) / log2(1 + max H))^(1/gamma), 0, 1)
//             with density `log` (the log-density shading of paper 02 eq. (28), so density
//             still shows); with `flat` every hit pixel shows its full colour.
//   Empty bins take the background. Distances are in pixels (the view's aspect is the
//   image's).
//
// It reads only the hit counts (needs_colour() is false): the colour is a function of the
// position, not of the maps a chain used, so update() has nothing to carry and the renderer
// may skip the colour sums.
#include "finishing.hpp"
#include "tone_map.hpp"

#include <array>

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace {

constexpr fp::ParamSpec params[] = {
    fp::param::colour("inner", "colour at the centre of mass (t = 0)")
        .def("\"#ffe066\"")
        .as(fp::ParamRole::finish),
    fp::param::colour("middle", "colour halfway out (t = 1/2); default: none, inner to outer directly")
        .opt()
        .as(fp::ParamRole::finish),
    fp::param::colour("outer", "colour at the farthest hit pixel (t = 1)")
        .def("\"#3a0ca3\"")
        .as(fp::ParamRole::finish),
    fp_colourers::density_param.as(fp::ParamRole::finish),
    fp_colourers::gamma_param.as(fp::ParamRole::finish),
    fp::param::real("brightness", "factor on the final colour (clamped to [0, 1] afterwards)")
        .def("1")
        .above(0)
        .as(fp::ParamRole::finish),
};

class CentroidDistance final : public fp_colourers::Resolving<CentroidDistance> {
public:
    explicit CentroidDistance(const fp::ParamBag& p)
        : inner_(p.colour("inner")), outer_(p.colour("outer")), has_middle_(p.has("middle")),
          log_(p.string("density") == "log"), gamma_(p.real("gamma")), brightness_(p.real("brightness")) {
        middle_ = has_middle_ ? p.colour("middle") : inner_;
    }

    void update(const std::uint32_t*, fp::ColourState, const fp::Rgb*, const unsigned char*) const override {}

    bool needs_colour() const override { return false; }
    bool reads_hits_only() const override { return true; }

    // The centroid and the largest distance come from the whole histogram's summary (integer
    // sums and per-row extents: exact in any order, on any workers, and the same for the whole
    // histogram as for any strip of its rows); each pixel from its own bin.
    void run(const fp::Histogram& h, int row0, const fp::HistogramSummary& whole, fp::Rgb background,
             float* rgb, fp::RenderContext* ctx) const {
        const Centre c(whole);
        const std::size_t W = std::size_t(h.width);
        const fp_colourers::LogDensity density(whole.max_hits, gamma_, ctx);
        fp_colourers::shade_bins(ctx, h, background, rgb, [&](std::size_t i, std::uint64_t hits) {
            const fp::Rgb col = colour_at(c.t(i % W, std::size_t(row0) + i / W));
            double k = brightness_;
            if (log_) k *= density(hits);
            return std::array<double, 3>{double(col.r) * k, double(col.g) * k, double(col.b) * k};
        });
    }

    bool finishes() const override { return true; }
    void linear(const fp::Histogram& h, int row0, const fp::HistogramSummary& whole, double scale,
                std::size_t i0, std::size_t i1, float* out) const override {
        const Centre c(whole);
        const std::size_t W = std::size_t(h.width);
        fp_colourers::linear_bins(h, whole, scale, log_, i0, i1, out, [&](std::size_t i, std::uint64_t) {
            return colour_at(c.t(i % W, std::size_t(row0) + i / W));
        });
    }
    void display(const float* in, std::size_t n, fp::Rgb background, float* rgb) const override {
        fp_colourers::display_shaded(in, n, background, rgb, log_, gamma_, brightness_);
    }

    /// The centroid and the largest distance, from the whole histogram's summary (integer sums
    /// and per-row extents: exact in any order, on any workers, and the same for the whole
    /// histogram as for any strip of its rows).
    struct Centre {
        double cx, cy, inv_dmax;
        explicit Centre(const fp::HistogramSummary& whole) {
            // The hit-weighted mean column and row (pixel centres add 1/2).
            cx = whole.hits ? double(whole.hits_column) / double(whole.hits) + 0.5 : 0;
            cy = whole.hits ? double(whole.hits_row) / double(whole.hits) + 0.5 : 0;
            // The hit bin farthest from the centroid: in each row, |dx| is largest at the row's
            // first or last hit column, so those two bins per row give the maximum.
            double dmax2 = 0;
            for (std::size_t r = 0; r < whole.first.size(); ++r)
                if (whole.first[r] >= 0)
                    dmax2 = std::max(
                        {dmax2, dist2(std::size_t(whole.first[r]), r), dist2(std::size_t(whole.last[r]), r)});
            inv_dmax = dmax2 > 0 ? 1.0 / std::sqrt(dmax2) : 0.0;
        }
        double dist2(std::size_t col, std::size_t row) const {
            const double dx = double(col) + 0.5 - cx, dy = double(row) + 0.5 - cy;
            return dx * dx + dy * dy;
        }
        /// t in [0, 1] of the bin at (col, row).
        double t(std::size_t col, std::size_t row) const {
            return std::min(1.0, std::sqrt(dist2(col, row)) * inv_dmax);
        }
    };

    /// The colour map at t in [0, 1]: inner -> (middle ->) outer, linear in RGB.
    fp::Rgb colour_at(double t) const {
        if (!has_middle_) return lerp(inner_, outer_, t);
        return t < 0.5 ? lerp(inner_, middle_, 2 * t) : lerp(middle_, outer_, 2 * t - 1);
    }

private:
    static fp::Rgb lerp(fp::Rgb a, fp::Rgb b, double t) {
        return {float(a.r + (b.r - a.r) * t), float(a.g + (b.g - a.g) * t), float(a.b + (b.b - a.b) * t)};
    }

    fp::Rgb inner_, outer_, middle_;
    bool has_middle_, log_;
    double gamma_, brightness_;
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<CentroidDistance>(fp::Kind::Colourer, "centroid-distance",
                                   "colour by distance from the pattern's centre of mass through a "
                                   "colour map (paper 03 Fig. 6)",
                                   params)
        .with_example("{inner: \"#ffffff\", middle: \"#ff8800\", outer: \"#2040ff\"}"))
