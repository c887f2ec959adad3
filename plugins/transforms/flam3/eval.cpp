// flam3's apply_xform on the SIMD layer (xform_data.hpp has the formula), compiled once per
// instruction set and dispatched at run time. Every variation runs over the whole chunk in
// double lanes, with the SDK's own sin, cos, atan2, log and exp (fixpoint/simd-math-inl.hpp):
// no libm call per point, and the same bits on every target. The variations' formulas are in
// vars-*-inl.hpp, by their numbers; a variation's weight enters where flam3's does (some use it
// inside, not only as a factor: arch, rays, blade, secant2, twintrian, lazysusan, loonie, scry,
// whorl, flux).
#include "flam3/xform_data.hpp"

#include <fixpoint/batch.hpp>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "flam3/eval.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include <fixpoint/simd-math-inl.hpp>

#include <cmath>

HWY_BEFORE_NAMESPACE();
namespace fp_flam3::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace fs = fp::simd::HWY_NAMESPACE;
using D = hn::ScalableTag<double>;
using VD = hn::Vec<D>;
constexpr std::size_t cn = fp::chunk_size;
constexpr double pi = 3.14159265358979323846;

// Short names for the lane operations, so that the formulas read as flam3's do.
HWY_INLINE VD add(VD a, VD b) { return hn::Add(a, b); }
HWY_INLINE VD sub(VD a, VD b) { return hn::Sub(a, b); }
HWY_INLINE VD mul(VD a, VD b) { return hn::Mul(a, b); }
HWY_INLINE VD quo(VD a, VD b) { return hn::Div(a, b); }
HWY_INLINE VD neg(VD a) { return hn::Neg(a); }
HWY_INLINE VD k(double v) { return hn::Set(D(), v); }
HWY_INLINE VD sin_of(VD x) {
    VD s, c;
    fs::sin_cos(D(), x, s, c);
    return s;
}
HWY_INLINE VD cos_of(VD x) {
    VD s, c;
    fs::sin_cos(D(), x, s, c);
    return c;
}
HWY_INLINE void sincos(VD x, VD& s, VD& c) { fs::sin_cos(D(), x, s, c); }
HWY_INLINE VD tan_of(VD x) {
    VD s, c;
    fs::sin_cos(D(), x, s, c);
    return quo(s, c);
}
HWY_INLINE VD exp_of(VD x) { return fs::exp(D(), x); }
HWY_INLINE VD log_of(VD x) { return fs::log(D(), x); }
HWY_INLINE VD atan2_of(VD y, VD x) { return fs::atan2(D(), y, x); }
HWY_INLINE VD pow_of(VD x, VD y) { return fs::pow_abs(D(), x, y); } ///< x >= 0
HWY_INLINE VD sqrt_of(VD x) { return hn::Sqrt(x); }
HWY_INLINE VD abs_of(VD x) { return hn::Abs(x); }
HWY_INLINE VD floor_of(VD x) { return hn::Floor(x); }
HWY_INLINE VD trunc_of(VD x) { return hn::Trunc(x); }
/// C's fmod as a - b trunc(a / b) (C's is exact; this rounds, within an ulp of a).
HWY_INLINE VD fmod_of(VD a, VD b) { return sub(a, mul(b, trunc_of(quo(a, b)))); }
/// sinh: a series below 1 in magnitude (where (e^x - e^-x) / 2 would cancel), else by exp.
HWY_INLINE VD sinh_of(VD x) {
    const VD x2 = mul(x, x);
    // x (1 + x^2/3! + x^4/5! + ... + x^18/19!), Horner in x^2.
    constexpr double c[] = {1.0 / 121645100408832000.0,
                            1.0 / 355687428096000.0,
                            1.0 / 1307674368000.0,
                            1.0 / 6227020800.0,
                            1.0 / 39916800.0,
                            1.0 / 362880.0,
                            1.0 / 5040.0,
                            1.0 / 120.0,
                            1.0 / 6.0,
                            1.0};
    VD s = k(c[0]);
    for (std::size_t i = 1; i < std::size(c); ++i) s = add(mul(s, x2), k(c[i]));
    const VD series = mul(x, s);
    const VD e = exp_of(x);
    const VD big = mul(k(0.5), sub(e, quo(k(1.0), e)));
    return hn::IfThenElse(hn::Lt(abs_of(x), k(1.0)), series, big);
}
HWY_INLINE VD cosh_of(VD x) {
    const VD e = exp_of(x);
    return mul(k(0.5), add(e, quo(k(1.0), e)));
}
HWY_INLINE VD sel(hn::Mask<D> m, VD a, VD b) { return hn::IfThenElse(m, a, b); }

/// The chunk's working arrays.
struct Work {
    alignas(64) double tx[cn], ty[cn], r2[cn], r[cn], atan[cn], atanyx[cn], sina[cn], cosa[cn];
    alignas(64) double p0[cn], p1[cn];
};

/// One vector of the chunk's inputs for a variation's formula.
struct In {
    VD tx, ty, r2, r;
    const Work* w;
    const double* rnd;
    std::size_t i;
    VD atan() const { return hn::Load(D(), w->atan + i); }
    VD atanyx() const { return hn::Load(D(), w->atanyx + i); }
    VD sina() const { return hn::Load(D(), w->sina + i); }
    VD cosa() const { return hn::Load(D(), w->cosa + i); }
    /// The j-th of the variation's random numbers.
    VD u(std::uint32_t j) const { return hn::Load(D(), rnd + j * cn + i); }
};

/// What a variation's formula sees besides its point: its weight, the xform's parameters.
struct Ctx {
    const XformData& x;
    Work& w;
    std::size_t n; ///< the chunk's points rounded up to whole vectors
    const double* rnd;
    double weight;
    VD W() const { return k(weight); }
    VD P(Param p) const { return k(x.prm[p]); }
    VD R(Derived d) const { return k(x.der[d]); }
    double c(int i) const { return x.coef[i]; }
};

/// Runs f(in, ox, oy) on every vector of the chunk and adds (ox, oy) to the sums (p0, p1).
template <class F>
HWY_INLINE bool each(const Ctx& c, std::uint32_t roff, const F& f) {
    const D d;
    for (std::size_t i = 0; i < c.n; i += hn::Lanes(d)) {
        const In in{hn::Load(d, c.w.tx + i),
                    hn::Load(d, c.w.ty + i),
                    hn::Load(d, c.w.r2 + i),
                    hn::Load(d, c.w.r + i),
                    &c.w,
                    c.rnd + roff * cn,
                    i};
        VD ox, oy;
        f(in, ox, oy);
        hn::Store(add(hn::Load(d, c.w.p0 + i), ox), d, c.w.p0 + i);
        hn::Store(add(hn::Load(d, c.w.p1 + i), oy), d, c.w.p1 + i);
    }
    return true;
}

// clang-format off
#include "flam3/vars-a-inl.hpp"
#include "flam3/vars-b-inl.hpp"
#include "flam3/vars-c-inl.hpp"
// clang-format on

void derive_t(XformData* xp) {
    XformData& x = *xp;
    const D d;
    // One lane's worth of the SIMD layer's sin and cos (the same on every target).
    const auto sc = [&](double a, double& s, double& c) {
        alignas(HWY_MAX_BYTES) double in[HWY_MAX_BYTES / 8] = {a}, so[HWY_MAX_BYTES / 8],
                                                         co[HWY_MAX_BYTES / 8];
        VD vs, vc;
        fs::sin_cos(d, hn::Load(d, in), vs, vc);
        hn::Store(vs, d, so);
        hn::Store(vc, d, co);
        s = so[0], c = co[0];
    };
    const double* p = x.prm;
    double* r = x.der;
    r[d_julian_rn] = std::fabs(p[p_julian_power]);
    r[d_julian_cn] = p[p_julian_dist] / p[p_julian_power] / 2.0;
    r[d_juliascope_rn] = std::fabs(p[p_juliascope_power]);
    r[d_juliascope_cn] = p[p_juliascope_dist] / p[p_juliascope_power] / 2.0;
    double s, c;
    sc(p[p_perspective_angle] * pi / 2.0, s, c);
    r[d_persp_vsin] = s;
    r[d_persp_vfcos] = p[p_perspective_dist] * c;
    sc(p[p_radial_blur_angle] * pi / 2.0, s, c);
    r[d_radial_spin] = s, r[d_radial_zoom] = c;
    r[d_waves_dx2] = 1.0 / (x.coef[4] * x.coef[4] + eps);
    r[d_waves_dy2] = 1.0 / (x.coef[5] * x.coef[5] + eps);
    const double add_ = p[p_disc2_twist];
    r[d_disc2_timespi] = p[p_disc2_rot] * pi;
    sc(add_, s, c);
    c -= 1;
    if (add_ > 2 * pi) {
        const double f = 1 + add_ - 2 * pi;
        c *= f, s *= f;
    }
    if (add_ < -2 * pi) {
        const double f = 1 + add_ + 2 * pi;
        c *= f, s *= f;
    }
    r[d_disc2_sinadd] = s, r[d_disc2_cosadd] = c;
    r[d_ss_pm4] = p[p_super_shape_m] / 4.0;
    r[d_ss_pneg1_n1] = -1.0 / p[p_super_shape_n1];
    r[d_wj_cf] = 1.0 - p[p_wedge_julia_angle] * p[p_wedge_julia_count] * (1.0 / pi) * 0.5;
    r[d_wj_rn] = std::fabs(p[p_wedge_julia_power]);
    r[d_wj_cn] = p[p_wedge_julia_dist] / p[p_wedge_julia_power] / 2.0;
    sc(p[p_escher_beta], s, c);
    r[d_escher_seb] = s, r[d_escher_ceb] = c;
}

void eval_t(const XformData* xp, double* px, double* py, std::size_t count, const double* rnd) {
    const XformData& x = *xp;
    const D d;
    const std::size_t N = hn::Lanes(d);
    const std::size_t n = (count + N - 1) / N * N;
    Work w;
    // The affine pre-transform; the lanes past the points are zeros (their results unused).
    for (std::size_t i = 0; i < n; ++i) {
        const double X = i < count ? px[i] : 0.0, Y = i < count ? py[i] : 0.0;
        w.tx[i] = (x.coef[0] * X + x.coef[2] * Y) + x.coef[4];
        w.ty[i] = (x.coef[1] * X + x.coef[3] * Y) + x.coef[5];
    }
    if (x.pre_blur != 0) {
        // pre_blur: t += rndG (cos A, sin A), rndG = w (u0 + u1 + u2 + u3 - 2), A = 2 pi u4.
        const double* u = rnd + x.pre_blur_roff * cn;
        for (std::size_t i = 0; i < n; i += N) {
            const VD g = mul(k(x.pre_blur), sub(add(add(add(hn::Load(d, u + i), hn::Load(d, u + cn + i)),
                                                        hn::Load(d, u + 2 * cn + i)),
                                                    hn::Load(d, u + 3 * cn + i)),
                                                k(2.0)));
            VD s, c;
            sincos(mul(mul(hn::Load(d, u + 4 * cn + i), k(2.0)), k(pi)), s, c);
            hn::Store(add(hn::Load(d, w.tx + i), mul(g, c)), d, w.tx + i);
            hn::Store(add(hn::Load(d, w.ty + i), mul(g, s)), d, w.ty + i);
        }
    }
    for (std::size_t i = 0; i < n; i += N) {
        const VD tx = hn::Load(d, w.tx + i), ty = hn::Load(d, w.ty + i);
        const VD r2 = add(mul(tx, tx), mul(ty, ty)), r = hn::Sqrt(r2);
        hn::Store(r2, d, w.r2 + i);
        hn::Store(r, d, w.r + i);
        if (x.atan) hn::Store(atan2_of(tx, ty), d, w.atan + i);
        if (x.atanyx) hn::Store(atan2_of(ty, tx), d, w.atanyx + i);
        if (x.angles) {
            hn::Store(quo(tx, r), d, w.sina + i);
            hn::Store(quo(ty, r), d, w.cosa + i);
        }
        hn::Store(hn::Zero(d), d, w.p0 + i);
        hn::Store(hn::Zero(d), d, w.p1 + i);
    }
    for (std::uint32_t j = 0; j < x.n; ++j) {
        const Ctx c{x, w, n, rnd, x.weight[j]};
        const std::uint32_t v = x.var[j], ro = x.roff[j];
        if (!vars_a(c, v, ro) && !vars_b(c, v, ro)) vars_c(c, v, ro);
    }
    for (std::size_t i = 0; i < count; ++i) {
        const double p0 = w.p0[i], p1 = w.p1[i];
        if (x.has_post) {
            px[i] = (x.post[0] * p0 + x.post[2] * p1) + x.post[4];
            py[i] = (x.post[1] * p0 + x.post[3] * p1) + x.post[5];
        } else {
            px[i] = p0, py[i] = p1;
        }
    }
}

} // namespace fp_flam3::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp_flam3 {
HWY_EXPORT(derive_t);
HWY_EXPORT(eval_t);

void derive(XformData& x) { HWY_DYNAMIC_DISPATCH(derive_t)(&x); }
void eval_chunk(const XformData& x, double* px, double* py, std::size_t n, const double* rnd) {
    HWY_DYNAMIC_DISPATCH(eval_t)(&x, px, py, n, rnd);
}

void add_variation(XformData& x, std::uint32_t v, double w) {
    const std::uint32_t rows = var_info[v].randoms;
    if (v == v_pre_blur) {
        x.pre_blur = w;
        x.pre_blur_roff = x.randoms;
    } else {
        x.var[x.n] = v;
        x.weight[x.n] = w;
        x.roff[x.n] = x.randoms;
        ++x.n;
    }
    x.randoms += rows;
    x.atan = x.atan || reads_atan(v);
    x.atanyx = x.atanyx || reads_atanyx(v);
    x.angles = x.angles || reads_angles(v);
}
} // namespace fp_flam3
#endif
