// The polygon shapes' batch kernels (polygon_core.hpp's crossing-number inside test and ray
// exit), compiled once per SIMD target by polygon_kernels.hpp and dispatched at run time.
//
// Each vector holds one point per lane; the loop runs over the edges with each edge's data
// broadcast. Per lane the operations are the scalar ones, in the same order (no FMA: the
// plugins build with -ffp-contract=off and nothing here calls MulAdd), so every target gives
// the bits of polygon_core.hpp's point-by-point reference (inside_pt, ray_exit_pt), which the
// tests compare against.

// Per-target include guard (Highway's convention).
#if defined(FIXPOINT_POLYGON_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef FIXPOINT_POLYGON_INL_HPP_
#undef FIXPOINT_POLYGON_INL_HPP_
#else
#define FIXPOINT_POLYGON_INL_HPP_
#endif

#include <fixpoint/simd-inl.hpp>

#include <cstddef>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace fp_shapes::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace fs = fp::simd::HWY_NAMESPACE;

/// Crossing number along +x, half-open in y: for each edge, the point's row straddles it and
/// the point lies left of the crossing.
template <class T>
void inside_t(const EdgeView<T>& e, T rx, T ry, fp::Points<const T> p, unsigned char* out) {
    const hn::ScalableTag<T> d;
    const auto vrx = hn::Set(d, rx), vry = hn::Set(d, ry);
    fs::test_points(d, p, out, [&](auto x, auto y) {
        const auto px = hn::Sub(x, vrx), py = hn::Sub(y, vry);
        auto in = hn::Lt(px, px); // all false (NaN lanes too)
        auto above_i = hn::Gt(hn::Set(d, e.vy[0]), py);
        for (std::size_t i = 0; i < e.n; ++i) {
            const auto yi = hn::Set(d, e.vy[i]);
            const auto above_j = hn::Gt(hn::Set(d, e.vy[i + 1]), py);
            const auto xc = hn::Add(hn::Set(d, e.vx[i]), hn::Mul(hn::Sub(py, yi), hn::Set(d, e.sx[i])));
            in = hn::Xor(in, hn::And(hn::Xor(above_i, above_j), hn::Lt(px, xc)));
            above_i = above_j;
        }
        return in;
    });
}
void inside_f(const EdgeView<float>& e, float rx, float ry, fp::Points<const float> p, unsigned char* out) {
    inside_t(e, rx, ry, p, out);
}
void inside_d(const EdgeView<double>& e, double rx, double ry, fp::Points<const double> p,
              unsigned char* out) {
    inside_t(e, rx, ry, p, out);
}

/// The nearest edge the ray leaves through. w = v_i - o and cross(w, e_i) = t * den do not
/// depend on the direction: computed once per edge in scalar (the same IEEE operations), and
/// an edge with cross(w, e_i) <= 0 is skipped for the whole vector, as every lane would
/// reject it.
template <class T>
void ray_t(const EdgeView<T>& e, T ox, T oy, fp::Points<const T> dd, T* t) {
    const hn::ScalableTag<T> d;
    const auto zero = hn::Zero(d);
    const auto inf = hn::Set(d, std::numeric_limits<T>::infinity());
    fs::eval_points(d, dd, t, [&](auto dx, auto dy) {
        auto best = inf;
        for (std::size_t i = 0; i < e.n; ++i) {
            const T wx = e.vx[i] - ox, wy = e.vy[i] - oy;
            const T tn = wx * e.ey[i] - wy * e.ex[i];
            if (!(tn > T(0))) continue;
            const auto den = hn::Sub(hn::Mul(dx, hn::Set(d, e.ey[i])), hn::Mul(dy, hn::Set(d, e.ex[i])));
            const auto sn = hn::Sub(hn::Mul(hn::Set(d, wx), dy), hn::Mul(hn::Set(d, wy), dx));
            const auto ti = hn::Div(hn::Set(d, tn), den);
            const auto hit =
                hn::And(hn::And(hn::Gt(den, zero), hn::Ge(sn, hn::Mul(hn::Set(d, e.s_lo[i]), den))),
                        hn::And(hn::Le(sn, hn::Mul(hn::Set(d, e.s_hi[i]), den)), hn::Lt(ti, best)));
            best = hn::IfThenElse(hit, ti, best);
        }
        return best;
    });
}
void ray_f(const EdgeView<float>& e, float ox, float oy, fp::Points<const float> d, float* t) {
    ray_t(e, ox, oy, d, t);
}
void ray_d(const EdgeView<double>& e, double ox, double oy, fp::Points<const double> d, double* t) {
    ray_t(e, ox, oy, d, t);
}

} // namespace fp_shapes::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif // per-target guard
