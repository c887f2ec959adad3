// What the four filters share: the radius parameter, read with the same range and message.
#pragma once

#include <fixpoint/fixpoint.hpp>

namespace fp_filters {

/// The radius, in image pixels (flam3's spatial_filter_radius); `def` its default.
constexpr fp::ParamSpec radius_param(const char* def) {
    return fp::param::real("radius", "the filter's radius in image pixels (flam3's spatial_filter_radius): "
                                     "the kernel at u pixels is its function at u / radius")
        .def(def)
        .above(0)
        .max(16);
}

/// A filter whose kernel is F(x) on [-S, S].
template <double (*F)(double), double S>
class Kernel final : public fp::Filter {
public:
    explicit Kernel(const fp::ParamBag& p) : radius_(p.real("radius")) {}
    double value(double x) const override { return x < -S || x > S ? 0.0 : F(x); }
    double support() const override { return S; }
    double radius() const override { return radius_; }

private:
    double radius_;
};

} // namespace fp_filters
