// The point loops of fixpoint/scheme.hpp's chunks (linear combinations of points, the masked
// write-back), compiled once per instruction set of the build from scheme.hpp itself and
// dispatched at run time: every scheme plugin includes scheme.hpp once, so each carries its
// own copies. Plain loops, vectorised by the compiler with each target's instructions, in the
// order of the scalar expressions (no FMA: the same bits on every target). Not for plugins to
// include: scheme.hpp does.

#if defined(FIXPOINT_SCHEME_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef FIXPOINT_SCHEME_INL_HPP_
#undef FIXPOINT_SCHEME_INL_HPP_
#else
#define FIXPOINT_SCHEME_INL_HPP_
#endif

#include <hwy/highway.h>

#include <cstddef>

HWY_BEFORE_NAMESPACE();
// inline: a plugin of several files may include scheme.hpp in more than one.
namespace fp::scheme::HWY_NAMESPACE {

/// dst <- A u + B v with k = {A.a, A.b, A.c, A.d, B.a, B.b, B.c, B.d} (dst may alias u or v).
template <class T>
HWY_INLINE void lin2_t(const T* k, const T* ux, const T* uy, const T* vx, const T* vy, T* dx, T* dy,
                       std::size_t n) {
    const T a = k[0], b = k[1], c = k[2], d = k[3], e = k[4], f = k[5], g = k[6], h = k[7];
    for (std::size_t i = 0; i < n; ++i) {
        const T x0 = ux[i], y0 = uy[i], x1 = vx[i], y1 = vy[i];
        dx[i] = (a * x0 + b * y0) + (e * x1 + f * y1);
        dy[i] = (c * x0 + d * y0) + (g * x1 + h * y1);
    }
}

/// dst <- A u + B v + C w with k = {A, B, C} as in lin2_t.
template <class T>
HWY_INLINE void lin3_t(const T* k, const T* ux, const T* uy, const T* vx, const T* vy, const T* wx,
                       const T* wy, T* dx, T* dy, std::size_t n) {
    const T a = k[0], b = k[1], c = k[2], d = k[3], e = k[4], f = k[5], g = k[6], h = k[7];
    const T p = k[8], l = k[9], m = k[10], o = k[11];
    for (std::size_t i = 0; i < n; ++i) {
        const T x0 = ux[i], y0 = uy[i], x1 = vx[i], y1 = vy[i], x2 = wx[i], y2 = wy[i];
        dx[i] = (a * x0 + b * y0) + (e * x1 + f * y1) + (p * x2 + l * y2);
        dy[i] = (c * x0 + d * y0) + (g * x1 + h * y1) + (m * x2 + o * y2);
    }
}

/// x[i] <- px[i] where the mask is on (a null mask: everywhere).
template <class T>
HWY_INLINE void merge_t(T* x, T* y, const T* px, const T* py, const unsigned char* m, std::size_t n) {
    if (!m) {
        for (std::size_t i = 0; i < n; ++i) x[i] = px[i], y[i] = py[i];
        return;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const bool on = m[i] != 0;
        x[i] = on ? px[i] : x[i];
        y[i] = on ? py[i] : y[i];
    }
}

inline void lin2_f(const float* k, const float* ux, const float* uy, const float* vx, const float* vy,
                   float* dx, float* dy, std::size_t n) {
    lin2_t(k, ux, uy, vx, vy, dx, dy, n);
}
inline void lin2_d(const double* k, const double* ux, const double* uy, const double* vx, const double* vy,
                   double* dx, double* dy, std::size_t n) {
    lin2_t(k, ux, uy, vx, vy, dx, dy, n);
}
inline void lin3_f(const float* k, const float* ux, const float* uy, const float* vx, const float* vy,
                   const float* wx, const float* wy, float* dx, float* dy, std::size_t n) {
    lin3_t(k, ux, uy, vx, vy, wx, wy, dx, dy, n);
}
inline void lin3_d(const double* k, const double* ux, const double* uy, const double* vx, const double* vy,
                   const double* wx, const double* wy, double* dx, double* dy, std::size_t n) {
    lin3_t(k, ux, uy, vx, vy, wx, wy, dx, dy, n);
}
inline void merge_f(float* x, float* y, const float* px, const float* py, const unsigned char* m,
                    std::size_t n) {
    merge_t(x, y, px, py, m, n);
}
inline void merge_d(double* x, double* y, const double* px, const double* py, const unsigned char* m,
                    std::size_t n) {
    merge_t(x, y, px, py, m, n);
}

} // namespace fp::scheme::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif // per-target include guard
