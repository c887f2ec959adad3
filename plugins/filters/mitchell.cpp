// mitchell — the Mitchell-Netravali cubic with B = C = 1/3, flam3's `mitchell` (filters.c),
// support 2: sharper than the gaussian, with a slight negative lobe (pixels are clamped
// afterwards).
#include "filter_base.hpp"

#include <cmath>

namespace {

double mitchell(double x) {
    constexpr double B = 1.0 / 3.0, C = 1.0 / 3.0;
    const double t = std::fabs(x), t2 = t * t;
    if (t < 1) return ((12 - 9 * B - 6 * C) * t * t2 + (-18 + 12 * B + 6 * C) * t2 + (6 - 2 * B)) / 6;
    if (t < 2)
        return ((-B - 6 * C) * t * t2 + (6 * B + 30 * C) * t2 + (-12 * B - 48 * C) * t + (8 * B + 24 * C)) /
               6;
    return 0;
}

constexpr fp::ParamSpec params[] = {fp_filters::radius_param("1")};

} // namespace

FIXPOINT_PLUGIN(fp::describe<fp_filters::Kernel<mitchell, 4>>(
    fp::Kind::Filter, "mitchell", "Mitchell-Netravali cubic (B = C = 1/3), support 2 radius pixels", params))
