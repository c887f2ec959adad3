// box — the box filter, flam3's (filters.c): 1 on (-1/2, 1/2], support 1/2. With radius 1 it
// averages exactly the N x N bins of each pixel of a supersampled histogram.
#include "filter_base.hpp"

namespace {

double box(double x) { return x > -0.5 && x <= 0.5 ? 1.0 : 0.0; }

constexpr fp::ParamSpec params[] = {fp_filters::radius_param("1")};

} // namespace

FIXPOINT_PLUGIN(fp::describe<fp_filters::Kernel<box, 1>>(
    fp::Kind::Filter, "box", "box filter: the mean over a square of radius pixels (flam3's box)", params))
