// The conformance checks of a reconstruction filter (fp::Filter): what the finishing stage
// (fixpoint/finish.hpp) relies on when it builds the taps.
#include "conformance_detail.hpp"

#include <fixpoint/fixpoint.hpp>

#include <cmath>
#include <string>

namespace fp::host::detail {

void check_filter(const Filter& flt, Findings& f) {
    const double s = flt.support(), r = flt.radius();
    if (!(s > 0) || !std::isfinite(s)) f.push_back("filter: support() is not a positive number");
    if (!(r > 0) || !std::isfinite(r)) f.push_back("filter: radius() is not a positive number");
    if (!(s > 0) || !std::isfinite(s)) return;
    if (!(flt.value(0) > 0)) f.push_back("filter: value(0) is not positive");
    int odd = 0, outside = 0, bad = 0;
    for (int i = 1; i <= 400; ++i) {
        const double x = s * i / 400.0;
        const double a = flt.value(x), b = flt.value(-x);
        bad += !std::isfinite(a);
        // (The box is 1 on (-0.5, 0.5]: its edge is the one point where the two sides differ.)
        odd += a != b && i != 400;
        // Beyond twice the support, nothing to speak of (flam3's gaussian is not cut at its
        // support: its outermost taps fall a little past it).
        outside += std::fabs(flt.value(2 * s + x)) > 1e-3 * std::fabs(flt.value(0)) ||
                   std::fabs(flt.value(-2 * s - x)) > 1e-3 * std::fabs(flt.value(0));
    }
    if (bad) f.push_back("filter: value() is not finite inside the support");
    if (odd) f.push_back("filter: value() is not even (" + std::to_string(odd) + " of 399 points)");
    if (outside) f.push_back("filter: value() beyond twice the support is above 1e-3 of value(0)");
}

} // namespace fp::host::detail
