// Branch-free sin/cos for the wallpaper transform's hot loop, in float and double (its "mod 2 pi"
// is the SDK's: fixpoint/lattice.hpp).
//
// Why not libm: a call per point blocks vectorisation (the loop of wallpaper.cpp evaluates
// sin and cos of x and y for every point of a 256-point chunk); these inline functions use only
// +, *, fabs, nearbyint, copysign, bit operations (std::bit_cast) and selects, which GCC
// turns into SIMD instructions (vroundps, vpternlogd, vblendmps, ...).
//
// Symmetry, bitwise: the wallpaper maps must commute with x -> -x exactly, so
//   sincos(-x) = (-sin x, cos x) bit for bit (also for x = -0).
// Both are computed from |x|; the sine gets x's sign by an XOR of the sign bit. Nothing else
// depends on the sign of x.
//
// Method (the classical one of Cephes and fdlibm, written from the definitions): q = the
// nearest integer to |x| / (pi / 2) (adding and subtracting 1.5 * 2^23, or 1.5 * 2^52: the low bits
// of the sum are q mod 4); r = |x| - q pi / 2 by Cody-Waite reduction with pi / 2 split in three
// parts (the first parts have few significant bits, so q * part is exact); then minimax
// polynomials for sin and cos on [-pi/4, pi/4] (Cephes' sinf/cosf and sin/cos coefficients);
// the quadrant q mod 4 swaps them and flips sign bits (XOR, as x's sign). Accuracy: about 1-2
// ulp for |x| below 8192 (float) or 2^19 (double); beyond, the reduction loses digits
// gradually; |x| above 2^20 (float) or 2^40 (double) is taken as that bound, so every finite x
// gives values in [-1, 1] (so does inf); NaN gives NaN.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace fp_wallpaper {

template <class T>
struct TrigConst;

template <>
struct TrigConst<float> {
    static constexpr float two_over_pi = 0.636619772367581343f;
    // pi / 2 = p1 + p2 + p3 (Cephes' DP1..DP3 times 2)
    static constexpr float p1 = 1.5703125f, p2 = 4.837512969970703125e-4f, p3 = 7.54978995489188216e-8f;
    static constexpr float s1 = -1.6666654611e-1f, s2 = 8.3321608736e-3f, s3 = -1.9515295891e-4f;
    static constexpr float c1 = 4.166664568298827e-2f, c2 = -1.388731625493765e-3f,
                           c3 = 2.443315711809948e-5f;
    static constexpr float magic = 12582912.0f;  // 1.5 * 2^23
    static constexpr float max_arg = 1048576.0f; // 2^20
};

template <>
struct TrigConst<double> {
    static constexpr double two_over_pi = 0.636619772367581343;
    // pi / 2 in 33 + 33 + rest bits (fdlibm's pio2_1, pio2_2, pio2_2t)
    static constexpr double p1 = 1.57079632673412561417e+00, p2 = 6.07710050630396597660e-11,
                            p3 = 2.02226624879595063154e-21;
    static constexpr double s[6] = {1.58962301576546568060e-10, -2.50507477628578072866e-8,
                                    2.75573136213857245213e-6,  -1.98412698295895385996e-4,
                                    8.33333333332211858878e-3,  -1.66666666666666307295e-1};
    static constexpr double c[6] = {-1.13585365213876817300e-11, 2.08757008419747316778e-9,
                                    -2.75573141792967388112e-7,  2.48015872888517045348e-5,
                                    -1.38888888888730564116e-3,  4.16666666666665929218e-2};
    static constexpr double magic = 6755399441055744.0; // 1.5 * 2^52
    static constexpr double max_arg = 1099511627776.0;  // 2^40
};

/// sin(r) and cos(r) for |r| <= pi / 4 (float: Cephes sinf/cosf polynomials).
[[gnu::always_inline]] inline void sincos_kernel(float r, float& s, float& c) {
    using K = TrigConst<float>;
    const float z = r * r;
    s = r + r * z * (K::s1 + z * (K::s2 + z * K::s3));
    c = (1.0f - 0.5f * z) + z * z * (K::c1 + z * (K::c2 + z * K::c3));
}

/// sin(r) and cos(r) for |r| <= pi / 4 (double: Cephes sin/cos polynomials).
[[gnu::always_inline]] inline void sincos_kernel(double r, double& s, double& c) {
    using K = TrigConst<double>;
    const double z = r * r;
    const double ps = ((((K::s[0] * z + K::s[1]) * z + K::s[2]) * z + K::s[3]) * z + K::s[4]) * z + K::s[5];
    const double pc = ((((K::c[0] * z + K::c[1]) * z + K::c[2]) * z + K::c[3]) * z + K::c[4]) * z + K::c[5];
    s = r + r * z * ps;
    c = (1.0 - 0.5 * z) + z * z * pc;
}

/// Unsigned integer of T's width (for sign-bit and quadrant arithmetic on the bits).
template <class T>
using Bits = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;

/// s = sin x, c = cos x, branch-free; sincos(-x) = (-s, c) bitwise.
template <class T>
[[gnu::always_inline]] inline void sincos(T x, T& s, T& c) {
    using K = TrigConst<T>;
    using U = Bits<T>;
    constexpr U sign_bit = U(1) << (8 * sizeof(T) - 1);
    // |x| beyond max_arg is taken as max_arg (the reduction below would have lost all digits
    // there; this keeps the result finite); NaN stays NaN.
    const T a0 = std::fabs(x), a = a0 > K::max_arg ? K::max_arg : a0;
    // q = round(a 2 / pi) by the 1.5 * 2^mantissa trick: the low bits of t hold q as an integer.
    const T t = a * K::two_over_pi + K::magic;
    const T q = t - K::magic;
    const U qi = std::bit_cast<U>(t);
    T r = a - q * K::p1;
    r = r - q * K::p2;
    r = r - q * K::p3;
    T sp, cp;
    sincos_kernel(r, sp, cp);
    const bool odd = qi & 1;
    const T sv = odd ? cp : sp, cv = odd ? sp : cp;
    // sin is negative in quadrants 2, 3 and takes x's sign; cos is negative in quadrants 1, 2.
    const U s_flip = ((qi & 2) << (8 * sizeof(T) - 2)) ^ (std::bit_cast<U>(x) & sign_bit);
    const U c_flip = ((qi + 1) & 2) << (8 * sizeof(T) - 2);
    s = std::bit_cast<T>(std::bit_cast<U>(sv) ^ s_flip);
    c = std::bit_cast<T>(std::bit_cast<U>(cv) ^ c_flip);
}

} // namespace fp_wallpaper
