// Tone mapping shared by the colourers: histogram bins to display pixels.
#pragma once

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace fp_colourers {

/// pixel = clamp(mean colour of the bin * density^(1/gamma) * brightness, 0, 1), where the
/// mean colour is the bin's colour sum / hits / colour_scale and, with `log_density`,
/// density = log2(1 + hits) / log2(1 + max hits) (paper 02, eq. (28)); otherwise density
/// = 1. Empty bins take `background`. Fixed order, no state: the same histogram gives the
/// same bytes.
inline void tone_map(const fp::Histogram& h, fp::Rgb background, float* rgb, bool log_density, double gamma,
                     double brightness) {
    std::uint64_t max_hits = 0;
    for (const auto& b : h.bins) max_hits = std::max(max_hits, b.hits);
    const double inv_log_max = max_hits > 0 ? 1.0 / std::log2(1.0 + double(max_hits)) : 0.0;
    const double inv_gamma = 1.0 / gamma;
    auto clamp01 = [](double v) { return float(std::clamp(v, 0.0, 1.0)); };
    for (std::size_t i = 0; i < h.bins.size(); ++i) {
        const fp::HistBin& b = h.bins[i];
        float* px = rgb + 3 * i;
        if (b.hits == 0) {
            px[0] = background.r;
            px[1] = background.g;
            px[2] = background.b;
            continue;
        }
        double k = brightness / (double(b.hits) * double(fp::colour_scale));
        if (log_density) k *= std::pow(std::log2(1.0 + double(b.hits)) * inv_log_max, inv_gamma);
        px[0] = clamp01(double(b.r) * k);
        px[1] = clamp01(double(b.g) * k);
        px[2] = clamp01(double(b.b) * k);
    }
}

} // namespace fp_colourers
