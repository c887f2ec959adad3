// Filter: the reconstruction filter a renderer applies to its histogram or samples when it
// makes the image (the finishing stage, fixpoint/finish.hpp): box, gaussian, mitchell and
// lanczos, flam3's kernels of those names. (Added in ABI 17.)
#pragma once

#include <fixpoint/object.hpp>

namespace fp {

class Filter : public Object {
public:
    ~Filter() override;

    /// The kernel at x, in units of the radius: an even function, 0 (or negligible: below
    /// 1e-3 of value(0)) beyond twice support(). Called while the kernel's taps are built,
    /// never per point.
    virtual double value(double x) const = 0;
    /// Where the taps are laid: [-support(), support()] (flam3's spatial support).
    virtual double support() const = 0;
    /// The radius in image pixels: the weight of a bin u pixels from a pixel's centre is
    /// value(u / radius), normalised (flam3's spatial_filter_radius).
    virtual double radius() const = 0;
};

} // namespace fp
