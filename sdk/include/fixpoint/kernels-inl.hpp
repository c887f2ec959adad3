// The known kernels' formulas on a target's lanes, written once for the plugins that compute the
// maps (through the SDK's batch functions, fixpoint/kernels.hpp, compiled per target in the SDK
// library) and for the renderers that run them fused (chaos-game, orbit-trap):
//   - inversion in a circle (paper 01, eq. (2)) and eq. (4)'s last step p' = o + t_b^2 (p - o);
//   - the affine map of the plane (paper 02's IFS maps);
//   - the Gumowski-Mira map GM(alpha, mu) (paper 03, eq. (1)),
//         f(u) = mu u + (m2 u u) / (1 + u u),  m2 = 2 (1 - mu), u u computed once,
//         x'   = (y + alpha (1 - (0.05 y) y) y) + f(x),  y' = -x + f(x');
//   - the hexagon's test of the hexagonal lattice reduction (fixpoint/lattice.hpp's in_cell: the
//     same constants and operations, lane-wise).
// fp::KnownKernel promises a renderer these exact operations, in this order, with no FMA: the
// same bits however a map is run. Per-target header (Highway's convention, as
// fixpoint/simd-inl.hpp): include it after hwy/foreach_target.h; V is any Highway vector of float
// or double.

#if defined(FIXPOINT_KERNELS_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef FIXPOINT_KERNELS_INL_HPP_
#undef FIXPOINT_KERNELS_INL_HPP_
#else
#define FIXPOINT_KERNELS_INL_HPP_
#endif

#include <fixpoint/lattice.hpp>

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace fp::kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// ---------------------------------------------------------------- inversion in a circle
/// |d|^2 = dx dx + dy dy.
template <class V>
HWY_INLINE V sq_norm(V dx, V dy) {
    return hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy));
}

/// A point's offset d = p - c from a circle's centre and |d|^2: what the circle's inside test
/// and its inversion share (a renderer that tests the set before it inverts keeps it).
template <class V>
struct Offset {
    V dx, dy, d2;
};

template <class V>
HWY_INLINE Offset<V> offset(V x, V y, V cx, V cy) {
    const V dx = hn::Sub(x, cx), dy = hn::Sub(y, cy);
    return {dx, dy, sq_norm(dx, dy)};
}

/// The disc's inside: |p - c|^2 < r2 (NaN: outside).
template <class V>
HWY_INLINE auto in_circle(const Offset<V>& o, V r2) {
    return hn::Lt(o.d2, r2);
}
template <class V>
HWY_INLINE auto in_circle(V x, V y, V cx, V cy, V r2) {
    return in_circle(offset(x, y, cx, cy), r2);
}

/// The inversion factor about the centre, r2 / |d|^2 (t_b^2 of eq. (4) for a circle about its
/// own centre: no square root, no squaring).
template <class V>
HWY_INLINE V inversion_factor(V d2, V r2) {
    return hn::Div(r2, d2);
}

/// p' = o + s d with d = p - o: eq. (4)'s last step, whatever the factor s.
template <class V>
HWY_INLINE void scale_from(V ox, V oy, V s, V dx, V dy, V& x, V& y) {
    x = hn::Add(ox, hn::Mul(s, dx));
    y = hn::Add(oy, hn::Mul(s, dy));
}
/// The same with d computed here from p.
template <class V>
HWY_INLINE void scale_from(V ox, V oy, V s, V& x, V& y) {
    scale_from(ox, oy, s, hn::Sub(x, ox), hn::Sub(y, oy), x, y);
}

/// Inversion in the circle (c, r2) of the point whose offset is o: p' = c + (r2 / |d|^2) d.
template <class V>
HWY_INLINE void invert_in_circle(const Offset<V>& o, V cx, V cy, V r2, V& x, V& y) {
    scale_from(cx, cy, inversion_factor(o.d2, r2), o.dx, o.dy, x, y);
}
template <class V>
HWY_INLINE void invert_in_circle(V cx, V cy, V r2, V& x, V& y) {
    invert_in_circle(offset(x, y, cx, cy), cx, cy, r2, x, y);
}

// ---------------------------------------------------------------- the affine map
/// (x, y) <- ((a x + b y) + e, (c x + d y) + f) with k = {a, b, c, d, e, f}.
template <class V>
HWY_INLINE void affine(const V (&k)[6], V& x, V& y) {
    const V nx = hn::Add(hn::Add(hn::Mul(k[0], x), hn::Mul(k[1], y)), k[4]);
    const V ny = hn::Add(hn::Add(hn::Mul(k[2], x), hn::Mul(k[3], y)), k[5]);
    x = nx;
    y = ny;
}

// ---------------------------------------------------------------- Gumowski-Mira
/// f(u) = mu u + (m2 u u) / (1 + u u).
template <class V>
HWY_INLINE V gm_f(V mu, V m2, V u) {
    const V u2 = hn::Mul(u, u);
    const V one = hn::Set(hn::DFromV<V>(), hn::TFromV<V>(1));
    return hn::Add(hn::Mul(mu, u), hn::Div(hn::Mul(m2, u2), hn::Add(one, u2)));
}

/// The damping term alpha (1 - (0.05 y) y) y (the paper's fixed sigma = 0.05).
template <class V>
HWY_INLINE V gm_damping(V alpha, V y) {
    using T = hn::TFromV<V>;
    const hn::DFromV<V> d;
    return hn::Mul(hn::Mul(alpha, hn::Sub(hn::Set(d, T(1)), hn::Mul(hn::Mul(hn::Set(d, T(0.05)), y), y))), y);
}

/// One step (x, y) <- GM(x, y).
template <class V>
HWY_INLINE void gumowski_mira(V alpha, V mu, V m2, V& x, V& y) {
    const V nx = hn::Add(hn::Add(y, gm_damping(alpha, y)), gm_f(mu, m2, x));
    y = hn::Add(hn::Neg(x), gm_f(mu, m2, nx));
    x = nx;
}

// ---------------------------------------------------------------- the hexagonal lattice
/// in_cell(x, y) for each lane: strictly inside the hexagon H about 0 (NaN: no).
template <class D>
HWY_INLINE hn::Mask<D> in_cell(D d, hn::Vec<D> x, hn::Vec<D> y) {
    using K = HexConst<hn::TFromD<D>>;
    const auto pi = hn::Set(d, K::pi);
    const auto hx = hn::Mul(x, hn::Set(d, hn::TFromD<D>(0.5))), hy = hn::Mul(y, hn::Set(d, K::h));
    return hn::And(hn::Lt(hn::Abs(x), pi),
                   hn::And(hn::Lt(hn::Abs(hn::Add(hx, hy)), pi), hn::Lt(hn::Abs(hn::Sub(hx, hy)), pi)));
}

} // namespace fp::kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif // per-target include guard
