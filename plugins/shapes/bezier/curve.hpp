// The Bézier set as its batch kernels see it (bezier/kernels.cpp: the vectorised inside test
// and ray exit, dispatched per instruction set). bezier.cpp's header says what the pieces are
// and why each holds at most one root.
#pragma once

#include <fixpoint/fixpoint.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace fp_bezier {

/// The number of sectors of YPieces' bounds.
constexpr std::size_t sector_count = 256;

/// Power-basis coefficients of one segment, b(t) = c[0] + c[1] t + c[2] t^2 + c[3] t^3 (a
/// quadratic has c[3] = 0), relative to a reference point.
struct Poly {
    std::array<double, 4> x{}, y{};
};

/// The curve cut, as seen from one origin o, into pieces of less than a quarter turn each,
/// in increasing order of the pseudo-angle of their start (fp_bezier::pseudo_angle), so that
/// a ray from o leaves through exactly one piece and crosses it once. Structure of arrays for
/// the kernels' gathers; `key` is padded with +inf to a power of two larger than n.
struct RayPieces {
    fp::Vec2 o{}; ///< the origin, in the curve's own coordinates
    std::size_t n = 0, n2 = 0;
    std::vector<double> key;
    std::vector<double> t0, t1;
    std::array<std::vector<double>, 4> cx, cy; ///< segment coefficients relative to o
    /// Squared bounds of the distance from o to the curve over each piece's sector, from its
    /// control hull (the nearest edge and the farthest corner, by 1e-9 apart for rounding): the
    /// inside test's sectors take them (Bezier::set_sectors).
    std::vector<double> in2, out2;
};

/// The curve cut where y'(t) = 0, so that y is monotonic on every piece: the inside test's
/// crossings, relative to `ref`.
struct YPieces {
    fp::Vec2 ref{};
    fp::Box box{}; ///< of the control points, relative to ref (the set lies inside)
    std::size_t n = 0;
    std::vector<double> t0, t1, y0, y1; ///< the ends of each piece and y there
    std::vector<double> xlo, xhi;       ///< bounds of x over the piece (its control hull)
    std::vector<Poly> poly;             ///< the piece's segment
    /// Bounds that answer first for most points: the squared distance from the centre `c`
    /// (relative to ref) to the curve over each of sector_count equal steps of the pseudo-angle
    /// about it lies in [in2, out2] (pairs, interleaved), so that a point of the sector nearer
    /// than sqrt(in2) is inside and one at sqrt(out2) or beyond outside. Empty: none yet (every
    /// point in the box counts its crossings).
    fp::Vec2 c{};
    std::vector<double> sectors;
};

/// An increasing function of atan2(y, x) on (-pi, pi] without a transcendental, from -2 to 2:
/// y / (|x| + |y|) where x >= 0, 2 - that where x < 0 <= y, -2 - that where x, y < 0.
inline double pseudo_angle(double x, double y) {
    const double t = y / (std::abs(x) + std::abs(y));
    return x >= 0 ? t : (y >= 0 ? 2 - t : -2 - t);
}

// Batch kernels, per target, dispatched from the class.
void inside(const YPieces& c, fp::Points<const float> p, unsigned char* out);
void inside(const YPieces& c, fp::Points<const double> p, unsigned char* out);
void ray(const RayPieces& r, fp::Points<const float> d, float* t);
void ray(const RayPieces& r, fp::Points<const double> d, double* t);

} // namespace fp_bezier
