// The accumulation buffer of point-plotting renderers.
//
// Integer sums: merging per-worker buffers is exact and independent of the order chains or
// workers are merged in, so the same recipe gives the same bytes on any number of threads.
#pragma once

#include <cstdint>
#include <vector>

namespace fp {

/// Colour sums are in units of 1/colour_scale.
constexpr std::uint64_t colour_scale = 65535;

struct HistBin {
    std::uint64_t hits = 0, r = 0, g = 0, b = 0;
};

/// The colour last written to a bin (PixelRule::last), in units of 1/colour_scale.
struct LastColour {
    std::uint16_t r = 0, g = 0, b = 0;
};

struct Histogram {
    int width = 0, height = 0;
    std::vector<HistBin> bins; ///< row-major, top row first
    /// Empty, or (for a colourer whose pixel_rule() is last) one entry per bin: the colour of
    /// the bin's last point in the order (step, chain); meaningful where hits > 0.
    std::vector<LastColour> last;

    void resize(int w, int h) {
        width = w;
        height = h;
        bins.assign(std::size_t(w) * std::size_t(h), HistBin{});
    }
};

} // namespace fp
