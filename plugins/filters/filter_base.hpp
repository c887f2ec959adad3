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

/// A filter whose kernel is F(x) (F zero where it ends), of support Halves / 2. (Halves, an
/// integer: clang 14 takes no floating-point template arguments.)
template <double (*F)(double), int Halves>
class Kernel final : public fp::Filter {
public:
    explicit Kernel(const fp::ParamBag& p) : radius_(p.real("radius")) {}
    double value(double x) const override { return F(x); }
    double support() const override { return Halves / 2.0; }
    double radius() const override { return radius_; }

private:
    double radius_;
};

} // namespace fp_filters
