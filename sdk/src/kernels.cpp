// The known kernels as batch functions (fixpoint/kernels.hpp): the formulas of
// fixpoint/kernels-inl.hpp in the SIMD layer's point loops (simd-inl.hpp), compiled once per
// instruction set of the build and dispatched at run time.
#include <fixpoint/kernels.hpp>

#include <algorithm>
#include <cstddef>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "kernels.cpp" // (sdk/src is on the library's own include path)
#include <hwy/foreach_target.h>          // IWYU pragma: keep

#include <fixpoint/kernels-inl.hpp>
#include <fixpoint/simd-inl.hpp>

HWY_BEFORE_NAMESPACE();
namespace fp::kernels::HWY_NAMESPACE {
namespace fs = fp::simd::HWY_NAMESPACE;

template <class T>
void affine_t(const double (&k)[6], Points<T> p, Mask mask) {
    const hn::ScalableTag<T> d;
    const hn::Vec<decltype(d)> c[6] = {hn::Set(d, T(k[0])), hn::Set(d, T(k[1])), hn::Set(d, T(k[2])),
                                       hn::Set(d, T(k[3])), hn::Set(d, T(k[4])), hn::Set(d, T(k[5]))};
    fs::map_points(d, p, mask, [&](auto& x, auto& y) { affine(c, x, y); });
}

template <class T>
void gumowski_mira_t(const double (&k)[3], Points<T> p, Mask mask) {
    const hn::ScalableTag<T> d;
    const auto alpha = hn::Set(d, T(k[0])), mu = hn::Set(d, T(k[1])), m2 = hn::Set(d, T(k[2]));
    fs::map_points(d, p, mask, [&](auto& x, auto& y) { gumowski_mira(alpha, mu, m2, x, y); });
}

template <class T>
void in_circle_t(T cx, T cy, T r2, Points<const T> p, unsigned char* out) {
    const hn::ScalableTag<T> d;
    const auto vcx = hn::Set(d, cx), vcy = hn::Set(d, cy), vr2 = hn::Set(d, r2);
    fs::test_points(d, p, out, [&](auto x, auto y) { return in_circle(x, y, vcx, vcy, vr2); });
}

template <class T>
void inversion_factor_t(T r2, Points<const T> dd, T* s) {
    const hn::ScalableTag<T> d;
    const auto vr2 = hn::Set(d, r2);
    fs::eval_points(d, dd, s, [&](auto dx, auto dy) { return inversion_factor(sq_norm(dx, dy), vr2); });
}

template <class T>
bool directions_t(T ox, T oy, Points<const T> p, Mask m, T* dx, T* dy) {
    const hn::ScalableTag<T> d;
    const auto vox = hn::Set(d, ox), voy = hn::Set(d, oy);
    std::copy_n(p.x, p.n, dx);
    std::copy_n(p.y, p.n, dy);
    fs::map_points(d, Points<T>{dx, dy, p.n}, nullptr, [&](auto& vx, auto& vy) {
        vx = hn::Sub(vx, vox);
        vy = hn::Sub(vy, voy);
    });
    if (!m) return true;
    bool any = false;
    for (std::size_t i = 0; i < p.n; ++i) {
        dx[i] = m[i] ? dx[i] : T(0);
        dy[i] = m[i] ? dy[i] : T(0);
        any |= m[i] != 0;
    }
    return any;
}

template <class T>
void scale_from_t(T ox, T oy, Points<T> p, Mask m, const T* t) {
    const hn::ScalableTag<T> d;
    const auto vox = hn::Set(d, ox), voy = hn::Set(d, oy);
    fs::map_points_with(d, p, m, t, [&](auto& x, auto& y, auto s) { scale_from(vox, voy, s, x, y); });
}

template <class T>
void in_cell_t(Points<const T> p, unsigned char* out) {
    const hn::ScalableTag<T> d;
    fs::test_points(d, p, out, [&](auto x, auto y) { return in_cell(d, x, y); });
}

// (One name per precision: HWY_EXPORT takes a function, not an overload set.)
void affine_f(const double (&k)[6], Points<float> p, Mask m) { affine_t(k, p, m); }
void affine_d(const double (&k)[6], Points<double> p, Mask m) { affine_t(k, p, m); }
void gumowski_mira_f(const double (&k)[3], Points<float> p, Mask m) { gumowski_mira_t(k, p, m); }
void gumowski_mira_d(const double (&k)[3], Points<double> p, Mask m) { gumowski_mira_t(k, p, m); }
void in_circle_f(float cx, float cy, float r2, Points<const float> p, unsigned char* o) {
    in_circle_t(cx, cy, r2, p, o);
}
void in_circle_d(double cx, double cy, double r2, Points<const double> p, unsigned char* o) {
    in_circle_t(cx, cy, r2, p, o);
}
void inversion_factor_f(float r2, Points<const float> dd, float* s) { inversion_factor_t(r2, dd, s); }
void inversion_factor_d(double r2, Points<const double> dd, double* s) { inversion_factor_t(r2, dd, s); }
bool directions_f(float ox, float oy, Points<const float> p, Mask m, float* dx, float* dy) {
    return directions_t(ox, oy, p, m, dx, dy);
}
bool directions_d(double ox, double oy, Points<const double> p, Mask m, double* dx, double* dy) {
    return directions_t(ox, oy, p, m, dx, dy);
}
void scale_from_f(float ox, float oy, Points<float> p, Mask m, const float* t) {
    scale_from_t(ox, oy, p, m, t);
}
void scale_from_d(double ox, double oy, Points<double> p, Mask m, const double* t) {
    scale_from_t(ox, oy, p, m, t);
}
void in_cell_f(Points<const float> p, unsigned char* out) { in_cell_t(p, out); }
void in_cell_d(Points<const double> p, unsigned char* out) { in_cell_t(p, out); }

} // namespace fp::kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp::kernels {
HWY_EXPORT(affine_f);
HWY_EXPORT(affine_d);
HWY_EXPORT(gumowski_mira_f);
HWY_EXPORT(gumowski_mira_d);
HWY_EXPORT(in_circle_f);
HWY_EXPORT(in_circle_d);
HWY_EXPORT(inversion_factor_f);
HWY_EXPORT(inversion_factor_d);
HWY_EXPORT(directions_f);
HWY_EXPORT(directions_d);
HWY_EXPORT(scale_from_f);
HWY_EXPORT(scale_from_d);
HWY_EXPORT(in_cell_f);
HWY_EXPORT(in_cell_d);

void affine(const double (&k)[6], Points<float> p, Mask m) { HWY_DYNAMIC_DISPATCH(affine_f)(k, p, m); }
void affine(const double (&k)[6], Points<double> p, Mask m) { HWY_DYNAMIC_DISPATCH(affine_d)(k, p, m); }
void gumowski_mira(const double (&k)[3], Points<float> p, Mask m) {
    HWY_DYNAMIC_DISPATCH(gumowski_mira_f)(k, p, m);
}
void gumowski_mira(const double (&k)[3], Points<double> p, Mask m) {
    HWY_DYNAMIC_DISPATCH(gumowski_mira_d)(k, p, m);
}
void in_circle(float cx, float cy, float r2, Points<const float> p, unsigned char* out) {
    HWY_DYNAMIC_DISPATCH(in_circle_f)(cx, cy, r2, p, out);
}
void in_circle(double cx, double cy, double r2, Points<const double> p, unsigned char* out) {
    HWY_DYNAMIC_DISPATCH(in_circle_d)(cx, cy, r2, p, out);
}
void inversion_factor(float r2, Points<const float> d, float* s) {
    HWY_DYNAMIC_DISPATCH(inversion_factor_f)(r2, d, s);
}
void inversion_factor(double r2, Points<const double> d, double* s) {
    HWY_DYNAMIC_DISPATCH(inversion_factor_d)(r2, d, s);
}
bool directions(float ox, float oy, Points<const float> p, Mask m, float* dx, float* dy) {
    return HWY_DYNAMIC_DISPATCH(directions_f)(ox, oy, p, m, dx, dy);
}
bool directions(double ox, double oy, Points<const double> p, Mask m, double* dx, double* dy) {
    return HWY_DYNAMIC_DISPATCH(directions_d)(ox, oy, p, m, dx, dy);
}
void scale_from(float ox, float oy, Points<float> p, Mask m, const float* t) {
    HWY_DYNAMIC_DISPATCH(scale_from_f)(ox, oy, p, m, t);
}
void scale_from(double ox, double oy, Points<double> p, Mask m, const double* t) {
    HWY_DYNAMIC_DISPATCH(scale_from_d)(ox, oy, p, m, t);
}
void in_cell(Points<const float> p, unsigned char* out) { HWY_DYNAMIC_DISPATCH(in_cell_f)(p, out); }
void in_cell(Points<const double> p, unsigned char* out) { HWY_DYNAMIC_DISPATCH(in_cell_d)(p, out); }
} // namespace fp::kernels
#endif // HWY_ONCE
