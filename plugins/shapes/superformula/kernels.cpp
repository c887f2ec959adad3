// The superformula's kernels on the SIMD layer (superformula.cpp's header: the arithmetic in
// double, the root finder a lane runs), compiled once per instruction set of the build and
// dispatched at run time: the functions superformula/curve.hpp declares.
#include "superformula/curve.hpp"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "superformula/kernels.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "shapes/lanes-inl.hpp"
#include <fixpoint/simd-math-inl.hpp>

HWY_BEFORE_NAMESPACE();
namespace fp_superformula::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace fs = fp::simd::HWY_NAMESPACE;
using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;

/// theta: the polar angle of q in the curve's own frame, in [-pi, pi].
HWY_INLINE V theta(D d, const Curve& c, V qx, V qy) {
    const auto cr = hn::Set(d, c.cr), sr = hn::Set(d, c.sr);
    return fs::atan2(d, hn::Sub(hn::Mul(cr, qy), hn::Mul(sr, qx)), hn::Add(hn::Mul(cr, qx), hn::Mul(sr, qy)));
}

/// r(theta) = scale (|cos(m theta / 4) / a|^n2 + |sin(m theta / 4) / b|^n3)^(-1/n1).
HWY_INLINE V radius(D d, const Curve& c, V th) {
    V s, co;
    fs::sin_cos(d, hn::Mul(hn::Set(d, c.m4), th), s, co);
    const auto A = fs::pow_abs(d, hn::Mul(hn::Abs(co), hn::Set(d, c.inv_a)), hn::Set(d, c.n2));
    const auto B = fs::pow_abs(d, hn::Mul(hn::Abs(s), hn::Set(d, c.inv_b)), hn::Set(d, c.n3));
    return hn::Mul(hn::Set(d, c.scale), fs::pow_abs(d, hn::Add(A, B), hn::Set(d, -c.inv_n1)));
}

/// f(t) = |w + t d| - r(theta(w + t d)): < 0 inside, >= 0 outside (NaN counts as outside).
HWY_INLINE V f_at(D d, const Curve& c, V wx, V wy, V dx, V dy, V t) {
    const auto qx = hn::Add(wx, hn::Mul(t, dx)), qy = hn::Add(wy, hn::Mul(t, dy));
    return hn::Sub(hn::Sqrt(hn::Add(hn::Mul(qx, qx), hn::Mul(qy, qy))), radius(d, c, theta(d, c, qx, qy)));
}

using fp_shapes::HWY_NAMESPACE::blocks;

/// The bounds' answers for N points (x, y): inside (the mask returned), outside, or `open`
/// where they cannot tell (between the bounds of the point's sector, or a NaN). The sector
/// comes from the pseudo-angle in the curve's frame (theta()'s rotation), its bounds by a
/// gather.
HWY_INLINE hn::Mask<D> classify(D d, const Curve& c, V x, V y, hn::Mask<D>& open) {
    const hn::RebindToSigned<D> di;
    const auto zero = hn::Zero(d), two = hn::Set(d, 2.0);
    const auto qx = hn::Sub(x, hn::Set(d, c.cx)), qy = hn::Sub(y, hn::Set(d, c.cy));
    const auto q2 = hn::Add(hn::Mul(qx, qx), hn::Mul(qy, qy));
    auto in = hn::Lt(q2, hn::Set(d, c.in2));
    open = hn::Not(hn::Or(in, hn::Ge(q2, hn::Set(d, c.out2)))); // (NaN: open)
    const auto sel = hn::And(open, hn::Gt(q2, zero));
    if (!hn::AllFalse(d, sel)) {
        const auto cr = hn::Set(d, c.cr), sr = hn::Set(d, c.sr);
        const auto rx = hn::Add(hn::Mul(cr, qx), hn::Mul(sr, qy)),
                   ry = hn::Sub(hn::Mul(cr, qy), hn::Mul(sr, qx));
        const auto t = hn::Div(ry, hn::Add(hn::Abs(rx), hn::Abs(ry)));
        const auto a = hn::IfThenElse(
            hn::Ge(rx, zero), t, hn::IfThenElse(hn::Ge(ry, zero), hn::Sub(two, t), hn::Sub(hn::Neg(two), t)));
        const auto f = hn::Mul(hn::Add(a, two), hn::Set(d, double(sector_count) / 4) /* 64: exact */);
        // (f > 0 is false for NaN: sector 0, whose bounds are the global ones.)
        const auto fc = hn::IfThenElseZero(hn::Gt(f, zero), hn::Min(f, hn::Set(d, double(sector_count - 1))));
        const auto i2 = hn::ShiftLeft<1>(hn::ConvertTo(di, fc));
        const auto lo = hn::GatherIndex(d, c.sectors, i2), hi = hn::GatherIndex(d, c.sectors + 1, i2);
        const auto in_s = hn::Lt(q2, lo);
        const auto open_s = hn::Not(hn::Or(in_s, hn::Ge(q2, hi)));
        in = hn::Or(hn::AndNot(sel, in), hn::And(sel, in_s));
        open = hn::Or(hn::AndNot(sel, open), hn::And(sel, open_s));
    }
    return in;
}

/// spread[b]: the bits of b as eight bytes 0 or 1, lowest bit first (masks to bytes).
struct Spread {
    unsigned char b[256][8];
    constexpr Spread() : b{} {
        for (int v = 0; v < 256; ++v)
            for (int j = 0; j < 8; ++j) b[v][j] = static_cast<unsigned char>((v >> j) & 1);
    }
};
constexpr Spread spread;

/// The inside test: the bounds first (classify), and r(theta) only for the points they
/// leave open, gathered into whole vectors: in a chaos game most points lie far outside most
/// sets. Each point's answer is the one r(theta) gives.
template <class T>
void inside_t(const Curve& c, fp::Points<const T> p, unsigned char* out) {
    const D d;
    const hn::Rebind<T, D> dt;
    const std::size_t N = hn::Lanes(d);
    const auto cx = hn::Set(d, c.cx), cy = hn::Set(d, c.cy), one = hn::Set(d, 1.0);
    const auto load = [&](const T* v) {
        if constexpr (sizeof(T) == 8)
            return hn::LoadU(d, v);
        else
            return hn::PromoteTo(d, hn::LoadU(dt, v));
    };
    const hn::RebindToUnsigned<D> du;
    constexpr std::size_t chunk = 256;
    std::uint64_t list[chunk + HWY_MAX_BYTES / 8]; // (room for CompressStore's whole vector)
    alignas(HWY_MAX_BYTES) double bx[HWY_MAX_BYTES / 8] = {}, by[HWY_MAX_BYTES / 8] = {};
    alignas(HWY_MAX_BYTES) double br[HWY_MAX_BYTES / 8];
    std::uint8_t bits[HWY_MAX_BYTES / 8 + 8];
    for (std::size_t i0 = 0; i0 < p.n; i0 += chunk) {
        const std::size_t n = std::min(chunk, p.n - i0);
        std::size_t m = 0;
        for (std::size_t k = 0; k < n; k += N) {
            const std::size_t i = i0 + k, l = std::min(N, n - k);
            V x, y;
            if (l == N) {
                x = load(p.x + i), y = load(p.y + i);
            } else { // (a padded copy for the last few)
                for (std::size_t j = 0; j < l; ++j) bx[j] = double(p.x[i + j]), by[j] = double(p.y[i + j]);
                x = hn::Load(d, bx), y = hn::Load(d, by);
            }
            hn::Mask<D> open;
            const auto in = classify(d, c, x, y, open);
            const std::size_t nbytes = hn::StoreMaskBits(d, in, bits);
            for (std::size_t q = 0; q < nbytes && 8 * q < l; ++q)
                std::memcpy(out + i + 8 * q, spread.b[bits[q]], std::min<std::size_t>(8, l - 8 * q));
            const auto listed = hn::And(open, hn::FirstN(d, l));
            if (!hn::AllFalse(d, listed))
                m += hn::CompressStore(hn::Iota(du, std::uint64_t(i)), hn::RebindMask(du, listed), du,
                                       list + m);
        }
        for (std::size_t j = 0; j < m; j += N) {
            const std::size_t l = std::min(N, m - j);
            for (std::size_t k = 0; k < l; ++k)
                bx[k] = double(p.x[list[j + k]]), by[k] = double(p.y[list[j + k]]);
            const auto qx = hn::Sub(hn::Load(d, bx), cx), qy = hn::Sub(hn::Load(d, by), cy);
            const auto r = radius(d, c, theta(d, c, qx, qy));
            hn::Store(
                hn::IfThenElseZero(hn::Lt(hn::Add(hn::Mul(qx, qx), hn::Mul(qy, qy)), hn::Mul(r, r)), one), d,
                br);
            for (std::size_t k = 0; k < l; ++k) out[list[j + k]] = br[k] != 0 ? 1 : 0;
        }
    }
}
void inside_f(const Curve& c, fp::Points<const float> p, unsigned char* out) { inside_t(c, p, out); }
void inside_d(const Curve& c, fp::Points<const double> p, unsigned char* out) { inside_t(c, p, out); }

/// The exit from the centre: r(theta(d)) / |d|, +inf for a zero or NaN direction.
HWY_INLINE V from_centre(D d, const Curve& c, V dx, V dy) {
    const auto dd = hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy));
    const auto r = hn::Div(radius(d, c, theta(d, c, dx, dy)), hn::Sqrt(dd));
    return hn::IfThenElse(hn::Gt(dd, hn::Zero(d)), r, hn::Set(d, std::numeric_limits<double>::infinity()));
}

/// The exit from w != 0: the root of f on a bracket, by safeguarded Illinois (the comment at
/// the top of superformula.cpp; shapes/lanes-inl.hpp), stopping within 4 ulps of T.
template <class T>
HWY_INLINE V from_point(D d, const Curve& c, const Origin& o, V dx, V dy) {
    const auto zero = hn::Zero(d), two = hn::Set(d, 2.0);
    const auto wx = hn::Set(d, o.x), wy = hn::Set(d, o.y), norm = hn::Set(d, o.norm);
    auto f = [&](V t) { return f_at(d, c, wx, wy, dx, dy, t); };
    const auto dd = hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy));
    const auto ok = hn::Gt(dd, zero);
    const auto nd = hn::Sqrt(dd);
    // Bracket [lo, hi] with f(lo) < 0 <= f(hi), from r_lo <= r <= r_hi; each end checked.
    auto hi = hn::Div(hn::Add(norm, hn::Set(d, c.r_hi)), nd);
    auto fhi = f(hi);
    auto grow = hn::And(ok, hn::Lt(fhi, zero));
    for (int k = 0; k < 64 && !hn::AllFalse(d, grow); ++k) {
        hi = hn::IfThenElse(grow, hn::Mul(hi, two), hi);
        fhi = hn::IfThenElse(grow, f(hi), fhi);
        grow = hn::And(grow, hn::Lt(fhi, zero));
    }
    auto lo = zero, flo = hn::Set(d, o.f0);
    const auto l = hn::Div(hn::Sub(hn::Set(d, c.r_lo), norm), nd);
    const auto try_l = hn::And(ok, hn::And(hn::Gt(l, zero), hn::Lt(l, hi)));
    if (!hn::AllFalse(d, try_l)) {
        const auto fl = f(l);
        const auto take = hn::And(try_l, hn::Lt(fl, zero));
        lo = hn::IfThenElse(take, l, lo);
        flo = hn::IfThenElse(take, fl, flo);
    }
    const auto rel = hn::Set(d, 4 * double(std::numeric_limits<T>::epsilon()));
    hn::Mask<D> found;
    const auto root = fp_shapes::HWY_NAMESPACE::illinois(d, lo, hi, flo, fhi, ok, rel,
                                                         4 * std::numeric_limits<T>::digits, f, found);
    const auto inf = hn::Set(d, std::numeric_limits<double>::infinity());
    return hn::IfThenElse(ok, root, inf);
}

template <class T>
void ray_t(const Curve& c, const Origin* o, fp::Points<const T> dd, T* t) {
    const D d;
    if (!o)
        blocks(d, dd, t, [&](V dx, V dy) { return from_centre(d, c, dx, dy); });
    else
        blocks(d, dd, t, [&](V dx, V dy) { return from_point<T>(d, c, *o, dx, dy); });
}
void ray_f(const Curve& c, const Origin* o, fp::Points<const float> d, float* t) { ray_t(c, o, d, t); }
void ray_d(const Curve& c, const Origin* o, fp::Points<const double> d, double* t) { ray_t(c, o, d, t); }

void radius_of(const Curve& c, const double* q, double* r) {
    const D d;
    alignas(HWY_MAX_BYTES) double bx[HWY_MAX_BYTES / 8] = {q[0]}, by[HWY_MAX_BYTES / 8] = {q[1]},
                                                     br[HWY_MAX_BYTES / 8];
    hn::Store(radius(d, c, theta(d, c, hn::Load(d, bx), hn::Load(d, by))), d, br);
    *r = br[0];
}

} // namespace fp_superformula::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp_superformula {
HWY_EXPORT(inside_f);
HWY_EXPORT(inside_d);
HWY_EXPORT(ray_f);
HWY_EXPORT(ray_d);
HWY_EXPORT(radius_of);

// (HWY_DYNAMIC_DISPATCH names the kernels unqualified: a build with static dispatch only
// resolves them as N_<target>::name from this namespace.)
void inside(const Curve& c, fp::Points<const float> p, unsigned char* out) {
    HWY_DYNAMIC_DISPATCH(inside_f)(c, p, out);
}
void inside(const Curve& c, fp::Points<const double> p, unsigned char* out) {
    HWY_DYNAMIC_DISPATCH(inside_d)(c, p, out);
}
void ray(const Curve& c, const Origin* w, fp::Points<const float> d, float* t) {
    HWY_DYNAMIC_DISPATCH(ray_f)(c, w, d, t);
}
void ray(const Curve& c, const Origin* w, fp::Points<const double> d, double* t) {
    HWY_DYNAMIC_DISPATCH(ray_d)(c, w, d, t);
}
double radius_at(const Curve& c, double qx, double qy) {
    const double q[2] = {qx, qy};
    double r = 0;
    HWY_DYNAMIC_DISPATCH(radius_of)(c, q, &r);
    return r;
}
} // namespace fp_superformula
#endif // HWY_ONCE
