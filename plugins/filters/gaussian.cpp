// gaussian — flam3's default spatial filter (filters.c): exp(-2 x^2) sqrt(2 / pi) on
// [-1.5, 1.5]. At u pixels from a pixel's centre the weight is exp(-2 (u / r)^2), so the
// radius r is twice the standard deviation (sigma = r / 2 pixels) and the kernel is cut at
// 1.5 r = 3 sigma: flam3's meaning of spatial_filter_radius, whose default is 0.5. (Not cut to
// 0 beyond 1.5: flam3 evaluates its outermost taps a little past it, and so does fixpoint.)
#include "filter_base.hpp"

#include <cmath>
#include <numbers>

namespace {

double gaussian(double x) { return std::exp(-2.0 * x * x) * std::sqrt(2.0 / std::numbers::pi); }

constexpr fp::ParamSpec params[] = {fp_filters::radius_param("0.5")};

} // namespace

FIXPOINT_PLUGIN(fp::describe<fp_filters::Kernel<gaussian, 3>>(
    fp::Kind::Filter, "gaussian",
    "gaussian filter exp(-2 (u / radius)^2), cut at 1.5 radius pixels (flam3's default filter)", params))
