// blend: a colourer. Each chain's colour moves towards the colour of the map that moved it,
// c' = (1 - w) c + w c_j (w = 0.5 is paper 02's running average, Sec. 5); a pixel shows the
// mean colour of its hits, darkened by its log-density (log(1 + H) / log(1 + max H))^(1/gamma).
// The colourer example of docs/writing-a-scheme.md, built out of tree by
// tests/external-scheme/run.sh.
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>

namespace {

class Blend final : public fp::Colourer {
public:
    static constexpr fp::ParamSpec params[] = {
        fp::param::real("weight", "w: the weight of the map's colour in c' = (1 - w) c + w c_j")
            .def("0.5")
            .min(0)
            .max(1),
        fp::param::real("gamma", "gamma of the log-density shading").def("2.2").above(0),
    };
    explicit Blend(const fp::ParamBag& p) : w_(float(p.real("weight"))), gamma_(p.real("gamma")) {}

    // After a step: chain i was moved by map[i], whose colour is colours[map[i]].
    void update(const std::uint32_t* map, fp::ColourState s, const fp::Rgb* colours,
                const unsigned char* mask) const override {
        for (std::size_t i = 0; i < s.n; ++i) {
            if (mask && !mask[i]) continue;
            const fp::Rgb c = colours[map[i]];
            s.r[i] = (1 - w_) * s.r[i] + w_ * c.r;
            s.g[i] = (1 - w_) * s.g[i] + w_ * c.g;
            s.b[i] = (1 - w_) * s.b[i] + w_ * c.b;
        }
    }

    // The histogram to pixels: 3 floats in [0, 1] per bin.
    void resolve(const fp::Histogram& h, fp::Rgb background, float* rgb) const override {
        std::uint64_t most = 0;
        for (const fp::HistBin& b : h.bins) most = std::max(most, b.hits);
        const double log_most = std::log1p(double(most));
        for (std::size_t i = 0; i < h.bins.size(); ++i) {
            const fp::HistBin& b = h.bins[i];
            float* px = rgb + 3 * i;
            if (b.hits == 0) {
                px[0] = background.r, px[1] = background.g, px[2] = background.b;
                continue;
            }
            const double shade = std::pow(std::log1p(double(b.hits)) / log_most, 1 / gamma_);
            const double scale = shade / (double(b.hits) * double(fp::colour_scale)); // mean, shaded
            px[0] = float(std::min(1.0, double(b.r) * scale));
            px[1] = float(std::min(1.0, double(b.g) * scale));
            px[2] = float(std::min(1.0, double(b.b) * scale));
        }
    }

private:
    float w_;
    double gamma_;
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Blend>(fp::Kind::Colourer, "blend",
                                    "each chain's colour blends towards its map's; pixels show the mean "
                                    "colour, shaded by log-density",
                                    Blend::params))
