// The reduction "mod 2 pi" of paper 04, eq. (13), applied by the orbit-trap renderer after every
// step of the iteration scheme, over a batch (structure of arrays), vectorised.
//
//   fmod     C's fmod: x - 2 pi trunc(x / 2 pi), the sign of x, in (-2 pi, 2 pi) (the default:
//            symmetric about 0, so the traps at negative coordinates stay reachable and the
//            pattern keeps the symmetries of the paper's figures)
//   centred  into [-pi, pi): x - 2 pi round(x / 2 pi)
//   floor    into [0, 2 pi): x - 2 pi floor(x / 2 pi) (the textbook "mod"; it makes traps at
//            negative coordinates unreachable, kept for comparison)
//   none     no reduction (maps that are not periodic)
//   hexagonal x and y together, modulo the hexagonal lattice 2 pi Z (1, 0) + 2 pi Z (1/2, sqrt 3 / 2)
//            of the hexagonal wallpaper groups into its hexagon about 0 (the wallpaper transform's
//            own `reduction: hexagonal`, the same function: fixpoint/lattice.hpp, which
//            derives it). Its range is the hexagon (in_cell), not a box: reduce_xy and the
//            fused pass's check test it; points in it stay as they are, bit for bit. Not exact
//            like the others (the lattice is irrational), but one function of the point, the
//            same on every instruction set and in both passes.
//
// The period is 2 pi rounded to T. Float lanes are reduced exactly (the result is the exact
// value of the formula, as std::fmod gives): x and n * a are computed in double, where
// n * a is exact for |n| < 2^28 (a has 24 significant bits) and x - n * a is the exact result
// because that result is a float; the quotient's rounding can miss by one only at an exact
// boundary, and the fix-ups below move such a result back into range, again exactly. Batches
// holding |x| >= 2^28 * 2 pi (rare: diverging orbits) take the scalar library path. Double
// lanes use std::fmod / std::remainder / std::floor directly (scalar; double is the slow path
// anyway).
#pragma once

#include <fixpoint/lattice.hpp>

#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>

namespace fp_orbit_trap {

/// The reduction's kinds: the wallpaper transform's (the SDK's lattice reductions).
using Reduction = fp::kernels::Reduction;

template <class T>
constexpr T period = T(2 * std::numbers::pi);

namespace detail {

inline float reduce_scalar(float v, Reduction r) {
    const float a = period<float>;
    switch (r) {
    case Reduction::fmod: return std::fmod(v, a);
    case Reduction::centred: {
        float x = std::remainder(v, a); // [-a/2, a/2], exact
        return x >= a / 2 ? x - a : x;
    }
    case Reduction::floor: {
        const float x = std::fmod(v, a);
        const float y = x < 0 ? x + a : x; // a - tiny may round up to a, which is 0 mod a
        return y >= a ? 0.0f : y;
    }
    case Reduction::none:
    case Reduction::hexagonal: return v; // (reduce_xy: x and y together)
    }
    return v;
}

inline double reduce_scalar(double v, Reduction r) {
    const double a = period<double>;
    switch (r) {
    case Reduction::fmod: return std::fmod(v, a);
    case Reduction::centred: {
        const double x = std::remainder(v, a);
        return x >= a / 2 ? x - a : x;
    }
    case Reduction::floor: {
        const double x = std::fmod(v, a);
        const double y = x < 0 ? x + a : x;
        return y >= a ? 0.0 : y;
    }
    case Reduction::none:
    case Reduction::hexagonal: return v; // (reduce_xy: x and y together)
    }
    return v;
}

// Exact reduction of float lanes through double (see above); the caller guarantees |x| is
// below the fast bound or not finite.
template <Reduction R>
inline void reduce_fast(float* __restrict x, std::size_t n) {
    const double a = double(period<float>), inv = 1.0 / a, half = a / 2;
    for (std::size_t i = 0; i < n; ++i) {
        const double v = double(x[i]);
        double r;
        if constexpr (R == Reduction::fmod) {
            r = v - std::trunc(v * inv) * a;
            r = (v >= 0 && r < 0) ? r + a : r;
            r = (v < 0 && r > 0) ? r - a : r;
            r = r >= a ? r - a : r;
            r = r <= -a ? r + a : r;
        } else if constexpr (R == Reduction::centred) {
            r = v - std::nearbyint(v * inv) * a;
            r = r >= half ? r - a : r;
            r = r < -half ? r + a : r;
        } else {
            r = v - std::floor(v * inv) * a;
            r = r < 0 ? r + a : r;
            r = r >= a ? r - a : r;
        }
        // Exact for fmod and centred; floor's a - tiny can round up to a, which is 0 mod a.
        const float f = float(r);
        x[i] = f >= period<float> ? 0.0f : f;
    }
}

} // namespace detail

/// The target range of a reduction as lo <= v < hi, in T (fmod's open lower end -a as the next
/// value above it); values in it stay as they are (exactly: see above). none: everything;
/// hexagonal: not a box (in_cell), everything here.
template <class T>
struct Range {
    T lo, hi;
    explicit Range(Reduction r) {
        const T a = period<T>;
        lo = r == Reduction::fmod      ? std::nextafter(-a, T(0))
             : r == Reduction::centred ? -a / 2
             : r == Reduction::floor   ? T(0)
                                       : -std::numeric_limits<T>::infinity();
        hi = r == Reduction::centred                             ? a / 2
             : r == Reduction::none || r == Reduction::hexagonal ? std::numeric_limits<T>::infinity()
                                                                 : a;
    }
};

/// x[i] <- x[i] reduced, for i < n. Returns whether some value was outside the target range
/// (false: nothing changed; the renderer then checks the range inline for the next step).
inline bool reduce(float* x, std::size_t n, Reduction r) {
    if (r == Reduction::none || r == Reduction::hexagonal) return false;
    constexpr float bound = float(1 << 28) * period<float>;
    // One scan (integer sums, so that it vectorises): values already in the target range stay as
    // they are under every reduction (exactly: see above), which is the common case after a map
    // that reduces itself (Picard); values too large for the fast path take the library.
    const Range<float> range(r);
    const float lo = range.lo, hi = range.hi;
    unsigned big = 0, outside = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const float v = x[i];
        big += unsigned(std::fabs(v) >= bound);
        outside += unsigned(!((v >= lo) & (v < hi))); // NaN: outside
    }
    if (outside == 0) return false;
    if (big) {
        for (std::size_t i = 0; i < n; ++i) x[i] = detail::reduce_scalar(x[i], r);
        return true;
    }
    switch (r) {
    case Reduction::fmod: detail::reduce_fast<Reduction::fmod>(x, n); break;
    case Reduction::centred: detail::reduce_fast<Reduction::centred>(x, n); break;
    case Reduction::floor: detail::reduce_fast<Reduction::floor>(x, n); break;
    case Reduction::none:
    case Reduction::hexagonal: break;
    }
    return true;
}

inline bool reduce(double* x, std::size_t n, Reduction r) {
    if (r == Reduction::none || r == Reduction::hexagonal) return false;
    for (std::size_t i = 0; i < n; ++i) x[i] = detail::reduce_scalar(x[i], r);
    return true; // not scanned: double lanes are never checked inline
}

/// Points (x[i], y[i]) reduced, i < n: hexagonal reduces each point as a whole, the others each
/// coordinate. Returns whether some point was outside the target range (false: nothing changed).
/// Hexagonal scans first, as reduce(float*) does (one vectorised pass counting points outside
/// the hexagon), then reduces every point (those inside are selected unchanged), in float and
/// double alike.
template <class T>
inline bool reduce_xy(T* __restrict x, T* __restrict y, std::size_t n, Reduction r) {
    if (r != Reduction::hexagonal) {
        const bool ox = reduce(x, n, r);
        const bool oy = reduce(y, n, r);
        return ox || oy;
    }
    unsigned outside = 0;
    for (std::size_t i = 0; i < n; ++i) outside += unsigned(!fp::kernels::in_cell(x[i], y[i]));
    if (outside == 0) return false;
    for (std::size_t i = 0; i < n; ++i) {
        T a = x[i], b = y[i];
        fp::kernels::reduce_hexagonal(a, b);
        x[i] = a, y[i] = b;
    }
    return true;
}

} // namespace fp_orbit_trap
