// What the curved shapes' kernels (superformula, bezier) share, per SIMD target: batches run
// in double lanes whatever their type, and a root finder one lane at a time.
//
// The root finder, for a ray exit (superformula, bezier) or a crossing (bezier's inside
// test) at the root of a function on a bracket: bisection accelerated by the
// Illinois variant of regula falsi. Every step keeps a bracket [lo, hi] with f(lo) < 0 <=
// f(hi), and a step that fails to halve it over two steps is followed by a plain bisection
// step, so it is never much slower than bisection. A lane stops at an exact zero of f or when
// the bracket is within `rel` of |hi| (the caller's precision); a stopped lane is frozen
// (masks), so each lane takes exactly the steps the scalar method would, whatever the lane
// count, and the loop ends when every lane has stopped.

// Per-target include guard (Highway's convention).
#if defined(FIXPOINT_SHAPES_LANES_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef FIXPOINT_SHAPES_LANES_INL_HPP_
#undef FIXPOINT_SHAPES_LANES_INL_HPP_
#else
#define FIXPOINT_SHAPES_LANES_INL_HPP_
#endif

#include <fixpoint/simd-math-inl.hpp>

#include <algorithm>
#include <cstddef>

HWY_BEFORE_NAMESPACE();
namespace fp_shapes::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

/// Runs body(x, y) on blocks of at most Lanes(d) points converted to double lanes (a padded
/// copy: the kernels are dominated by their arithmetic, not by the loads), and writes back
/// what body returns, converted to the output's type (rounded to float; 0 or 1 to bytes).
template <class D, class T, class Out, class F>
HWY_INLINE void blocks(D d, fp::Points<const T> p, Out* out, F&& body) {
    const std::size_t N = hn::Lanes(d);
    alignas(HWY_MAX_BYTES) double bx[HWY_MAX_BYTES / 8] = {}, by[HWY_MAX_BYTES / 8] = {};
    alignas(HWY_MAX_BYTES) double br[HWY_MAX_BYTES / 8];
    for (std::size_t i = 0; i < p.n; i += N) {
        const std::size_t m = std::min(N, p.n - i);
        for (std::size_t k = 0; k < m; ++k) bx[k] = double(p.x[i + k]), by[k] = double(p.y[i + k]);
        hn::Store(body(hn::Load(d, bx), hn::Load(d, by)), d, br);
        for (std::size_t k = 0; k < m; ++k) out[i + k] = Out(br[k]);
    }
}

/// The root of f in [lo, hi] for the lanes of `active` (f(lo) = flo < 0 <= fhi = f(hi)), at
/// most `steps` steps: an exact zero where one was met (`found` set), else the final hi.
/// Lanes not active return hi unchanged.
template <class D, class F>
HWY_INLINE hn::Vec<D> illinois(D d, hn::Vec<D> lo, hn::Vec<D> hi, hn::Vec<D> flo, hn::Vec<D> fhi,
                               hn::Mask<D> active, hn::Vec<D> rel, int steps, F&& f, hn::Mask<D>& found) {
    namespace fs = fp::simd::HWY_NAMESPACE;
    const auto zero = hn::Zero(d), two = hn::Set(d, 2.0);
    const auto one = hn::Set(d, 1.0), minus_one = hn::Set(d, -1.0);
    auto side = zero;                 // -1: lo moved last, 1: hi moved last, 0: neither yet
    auto bisect = hn::Lt(zero, zero); // all false
    auto width_before = hn::Sub(hi, lo);
    found = bisect;
    auto root = zero;
    for (int k = 0; k < steps; ++k) {
        const auto width = hn::Sub(hi, lo);
        active = hn::And(active, hn::Gt(width, hn::Mul(rel, hi)));
        const auto half = hn::Add(lo, hn::Div(width, two));
        auto x = hn::IfThenElse(bisect, half, hn::Add(lo, hn::Mul(width, hn::Div(flo, hn::Sub(flo, fhi)))));
        // At least half the tolerance away from both ends (std::clamp's semantics).
        const auto delta = hn::Div(hn::Mul(rel, hi), two);
        const auto a = hn::Add(lo, delta), b = hn::Sub(hi, delta);
        const auto clamped = hn::IfThenElse(hn::Lt(x, a), a, hn::IfThenElse(hn::Lt(b, x), b, x));
        const auto within = hn::And(hn::Gt(x, a), hn::Lt(x, b));
        x = hn::IfThenElse(within, x, hn::IfThenElse(fs::is_nan(x), half, clamped));
        active = hn::And(active, hn::And(hn::Gt(x, lo), hn::Lt(x, hi))); // else lo, hi adjacent
        if (hn::AllFalse(d, active)) break;
        const auto fx = f(x);
        const auto hit = hn::And(active, hn::Eq(fx, zero));
        root = hn::IfThenElse(hit, x, root);
        found = hn::Or(found, hit);
        active = hn::AndNot(hit, active);
        const auto below = hn::Lt(fx, zero);
        const auto neg = hn::And(active, below), pos = hn::AndNot(below, active);
        const auto halve_hi = hn::And(neg, hn::Lt(side, zero)), halve_lo = hn::And(pos, hn::Gt(side, zero));
        lo = hn::IfThenElse(neg, x, lo);
        hi = hn::IfThenElse(pos, x, hi);
        flo = hn::IfThenElse(neg, fx, hn::IfThenElse(halve_lo, hn::Div(flo, two), flo));
        fhi = hn::IfThenElse(pos, fx, hn::IfThenElse(halve_hi, hn::Div(fhi, two), fhi));
        side = hn::IfThenElse(neg, minus_one, hn::IfThenElse(pos, one, side));
        if (k % 2 == 1) {
            const auto w = hn::Sub(hi, lo);
            bisect =
                hn::Or(hn::And(active, hn::Gt(w, hn::Div(width_before, two))), hn::AndNot(active, bisect));
            width_before = hn::IfThenElse(active, w, width_before);
        } else {
            bisect = hn::AndNot(active, bisect);
        }
    }
    return hn::IfThenElse(found, root, hi);
}

} // namespace fp_shapes::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif // per-target guard
