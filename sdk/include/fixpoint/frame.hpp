// The picture a renderer makes: its size in pixels, the region of the plane it shows and the
// colour of pixels nothing reached. Every renderer reads these from the same parameters
// (`width`, `height`, the region as `view` or `area`, `background`) with the same checks and
// messages: one type, read once.
#pragma once

#include <fixpoint/params.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <string>

namespace fp {

struct Frame {
    int width = 0, height = 0;
    Box region;              ///< xmin < xmax and ymin < ymax, when has_region
    bool has_region = false; ///< false only when the region parameter is optional and unset
    Rgb background;
    bool has_background = false; ///< false only when `background` is optional and unset

    std::size_t pixels() const { return std::size_t(width) * std::size_t(height); }

    /// Reads `width`, `height`, the region `region_param` (reals of length 4, as declared in
    /// the plugin's ParamSpec) and `background`, each if the plugin declares it. Throws
    /// ParamError:
    ///   "height": "the image is too large: width * height must be below 4294967295 pixels"
    ///     (pixel indices are 32-bit in the renderers' histograms);
    ///   region_param: "the view must be [xmin, xmax, ymin, ymax] with xmin < xmax" (or
    ///     "with ymin < ymax"), the region named as the parameter is.
    static Frame read(const ParamBag& p, const std::string& region_param = "view");
};

} // namespace fp
