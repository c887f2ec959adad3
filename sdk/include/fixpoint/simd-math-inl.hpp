// Transcendental functions on double lanes for kernels that need them (superformula's polar
// radius, for one), written for the SIMD layer's promise: the same bits on every target.
//
// libm cannot be called per lane, and Highway's own contrib/math uses MulAdd, which fuses on
// targets with FMA and rounds twice on the others. These use +, -, *, /, comparisons,
// rounding to an integer and exponent bit manipulation only: all exact IEEE operations, so a
// lane's result does not depend on the target or on its neighbours. The polynomials are the
// classical Cephes ones (S. L. Moshier, "Methods and Programs for Mathematical Functions",
// 1989), evaluated by Horner's rule; tests/unit/test_simd_math.cpp measures them against
// libm (a few ulps at most in the ranges they are documented for) on every target.
//
// Special values follow C's: NaN propagates; log(0) = -inf, log(x < 0) = NaN, log(inf) = inf;
// exp overflows to inf and underflows through the subnormals to 0; atan2 handles signed
// zeros and both arguments zero (not infinite arguments: the result is then NaN).

// Per-target include guard (Highway's convention).
#if defined(FIXPOINT_SIMD_MATH_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef FIXPOINT_SIMD_MATH_INL_HPP_
#undef FIXPOINT_SIMD_MATH_INL_HPP_
#else
#define FIXPOINT_SIMD_MATH_INL_HPP_
#endif

#include <hwy/highway.h>

#include <cstdint>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace fp::simd::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace math_detail {

/// c[0] x^(n-1) + ... + c[n-1], by Horner's rule (no fused multiply-add).
template <class D, std::size_t N>
HWY_INLINE hn::Vec<D> horner(D d, hn::Vec<D> x, const double (&c)[N]) {
    auto y = hn::Set(d, c[0]);
    for (std::size_t i = 1; i < N; ++i) y = hn::Add(hn::Mul(y, x), hn::Set(d, c[i]));
    return y;
}

/// x^n + c[0] x^(n-1) + ... + c[n-1]: Horner with an implied leading 1.
template <class D, std::size_t N>
HWY_INLINE hn::Vec<D> horner1(D d, hn::Vec<D> x, const double (&c)[N]) {
    auto y = hn::Add(x, hn::Set(d, c[0]));
    for (std::size_t i = 1; i < N; ++i) y = hn::Add(hn::Mul(y, x), hn::Set(d, c[i]));
    return y;
}

/// 2^n for integral n in [-1022, 1023] (as doubles), by building the exponent field.
template <class D>
HWY_INLINE hn::Vec<D> pow2i(D d, hn::Vec<D> n) {
    const hn::RebindToSigned<D> di;
    const auto e = hn::Add(hn::ConvertTo(di, n), hn::Set(di, 1023));
    return hn::BitCast(d, hn::ShiftLeft<52>(e));
}

} // namespace math_detail

/// NaN lanes. (Not hn::Ne(x, x): Highway's Ne is the ordered comparison on some x86 targets
/// and the unordered one on others, so it disagrees about NaN.)
template <class V>
HWY_INLINE auto is_nan(V x) {
    return hn::Not(hn::Eq(x, x));
}

/// sin(x) and cos(x) at once, for |x| up to about 1e6 (Cody-Waite reduction by pi/2 in three
/// parts; beyond, the reduction loses bits like any three-part one).
template <class D>
HWY_INLINE void sin_cos(D d, hn::Vec<D> x, hn::Vec<D>& s, hn::Vec<D>& c) {
    static_assert(sizeof(hn::TFromD<D>) == 8, "double lanes");
    // pi/2 = P1 + P2 + P3: P1 and P2 have trailing zero bits, so k P1 and k P2 are exact.
    constexpr double two_over_pi = 0.63661977236758134308;
    constexpr double P1 = 1.57079625129699707031e+00, P2 = 7.54978941586159635335e-08,
                     P3 = 5.39030285815811905290e-15;
    constexpr double sin_c[] = {1.58962301576546568060e-10, -2.50507477628578072866e-8,
                                2.75573136213857245213e-6,  -1.98412698295895385996e-4,
                                8.33333333332211858878e-3,  -1.66666666666666307295e-1};
    constexpr double cos_c[] = {-1.13585365213876817300e-11, 2.08757008419747316778e-9,
                                -2.75573141792967388112e-7,  2.48015872888517045348e-5,
                                -1.38888888888730564116e-3,  4.16666666666665929218e-2};
    const auto k = hn::Round(hn::Mul(x, hn::Set(d, two_over_pi))); // nearest, ties to even
    auto r = hn::Sub(x, hn::Mul(k, hn::Set(d, P1)));
    r = hn::Sub(r, hn::Mul(k, hn::Set(d, P2)));
    r = hn::Sub(r, hn::Mul(k, hn::Set(d, P3))); // |r| <= pi/4 (a little more after rounding)
    const auto z = hn::Mul(r, r);
    const auto sr = hn::Add(r, hn::Mul(hn::Mul(r, z), math_detail::horner(d, z, sin_c)));
    const auto cr = hn::Add(hn::Sub(hn::Set(d, 1.0), hn::Mul(hn::Set(d, 0.5), z)),
                            hn::Mul(hn::Mul(z, z), math_detail::horner(d, z, cos_c)));
    // Quadrant q = k mod 4: sin x = (sr, cr, -sr, -cr)[q], cos x = (cr, -sr, -cr, sr)[q].
    // (k converted only where it is an integer well inside int64's range: a NaN or infinite
    // one, whose r is NaN anyway, takes 0; converting it would be undefined behaviour on the
    // emulated targets.)
    const hn::RebindToSigned<D> di;
    const auto q = hn::ConvertTo(di, hn::IfThenElseZero(hn::Lt(hn::Abs(k), hn::Set(d, 1e15)), k));
    const auto one = hn::Set(di, 1), two = hn::Set(di, 2);
    const auto odd = hn::RebindMask(d, hn::Eq(hn::And(q, one), one));
    const auto s_neg = hn::RebindMask(d, hn::Eq(hn::And(q, two), two));
    const auto c_neg = hn::RebindMask(d, hn::Eq(hn::And(hn::Add(q, one), two), two));
    const auto ss = hn::IfThenElse(odd, cr, sr), cc = hn::IfThenElse(odd, sr, cr);
    s = hn::IfThenElse(s_neg, hn::Neg(ss), ss);
    c = hn::IfThenElse(c_neg, hn::Neg(cc), cc);
}

/// atan2(y, x) in [-pi, pi], signed zeros as in C.
template <class D>
HWY_INLINE hn::Vec<D> atan2(D d, hn::Vec<D> y, hn::Vec<D> x) {
    static_assert(sizeof(hn::TFromD<D>) == 8, "double lanes");
    constexpr double P[] = {-8.750608600031904122785e-1, -1.615753718733365076637e1,
                            -7.500855792314704667340e1, -1.228866684490136173410e2,
                            -6.485021904942025371773e1};
    constexpr double Q[] = {2.485846490142306297962e1, 1.650270098316988542046e2, 4.328810604912902668951e2,
                            4.853903996359136964868e2, 1.945506571482613964425e2};
    constexpr double pi = 3.14159265358979323846, pi_2 = 1.57079632679489661923,
                     pi_4 = 0.78539816339744830962, more_bits = 6.123233995736765886130e-17;
    const auto zero = hn::Zero(d);
    const auto ax = hn::Abs(x), ay = hn::Abs(y);
    const auto big = hn::Max(ax, ay), small = hn::Min(ax, ay);
    // z = small / big in [0, 1] (0 when both are zero); above 0.66, atan z = pi/4 + atan t
    // with t = (z - 1) / (z + 1) in (-0.21, 0].
    const auto z = hn::IfThenElseZero(hn::Gt(big, zero), hn::Div(small, big));
    const auto far = hn::Gt(z, hn::Set(d, 0.66));
    const auto one = hn::Set(d, 1.0);
    const auto t = hn::IfThenElse(far, hn::Div(hn::Sub(z, one), hn::Add(z, one)), z);
    const auto t2 = hn::Mul(t, t);
    const auto p = hn::Div(hn::Mul(t2, math_detail::horner(d, t2, P)), math_detail::horner1(d, t2, Q));
    auto a = hn::Add(hn::Mul(t, p), t);
    a = hn::IfThenElse(far, hn::Add(hn::Set(d, pi_4), hn::Add(a, hn::Set(d, 0.5 * more_bits))), a);
    // Back from the octant: swap of x and y, then the left half-plane, then the sign of y.
    a = hn::IfThenElse(hn::Gt(ay, ax), hn::Sub(hn::Set(d, pi_2), a), a);
    a = hn::IfThenElse(hn::Lt(x, zero), hn::Sub(hn::Set(d, pi), a), a);
    // x = -0 counts as the left half-plane too (atan2(0, -0) = pi).
    const hn::RebindToSigned<D> di;
    const auto x_neg_zero =
        hn::And(hn::Eq(x, zero), hn::RebindMask(d, hn::Lt(hn::BitCast(di, x), hn::Zero(di))));
    a = hn::IfThenElse(x_neg_zero, hn::Set(d, pi), a);
    return hn::CopySign(a, y);
}

/// Natural logarithm.
template <class D>
HWY_INLINE hn::Vec<D> log(D d, hn::Vec<D> x) {
    static_assert(sizeof(hn::TFromD<D>) == 8, "double lanes");
    constexpr double P[] = {1.01875663804580931796e-4, 4.97494994976747001425e-1, 4.70579119878881725854e0,
                            1.44989225341610930846e1,  1.79368678507819816313e1,  7.70838733755885391666e0};
    constexpr double Q[] = {1.12873587189167450590e1, 4.52279145837532221105e1, 8.29875266912776603211e1,
                            7.11544750618563894466e1, 2.31251620126765340583e1};
    constexpr double ln2_hi = 6.93359375e-1, ln2_lo = -2.121944400546905827679e-4,
                     sqrt_half = 0.70710678118654752440;
    const hn::RebindToSigned<D> di;
    const auto zero = hn::Zero(d);
    // Subnormals: scale by 2^54 first, so the exponent field below is the true one.
    const auto tiny = hn::Lt(x, hn::Set(d, 2.2250738585072014e-308));
    const auto xs = hn::IfThenElse(tiny, hn::Mul(x, hn::Set(d, 18014398509481984.0)), x);
    // x = m 2^e with m in [0.5, 1).
    const auto bits = hn::BitCast(di, xs);
    const auto e_field = hn::And(hn::ShiftRight<52>(bits), hn::Set(di, 0x7ff));
    auto e = hn::ConvertTo(d, hn::Sub(e_field, hn::Set(di, 1022)));
    e = hn::IfThenElse(tiny, hn::Sub(e, hn::Set(d, 54.0)), e);
    const auto mant = hn::Or(hn::And(bits, hn::Set(di, std::int64_t(0x000fffffffffffff))),
                             hn::Set(di, std::int64_t(0x3fe0000000000000)));
    auto m = hn::BitCast(d, mant);
    // m in [sqrt(1/2), sqrt(2)) around 1: below sqrt(1/2), double it and lower e.
    const auto low = hn::Lt(m, hn::Set(d, sqrt_half));
    e = hn::IfThenElse(low, hn::Sub(e, hn::Set(d, 1.0)), e);
    const auto one = hn::Set(d, 1.0);
    m = hn::IfThenElse(low, hn::Sub(hn::Add(m, m), one), hn::Sub(m, one));
    const auto z = hn::Mul(m, m);
    auto y = hn::Div(hn::Mul(m, hn::Mul(z, math_detail::horner(d, m, P))), math_detail::horner1(d, m, Q));
    y = hn::Add(y, hn::Mul(e, hn::Set(d, ln2_lo)));
    y = hn::Sub(y, hn::Mul(hn::Set(d, 0.5), z));
    auto r = hn::Add(hn::Add(m, y), hn::Mul(e, hn::Set(d, ln2_hi)));
    // Special values: 0 -> -inf, negative -> NaN, +inf -> +inf; NaN propagates from m.
    const auto inf = hn::Set(d, std::numeric_limits<double>::infinity());
    r = hn::IfThenElse(hn::Eq(x, zero), hn::Neg(inf), r);
    r = hn::IfThenElse(hn::Lt(x, zero), hn::Set(d, std::numeric_limits<double>::quiet_NaN()), r);
    r = hn::IfThenElse(hn::Eq(x, inf), inf, r);
    return hn::IfThenElse(is_nan(x), x, r);
}

/// Exponential.
template <class D>
HWY_INLINE hn::Vec<D> exp(D d, hn::Vec<D> x) {
    static_assert(sizeof(hn::TFromD<D>) == 8, "double lanes");
    constexpr double P[] = {1.26177193074810590878e-4, 3.02994407707441961300e-2, 9.99999999999999999910e-1};
    constexpr double Q[] = {3.00198505138664455042e-6, 2.52448340349684104192e-3, 2.27265548208155028766e-1,
                            2.00000000000000000009e0};
    constexpr double log2e = 1.4426950408889634073599, c1 = 6.93145751953125e-1,
                     c2 = 1.42860682030941723212e-6;
    constexpr double max_log = 7.09782712893383996843e2, min_log = -7.451332191019412076235e2;
    // Clamp first, so that n below stays in range (and NaN to 0: converting a NaN n to an
    // integer would be undefined behaviour on the emulated targets); the ends and NaN are
    // replaced at the bottom.
    const auto xc =
        hn::Min(hn::Max(hn::IfThenZeroElse(is_nan(x), x), hn::Set(d, min_log)), hn::Set(d, max_log));
    const auto n = hn::Floor(hn::Add(hn::Mul(xc, hn::Set(d, log2e)), hn::Set(d, 0.5)));
    auto r = hn::Sub(xc, hn::Mul(n, hn::Set(d, c1)));
    r = hn::Sub(r, hn::Mul(n, hn::Set(d, c2))); // |r| <= ln(2) / 2
    const auto r2 = hn::Mul(r, r);
    const auto p = hn::Mul(r, math_detail::horner(d, r2, P));
    auto y = hn::Div(p, hn::Sub(math_detail::horner(d, r2, Q), p));
    y = hn::Add(hn::Set(d, 1.0), hn::Add(y, y));
    // y 2^n in two steps (n from -1075 to 1024): each factor a normal power of two, so only
    // the last product rounds, and subnormal results come out right.
    const auto half = hn::Floor(hn::Mul(n, hn::Set(d, 0.5)));
    y = hn::Mul(hn::Mul(y, math_detail::pow2i(d, half)), math_detail::pow2i(d, hn::Sub(n, half)));
    y = hn::IfThenElse(hn::Gt(x, hn::Set(d, max_log)), hn::Set(d, std::numeric_limits<double>::infinity()),
                       y);
    y = hn::IfThenElseZero(hn::Not(hn::Lt(x, hn::Set(d, min_log))), y);
    return hn::IfThenElse(is_nan(x), x, y);
}

/// x^y for x >= 0 (a magnitude): exp(y log x), with pow's values where that formula has
/// none: x^0 = 1 (0^0 and NaN^0 included), 0^y = 0 for y > 0 and inf for y < 0.
template <class D>
HWY_INLINE hn::Vec<D> pow_abs(D d, hn::Vec<D> x, hn::Vec<D> y) {
    const auto r = exp(d, hn::Mul(y, log(d, x)));
    return hn::IfThenElse(hn::Eq(y, hn::Zero(d)), hn::Set(d, 1.0), r);
}

} // namespace fp::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif // per-target guard
