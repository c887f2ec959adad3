// The bezier set's kernels on the SIMD layer (bezier.cpp's header: the pieces, the crossing
// count, the ray's piece and its root), compiled once per instruction set of the build and
// dispatched at run time: the functions bezier/curve.hpp declares. Everything is in double
// (float batches are converted on the way in and rounded on the way out), one point or
// direction per lane; the root finder stops at the precision of the batch's type.
#include "bezier/curve.hpp"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "bezier/kernels.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "shapes/lanes-inl.hpp"
#include <fixpoint/simd-math-inl.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace fp_bezier::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;

/// c0 + c1 t + c2 t^2 + c3 t^3 by Horner's rule (no FMA: the scalar setup's operations).
HWY_INLINE V horner(V c0, V c1, V c2, V c3, V t) {
    return hn::Add(hn::Mul(hn::Add(hn::Mul(hn::Add(hn::Mul(c3, t), c2), t), c1), t), c0);
}

using fp_shapes::HWY_NAMESPACE::blocks;

/// The piece of r whose sector holds the direction (x, y): a branch-free binary search over
/// the pieces' start pseudo-angles, by gathers; below the first start is the last piece,
/// which wraps round (and so is a zero or NaN direction's).
HWY_INLINE hn::Vec<hn::RebindToSigned<D>> piece_of(D d, const RayPieces& r, V x, V y) {
    const hn::RebindToSigned<D> di;
    const auto zero = hn::Zero(d), two = hn::Set(d, 2.0);
    const auto s = hn::Div(y, hn::Add(hn::Abs(x), hn::Abs(y)));
    const auto key = hn::IfThenElse(
        hn::Ge(x, zero), s, hn::IfThenElse(hn::Ge(y, zero), hn::Sub(two, s), hn::Sub(hn::Neg(two), s)));
    auto pos = hn::Zero(di); // the number of start keys <= key (NaN: none)
    for (std::size_t step = r.n2 / 2; step >= 1; step /= 2) {
        const auto cand = hn::Add(pos, hn::Set(di, std::int64_t(step)));
        const auto k = hn::GatherIndex(d, r.key.data(), hn::Sub(cand, hn::Set(di, 1)));
        pos = hn::IfThenElse(hn::RebindMask(di, hn::Le(k, key)), cand, pos);
    }
    const auto j = hn::IfThenElse(hn::Eq(pos, hn::Zero(di)), hn::Set(di, std::int64_t(r.n)), pos);
    return hn::Sub(j, hn::Set(di, 1));
}

/// The winding number of the curve about each point, by signed crossings of the ray to +x
/// (half-open in y, so that a row through a piece's end counts once): a piece whose y-range
/// holds the row is crossed left of the point when the point lies left of its control hull,
/// never when right of it, and otherwise where x(t*) > px at the root t* of y(t*) = py, which
/// is unique on the piece (y is monotonic there). 1 inside, 0 outside.
template <class T>
HWY_INLINE V winding(D d, const YPieces& c, V x, V y) {
    const auto zero = hn::Zero(d);
    const auto px = hn::Sub(x, hn::Set(d, c.ref.x)), py = hn::Sub(y, hn::Set(d, c.ref.y));
    const auto in_box =
        hn::And(hn::And(hn::Ge(px, hn::Set(d, c.box.xmin)), hn::Le(px, hn::Set(d, c.box.xmax))),
                hn::And(hn::Ge(py, hn::Set(d, c.box.ymin)), hn::Le(py, hn::Set(d, c.box.ymax))));
    auto w = zero;
    if (hn::AllFalse(d, in_box)) return w;
    const auto rel = hn::Set(d, 4 * double(std::numeric_limits<T>::epsilon()));
    for (std::size_t i = 0; i < c.n; ++i) {
        const double y0 = c.y0[i], y1 = c.y1[i];
        const auto straddle =
            hn::And(in_box, hn::Xor(hn::Gt(hn::Set(d, y0), py), hn::Gt(hn::Set(d, y1), py)));
        if (hn::AllFalse(d, straddle)) continue;
        auto crossed = hn::And(straddle, hn::Lt(px, hn::Set(d, c.xlo[i])));
        const auto open = hn::AndNot(crossed, hn::And(straddle, hn::Lt(px, hn::Set(d, c.xhi[i]))));
        if (!hn::AllFalse(d, open)) {
            const Poly& q = c.poly[i];
            const bool up = y1 > y0;
            // f(t) = +-(y(t) - py), negative at t0 and non-negative at t1.
            const auto s = hn::Set(d, up ? 1.0 : -1.0);
            const auto cy0 = hn::Set(d, q.y[0]), cy1 = hn::Set(d, q.y[1]), cy2 = hn::Set(d, q.y[2]),
                       cy3 = hn::Set(d, q.y[3]);
            auto f = [&](V t) { return hn::Mul(s, hn::Sub(horner(cy0, cy1, cy2, cy3, t), py)); };
            const auto flo = hn::Mul(s, hn::Sub(hn::Set(d, y0), py)),
                       fhi = hn::Mul(s, hn::Sub(hn::Set(d, y1), py));
            hn::Mask<D> found;
            const auto t =
                fp_shapes::HWY_NAMESPACE::illinois(d, hn::Set(d, c.t0[i]), hn::Set(d, c.t1[i]), flo, fhi,
                                                   open, rel, 4 * std::numeric_limits<T>::digits, f, found);
            const auto xs =
                horner(hn::Set(d, q.x[0]), hn::Set(d, q.x[1]), hn::Set(d, q.x[2]), hn::Set(d, q.x[3]), t);
            crossed = hn::Or(crossed, hn::And(open, hn::Lt(px, xs)));
        }
        w = hn::Add(w, hn::IfThenElseZero(crossed, hn::Set(d, y1 > y0 ? 1.0 : -1.0)));
    }
    return w;
}

/// Inside: the distance bounds of the point's sector about the centre first, and the winding
/// number for the vectors where a lane is left open, between its sector's bounds: the same
/// answers, for most points without a piece.
template <class T>
void inside_t(const YPieces& c, fp::Points<const T> p, unsigned char* out) {
    const D d;
    const hn::RebindToSigned<D> di;
    const auto zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
    const auto cx = hn::Set(d, c.ref.x + c.c.x), cy = hn::Set(d, c.ref.y + c.c.y);
    blocks(d, p, out, [&](V x, V y) {
        if (c.sectors.empty()) return hn::IfThenElseZero(hn::Ne(winding<T>(d, c, x, y), zero), one);
        const auto px = hn::Sub(x, hn::Set(d, c.ref.x)), py = hn::Sub(y, hn::Set(d, c.ref.y));
        const auto in_box =
            hn::And(hn::And(hn::Ge(px, hn::Set(d, c.box.xmin)), hn::Le(px, hn::Set(d, c.box.xmax))),
                    hn::And(hn::Ge(py, hn::Set(d, c.box.ymin)), hn::Le(py, hn::Set(d, c.box.ymax))));
        if (hn::AllFalse(d, in_box)) return zero;
        const auto qx = hn::Sub(x, cx), qy = hn::Sub(y, cy);
        const auto q2 = hn::Add(hn::Mul(qx, qx), hn::Mul(qy, qy));
        // The sector: the pseudo-angle (curve.hpp) in sector_count equal steps; NaN (the centre
        // itself) in sector 0, whose in2 holds it.
        const auto s = hn::Div(qy, hn::Add(hn::Abs(qx), hn::Abs(qy)));
        const auto a = hn::IfThenElse(
            hn::Ge(qx, zero), s, hn::IfThenElse(hn::Ge(qy, zero), hn::Sub(two, s), hn::Sub(hn::Neg(two), s)));
        const auto f = hn::Mul(hn::Add(a, two), hn::Set(d, double(sector_count) / 4));
        const auto fc = hn::IfThenElseZero(hn::Gt(f, zero), hn::Min(f, hn::Set(d, double(sector_count - 1))));
        const auto i2 = hn::ShiftLeft<1>(hn::ConvertTo(di, fc));
        const auto in = hn::Lt(q2, hn::GatherIndex(d, c.sectors.data(), i2));
        const auto open =
            hn::AndNot(hn::Or(in, hn::Ge(q2, hn::GatherIndex(d, c.sectors.data() + 1, i2))), in_box);
        if (hn::AllFalse(d, open)) return hn::IfThenElseZero(in, one);
        const auto w = hn::Ne(winding<T>(d, c, x, y), zero);
        return hn::IfThenElseZero(hn::Or(hn::And(open, w), hn::AndNot(open, in)), one);
    });
}
void inside_f(const YPieces& c, fp::Points<const float> p, unsigned char* out) { inside_t(c, p, out); }
void inside_d(const YPieces& c, fp::Points<const double> p, unsigned char* out) { inside_t(c, p, out); }

/// The exit along d: the piece whose sector holds d (piece_of), then the root of h(t) = cross(d, b(t) - o) on
/// the piece, where h goes from <= 0 to >= 0 once. A root at an end (h(t0) >= 0 or h(t1) <= 0: only within
/// rounding of a piece's end) is taken as that end. t = (b(t*) - o) . d / |d|^2.
template <class T>
HWY_INLINE V exit_along(D d, const RayPieces& r, V dx, V dy) {
    const auto zero = hn::Zero(d);
    const auto dd = hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy));
    const auto ok = hn::Gt(dd, zero);
    const auto idx = piece_of(d, r, dx, dy);
    const auto g = [&](const std::vector<double>& v) { return hn::GatherIndex(d, v.data(), idx); };
    const auto cx0 = g(r.cx[0]), cx1 = g(r.cx[1]), cx2 = g(r.cx[2]), cx3 = g(r.cx[3]);
    const auto cy0 = g(r.cy[0]), cy1 = g(r.cy[1]), cy2 = g(r.cy[2]), cy3 = g(r.cy[3]);
    // h's coefficients: cross(d, c_k) = dx cy_k - dy cx_k.
    const auto h = [&](V a, V b) { return hn::Sub(hn::Mul(dx, b), hn::Mul(dy, a)); };
    const auto h0 = h(cx0, cy0), h1 = h(cx1, cy1), h2 = h(cx2, cy2), h3 = h(cx3, cy3);
    const auto f = [&](V t) { return horner(h0, h1, h2, h3, t); };
    const auto t0 = g(r.t0), t1 = g(r.t1);
    const auto f0 = f(t0), f1 = f(t1);
    const auto at0 = hn::Ge(f0, zero), at1 = hn::AndNot(at0, hn::Le(f1, zero));
    const auto open = hn::AndNot(hn::Or(at0, at1), ok);
    hn::Mask<D> found;
    const auto rel = hn::Set(d, 4 * double(std::numeric_limits<T>::epsilon()));
    auto t = fp_shapes::HWY_NAMESPACE::illinois(d, t0, t1, f0, f1, open, rel,
                                                4 * std::numeric_limits<T>::digits, f, found);
    t = hn::IfThenElse(at0, t0, hn::IfThenElse(at1, t1, t));
    const auto qx = horner(cx0, cx1, cx2, cx3, t), qy = horner(cy0, cy1, cy2, cy3, t);
    const auto exit_t = hn::Div(hn::Add(hn::Mul(qx, dx), hn::Mul(qy, dy)), dd);
    return hn::IfThenElse(ok, exit_t, hn::Set(d, std::numeric_limits<double>::infinity()));
}

template <class T>
void ray_t(const RayPieces& r, fp::Points<const T> dir, T* t) {
    const D d;
    blocks(d, dir, t, [&](V dx, V dy) { return exit_along<T>(d, r, dx, dy); });
}
void ray_f(const RayPieces& r, fp::Points<const float> d, float* t) { ray_t(r, d, t); }
void ray_d(const RayPieces& r, fp::Points<const double> d, double* t) { ray_t(r, d, t); }

} // namespace fp_bezier::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp_bezier {
HWY_EXPORT(inside_f);
HWY_EXPORT(inside_d);
HWY_EXPORT(ray_f);
HWY_EXPORT(ray_d);

// (HWY_DYNAMIC_DISPATCH names the kernels unqualified: a build with static dispatch only
// resolves them as N_<target>::name from this namespace.)
void inside(const YPieces& c, fp::Points<const float> p, unsigned char* out) {
    HWY_DYNAMIC_DISPATCH(inside_f)(c, p, out);
}
void inside(const YPieces& c, fp::Points<const double> p, unsigned char* out) {
    HWY_DYNAMIC_DISPATCH(inside_d)(c, p, out);
}
void ray(const RayPieces& r, fp::Points<const float> d, float* t) { HWY_DYNAMIC_DISPATCH(ray_f)(r, d, t); }
void ray(const RayPieces& r, fp::Points<const double> d, double* t) { HWY_DYNAMIC_DISPATCH(ray_d)(r, d, t); }
} // namespace fp_bezier
#endif // HWY_ONCE
