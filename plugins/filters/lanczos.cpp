// lanczos — the Lanczos-3 window sinc(x) sinc(x / 3) on [-3, 3]. (flam3's `lanczos3` multiplies
// a second sinc(x / 3) into it; this is the textbook kernel.) The sharpest of the four, with
// ringing at hard edges (pixels are clamped afterwards).
#include "filter_base.hpp"

#include <cmath>
#include <numbers>

namespace {

double sinc(double x) {
    if (x == 0) return 1;
    const double px = std::numbers::pi * x;
    return std::sin(px) / px;
}

double lanczos(double x) { return x <= -3 || x >= 3 ? 0.0 : sinc(x) * sinc(x / 3.0); }

constexpr fp::ParamSpec params[] = {fp_filters::radius_param("1")};

} // namespace

FIXPOINT_PLUGIN(fp::describe<fp_filters::Kernel<lanczos, 6>>(
    fp::Kind::Filter, "lanczos", "Lanczos-3 windowed sinc, support 3 radius pixels", params))
