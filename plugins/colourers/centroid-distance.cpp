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
#include "tone_map.hpp"

#include <array>

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace {

__extension__ typedef unsigned __int128 u128;

constexpr fp::ParamSpec params[] = {
    fp::param::colour("inner", "colour at the centre of mass (t = 0)").def("\"#ffe066\""),
    fp::param::colour("middle", "colour halfway out (t = 1/2); default: none, inner to outer directly").opt(),
    fp::param::colour("outer", "colour at the farthest hit pixel (t = 1)").def("\"#3a0ca3\""),
    fp_colourers::density_param,
    fp_colourers::gamma_param,
    fp::param::real("brightness", "factor on the final colour (clamped to [0, 1] afterwards)")
        .def("1")
        .above(0),
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

    // Without ctx serial, with it on the host's workers (pieces of 16 rows): integer sums and
    // maxima are exact in any order, and the per-bin code is shared: the same bytes.
    void run(const fp::Histogram& h, fp::Rgb background, float* rgb, fp::RenderContext* ctx) const {
        const std::size_t W = std::size_t(h.width);
        const std::size_t piece_bins = 16 * std::max<std::size_t>(W, 1);
        const std::size_t pieces = std::max<std::size_t>(1, (h.bins.size() + piece_bins - 1) / piece_bins);
        // Centroid: integer sums of hits, hits * column, hits * row (pixel centres add 1/2).
        struct Part {
            u128 sw = 0, sx = 0, sy = 0;
            std::uint64_t max_hits = 0;
            double dmax2 = 0;
        };
        std::vector<Part> part(pieces);
        fp_colourers::for_rows(ctx, h, [&](std::size_t i0, std::size_t i1) {
            Part p;
            for (std::size_t i = i0; i < i1; ++i) {
                const std::uint64_t hits = h.bins[i].hits;
                if (!hits) continue;
                p.sw += hits;
                p.sx += u128(hits) * (i % W);
                p.sy += u128(hits) * (i / W);
                p.max_hits = std::max(p.max_hits, hits);
            }
            part[i0 / piece_bins] = p;
        });
        u128 sw = 0, sx = 0, sy = 0;
        std::uint64_t max_hits = 0;
        for (const Part& p : part) {
            sw += p.sw, sx += p.sx, sy += p.sy;
            max_hits = std::max(max_hits, p.max_hits);
        }
        const double cx = sw ? double(sx) / double(sw) + 0.5 : 0;
        const double cy = sw ? double(sy) / double(sw) + 0.5 : 0;
        auto dist2 = [&](std::size_t i) {
            const double dx = double(i % W) + 0.5 - cx, dy = double(i / W) + 0.5 - cy;
            return dx * dx + dy * dy;
        };
        fp_colourers::for_rows(ctx, h, [&](std::size_t i0, std::size_t i1) {
            double d = 0;
            for (std::size_t i = i0; i < i1; ++i)
                if (h.bins[i].hits) d = std::max(d, dist2(i));
            part[i0 / piece_bins].dmax2 = d;
        });
        double dmax2 = 0;
        for (const Part& p : part) dmax2 = std::max(dmax2, p.dmax2);
        const double inv_dmax = dmax2 > 0 ? 1.0 / std::sqrt(dmax2) : 0.0;
        const fp_colourers::LogDensity density(max_hits, gamma_, ctx);
        fp_colourers::shade_bins(ctx, h, background, rgb, [&](std::size_t i, std::uint64_t hits) {
            const fp::Rgb c = colour_at(std::min(1.0, std::sqrt(dist2(i)) * inv_dmax));
            double k = brightness_;
            if (log_) k *= density(hits);
            return std::array<double, 3>{double(c.r) * k, double(c.g) * k, double(c.b) * k};
        });
    }

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
