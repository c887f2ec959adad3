// superfractal's random choices: the probabilities of the IFSs and of the buffers as a recipe
// gives them, and a draw among them.
//
// Probabilities
// -------------
// Each list must have one entry per IFS (ifs_probabilities) or per buffer
// (buffer_probabilities); absent, the probabilities are equal. Entries must be >= 0 (the
// schema's range) and sum to 1 within 1e-6; otherwise the recipe is refused, not normalised:
// the paper requires p_1 + p_2 = 1, and a plugin cannot warn, so a silent normalisation would
// hide a missing or mistyped entry. Sums within the tolerance are divided by their sum. An
// entry of 0 is allowed: that IFS or buffer is never chosen.
#pragma once

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace fp_superfractal {

/// Tolerance on the sum of the probabilities.
constexpr double sum_tolerance = 1e-6;

/// Shortest decimal that reads back as v (for messages).
inline std::string real_text(double v) {
    char buf[32];
    for (int prec = 1; prec <= 17; ++prec) {
        std::snprintf(buf, sizeof buf, "%.*g", prec, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

/// The probabilities `name` (one per item, `what` naming the items), checked and divided by
/// their sum; equal when absent. Returned as cumulative sums.
inline std::vector<double> cumulative_probabilities(const fp::ParamBag& p, const char* name, std::size_t n,
                                                    const char* what) {
    std::vector<double> v(n, 1.0 / double(n));
    if (p.has(name)) {
        v = p.reals(name);
        if (v.size() != n)
            throw fp::ParamError(name, "expected " + std::to_string(n) +
                                           (n == 1 ? " probability" : " probabilities") + " (one per " +
                                           what + "), got " + std::to_string(v.size()));
        double sum = 0;
        for (double x : v) sum += x;
        if (!(std::fabs(sum - 1.0) <= sum_tolerance))
            throw fp::ParamError(name,
                                 "the probabilities sum to " + real_text(sum) +
                                     ", not 1: give probabilities that sum to 1 (they are not normalised)");
        for (double& x : v) x /= sum;
    }
    std::vector<double> cum(n);
    double acc = 0;
    for (std::size_t k = 0; k < n; ++k) cum[k] = acc += v[k];
    return cum;
}

/// Index k drawn with probability cum[k] - cum[k - 1]: the first k with u < cum[k] (a binary
/// search: thousands of buffers are fine). An entry of probability 0 is never drawn;
/// `fallback` (the last entry of positive probability) takes the case u >= cum.back() that
/// rounding could leave.
inline std::uint32_t draw(fp::Rng& rng, const std::vector<double>& cum, std::uint32_t fallback) {
    const double u = fp::uniform_double(rng);
    const auto it = std::upper_bound(cum.begin(), cum.end(), u);
    return it == cum.end() ? fallback : std::uint32_t(it - cum.begin());
}

inline std::uint32_t last_positive(const std::vector<double>& cum) {
    for (std::size_t k = cum.size(); k-- > 0;)
        if (cum[k] > (k ? cum[k - 1] : 0.0)) return std::uint32_t(k);
    return std::uint32_t(cum.size() - 1);
}

} // namespace fp_superfractal
