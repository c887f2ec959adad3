// The superformula curve as its kernels see it (superformula/kernels.cpp: the vectorised inside
// test, ray exit and radius, dispatched per instruction set).
#pragma once

#include <fixpoint/fixpoint.hpp>

#include <cstddef>

namespace fp_superformula {

/// Sectors of the inside test's bounds: equal steps of a pseudo-angle of (x, y) != 0 that
/// increases with atan2(y, x) from -2 to 2 without a transcendental: t = y / (|x| + |y|)
/// where x >= 0, 2 - t where x < 0 <= y, -2 - t where x, y < 0 (the kernels' classify;
/// prove_bounds inverts it).
constexpr std::size_t sector_count = 256;

/// The curve's parameters as the batch kernels take them.
struct Curve {
    double m4, inv_n1, n2, n3, inv_a, inv_b, scale; // m / 4, 1 / n1, n2, n3, 1 / a, 1 / b, scale
    double cx, cy, cr, sr;                          // centre; cosine and sine of the rotation
    double r_lo, r_hi; // bounds of the radius (sampled, checked by the root finder)
    /// Squared radii of the proven bounds (see Superformula::prove_bounds): |p - c|^2 >= out2
    /// is outside and < in2 inside for every angle, without r(theta); +inf and 0 when none.
    double out2, in2;
    /// The same per sector: sector_count pairs in2, out2 (the global ones where none tighter).
    double sectors[2 * sector_count];
};

/// A ray's origin relative to the centre: w, |w| and f(0) = |w| - r(theta(w)) < 0.
struct Origin {
    double x, y, norm, f0;
};

// Batch kernels, per target (below), dispatched from the class.
void inside(const Curve& c, fp::Points<const float> p, unsigned char* out);
void inside(const Curve& c, fp::Points<const double> p, unsigned char* out);
void ray(const Curve& c, const Origin* w, fp::Points<const float> d, float* t);
void ray(const Curve& c, const Origin* w, fp::Points<const double> d, double* t);
double radius_at(const Curve& c, double qx, double qy);

} // namespace fp_superformula
