// superformula — a curved star-shaped set bounded by Gielis' superformula (paper 01, Fig.
// 6(d): sets with curved boundaries).
//
// The set is { p : |p - c| < r(theta) } where theta is the polar angle of p - c measured from
// the direction `rotation`, in (-pi, pi], and
//
//     r(theta) = scale * ( |cos(m theta / 4) / a|^n2 + |sin(m theta / 4) / b|^n3 )^(-1/n1).
//
// Every such set is star-shaped with respect to its centre c (a radial segment from c stays
// inside), and c is the default centre of inversion. For non-integer m, r is not 2 pi
// periodic: the boundary then has a radial jump on the ray theta = pi, which is part of the
// boundary like any other; the set stays star-shaped from c.
//
// Inside: |p - c|^2 < r(theta)^2. Bounds of r proven from the parameters (prove_bounds) answer
// first for the points well outside or well inside, without the transcendentals: the same
// answers, for most of a chaos game's points.
//
// Ray exit from o in direction d: when o = c the answer is closed, t = r(theta(d)) / |d|.
// Otherwise we find the root of f(t) = |o + t d - c| - r(theta(o + t d - c)), negative inside
// and non-negative outside; for o in the kernel it changes sign once. The bracket comes from
// r_lo <= r <= r_hi (estimated from dense samples, so each end is checked by evaluating f,
// and the upper end doubled until f >= 0). Inside the bracket we use bisection accelerated
// by the Illinois variant of regula falsi: every step keeps a bracket, and a step that fails
// to halve it (over two steps) is followed by a plain bisection step, so it is never much
// slower than bisection. It stops at an exact zero of f or when the bracket is within 4 ulps
// of T: the full precision of float or double. Measured on the default shape from an
// off-centre o (one core, double): 9 evaluations of r per ray on average, at most 14,
// against 52 for plain bisection; about 1.5 against 7.7 us per ray.
//
// Kernel (approximation): the exact kernel of a curved set has no closed form here. We
// sample the boundary at 2048 angles and take the kernel of that inscribed polygon: o must
// lie strictly on the inner side of every segment's line. Where the boundary is concave
// between two samples the true kernel is slightly smaller than this one, so a centre of
// inversion placed within about a sample spacing of the kernel's edge may see the curve
// graze back; the centre c is always safely inside.
//
// Batches (inside, ray exit) run per SIMD target, one point per lane, with the SDK's own
// atan2, sin, cos, log and exp (fixpoint/simd-math-inl.hpp: libm cannot be called per lane,
// and its bits are not those of any polynomial of ours). The float batches are computed in
// double and rounded at the end; their ray exit stops at float's precision. A lane runs
// exactly the scalar root finder's steps, masked once it has stopped, so the result does not
// depend on the lane count. The set's setup (bounds, kernel samples, outline) uses libm in
// double, once.
//
// Parameters giving a radius that is not finite and positive at any of the samples are
// refused (e.g. huge a and b, where both terms underflow to 0). A negative n2 or n3 makes r
// tend to 0 where its cosine or sine vanishes, usually between samples: such a set pinches
// to its centre there and is accepted as long as the centre stays inside the sampled kernel.
#ifndef FIXPOINT_SUPERFORMULA_ONCE
#define FIXPOINT_SUPERFORMULA_ONCE
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace fp_superformula {

/// The curve's parameters as the batch kernels take them.
struct Curve {
    double m4, inv_n1, n2, n3, inv_a, inv_b, scale; // m / 4, 1 / n1, n2, n3, 1 / a, 1 / b, scale
    double cx, cy, cr, sr;                          // centre; cosine and sine of the rotation
    double r_lo, r_hi; // bounds of the radius (sampled, checked by the root finder)
    /// Squared radii of the proven bounds (see Superformula::prove_bounds): |p - c|^2 >= out2
    /// is outside and < in2 inside for every angle, without r(theta); +inf and 0 when none.
    double out2, in2;
};

/// A ray's origin relative to the centre: w, |w| and f(0) = |w| - r(theta(w)) < 0.
struct Origin {
    double x, y, norm, f0;
};

// Batch kernels, per target (below), dispatched from the class.
void inside(const Curve& c, fp::Points<const float> p, unsigned char* out);
void inside(const Curve& c, fp::Points<const double> p, unsigned char* out);
void ray(const Curve& c, const Origin* w, fp::Points<const float> d, float* t);
void ray(const Curve& c, const Origin* w, fp::Points<const double> d, double* t);
double radius_at(const Curve& c, double qx, double qy);

} // namespace fp_superformula

namespace {

constexpr fp::ParamSpec params[] = {
    fp::param::real("m",
                    "symmetry number: with n2 = n3 and a = b, an integer m gives m lobes; a non-integer m "
                    "leaves a jump at the angle pi")
        .def("5"),
    fp::param::real("n1", "overall exponent; small values pinch the lobes").def("2").above(0),
    fp::param::real("n2", "exponent of the cosine term").def("7"),
    fp::param::real("n3", "exponent of the sine term").def("7"),
    fp::param::real("a", "scale of the cosine term").def("1").above(0),
    fp::param::real("b", "scale of the sine term").def("1").above(0),
    fp::param::real("scale", "overall size").def("1").above(0),
    fp::param::real("rotation", "rotation in radians, counter-clockwise").def("0"),
    fp::param::vec2("centre", "centre of the polar curve; the default centre of inversion").def("[0, 0]"),
};

constexpr std::size_t kernel_samples = 2048;
constexpr std::size_t bound_samples = 16384;

/// Six significant digits, for angles in messages.
std::string short_num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

class Superformula final : public fp::Shape {
public:
    explicit Superformula(const fp::ParamBag& p) : c_(p.vec2("centre")) {
        k_.m4 = p.real("m") / 4, k_.inv_n1 = 1 / p.real("n1"), k_.n2 = p.real("n2"), k_.n3 = p.real("n3");
        k_.inv_a = 1 / p.real("a"), k_.inv_b = 1 / p.real("b"), k_.scale = p.real("scale");
        k_.cx = c_.x, k_.cy = c_.y;
        const double rot = p.real("rotation");
        k_.cr = std::cos(rot);
        k_.sr = std::sin(rot);

        // Radius bounds from dense samples, with a margin for what lies between samples.
        double lo = std::numeric_limits<double>::infinity(), hi = 0;
        for (std::size_t k = 0; k < bound_samples; ++k) {
            const double th = angle(k, bound_samples), r = radius(th);
            check(th, r);
            lo = std::min(lo, r);
            hi = std::max(hi, r);
        }
        k_.r_lo = 0.99 * lo;
        k_.r_hi = 1.01 * hi;
        size_ = 2 * k_.r_hi;

        // The inscribed 2048-gon whose kernel stands for the set's.
        bx_.resize(kernel_samples);
        by_.resize(kernel_samples);
        for (std::size_t k = 0; k < kernel_samples; ++k) {
            const double th = angle(k, kernel_samples);
            check(th, radius(th));
            const fp::Vec2 q = boundary(th);
            bx_[k] = q.x;
            by_[k] = q.y;
        }
        nx_.resize(kernel_samples);
        ny_.resize(kernel_samples);
        for (std::size_t k = 0; k < kernel_samples; ++k) {
            const std::size_t j = (k + 1) % kernel_samples;
            const double ex = bx_[j] - bx_[k], ey = by_[j] - by_[k], len = std::hypot(ex, ey);
            nx_[k] = -ey / len; // inward normal: the samples run counter-clockwise
            ny_[k] = ex / len;
        }
        if (!in_kernel(c_))
            throw fp::ParamError("superformula is too thin near its centre: the centre is not inside the "
                                 "kernel of its sampled boundary");
        prove_bounds();
    }

    fp::Vec2 centre() const override { return c_; }

    bool in_kernel(fp::Vec2 o) const override {
        const double tol = 1e-12 * size_;
        for (std::size_t k = 0; k < kernel_samples; ++k)
            if (!(nx_[k] * (o.x - bx_[k]) + ny_[k] * (o.y - by_[k]) > tol)) return false;
        return true;
    }

    fp::Box bounds() const override {
        return {c_.x - k_.r_hi, c_.x + k_.r_hi, c_.y - k_.r_hi, c_.y + k_.r_hi};
    }

    std::vector<fp::Vec2> outline(std::size_t samples) const override {
        const std::size_t n = std::max<std::size_t>(samples, 16);
        std::vector<fp::Vec2> out(n);
        for (std::size_t k = 0; k < n; ++k) out[k] = boundary(angle(k, n));
        return out;
    }

    void inside(fp::Points<const float> p, unsigned char* out) const override { inside_t(p, out); }
    void inside(fp::Points<const double> p, unsigned char* out) const override { inside_t(p, out); }
    void ray_exit(fp::Vec2 o, fp::Points<const float> d, float* t) const override { ray_t(o, d, t); }
    void ray_exit(fp::Vec2 o, fp::Points<const double> d, double* t) const override { ray_t(o, d, t); }

private:
    template <class T>
    void inside_t(fp::Points<const T> p, unsigned char* out) const {
        fp_superformula::inside(k_, p, out);
    }

    // w = o - c and f(0) are computed once per batch, in double (f(0) with the kernels' own
    // radius, so that the root finder's two ends agree).
    template <class T>
    void ray_t(fp::Vec2 o, fp::Points<const T> d, T* t) const {
        const double wx = o.x - c_.x, wy = o.y - c_.y;
        if (wx == 0 && wy == 0) return fp_superformula::ray(k_, nullptr, d, t);
        const double nw = std::hypot(wx, wy);
        const fp_superformula::Origin w{wx, wy, nw, nw - fp_superformula::radius_at(k_, wx, wy)};
        fp_superformula::ray(k_, &w, d, t);
    }

    /// Bounds of r over every angle that hold for the kernels' r (the inside test's shortcut:
    /// in a chaos game most points lie far from most sets). With c = |cos u| and s = |sin u|,
    /// both at most 1 and the larger at least 1/sqrt(2), each term is bounded:
    ///   n >= 0: (c / a)^n lies in [0, a^-n], and one of the two terms is at least
    ///           min((a sqrt 2)^-n2, (b sqrt 2)^-n3) when both exponents are >= 0;
    ///   n < 0:  (c / a)^n >= a^-n (unbounded above: the set pinches, no inner bound).
    /// r = scale (A + B)^(-1/n1) falls as A + B grows, so a lower bound L of A + B gives
    /// r <= scale L^(-1/n1), an upper one U gives r >= scale U^(-1/n1). A margin of 1e-3 of
    /// r covers the kernels' rounding (their transcendentals are good to about 1e-13 of r
    /// within the limits below, where the exponents stay moderate); outside those limits, or
    /// where a bound is not a normal number, the test computes r(theta) for every point.
    void prove_bounds() {
        k_.out2 = std::numeric_limits<double>::infinity();
        k_.in2 = 0;
        const double n2 = k_.n2, n3 = k_.n3, e = -k_.inv_n1;
        if (!(k_.inv_n1 <= 1e3 && std::abs(n2) <= 1e3 && std::abs(n3) <= 1e3 &&
              std::abs(k_.m4) * std::numbers::pi <= 1e5))
            return;
        const double h = std::numbers::sqrt2 / 2;
        double lower = 0;
        if (n2 < 0) lower = std::max(lower, std::pow(k_.inv_a, n2));
        if (n3 < 0) lower = std::max(lower, std::pow(k_.inv_b, n3));
        if (n2 >= 0 && n3 >= 0) lower = std::min(std::pow(k_.inv_a * h, n2), std::pow(k_.inv_b * h, n3));
        const double r_max = k_.scale * std::pow(lower, e) * (1 + 1e-3);
        if (std::isnormal(lower) && std::isnormal(r_max * r_max)) k_.out2 = r_max * r_max;
        if (n2 < 0 || n3 < 0) return;
        const double upper = std::pow(k_.inv_a, n2) + std::pow(k_.inv_b, n3);
        const double r_min = k_.scale * std::pow(upper, e) * (1 - 1e-3);
        if (std::isnormal(upper) && std::isnormal(r_min * r_min)) k_.in2 = r_min * r_min;
    }

    /// r(theta) with libm, for the setup (the batches use the kernels' own functions).
    double radius(double th) const {
        const double u = k_.m4 * th;
        const double A = std::pow(std::abs(std::cos(u) * k_.inv_a), k_.n2);
        const double B = std::pow(std::abs(std::sin(u) * k_.inv_b), k_.n3);
        return k_.scale * std::pow(A + B, -k_.inv_n1);
    }

    /// The k-th of n sample angles, at the middles of n equal steps of (-pi, pi].
    static double angle(std::size_t k, std::size_t n) {
        return -std::numbers::pi + 2 * std::numbers::pi * (double(k) + 0.5) / double(n);
    }

    fp::Vec2 boundary(double th) const {
        const double r = radius(th), x = r * std::cos(th), y = r * std::sin(th);
        return {c_.x + k_.cr * x - k_.sr * y, c_.y + k_.sr * x + k_.cr * y};
    }

    static void check(double th, double r) {
        if (!(std::isfinite(r) && r > 0))
            throw fp::ParamError(
                "superformula radius must be finite and positive, but r(theta) = " + fp::number_text(r) +
                " at theta = " + short_num(th) + "; check m, n1, n2, n3, a and b");
    }

    fp::Vec2 c_;
    fp_superformula::Curve k_{}; ///< the parameters, as the batch kernels take them too
    double size_ = 0;
    std::vector<double> bx_, by_, nx_, ny_;
};

} // namespace
#endif // FIXPOINT_SUPERFORMULA_ONCE

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "superformula.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

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

/// Runs body(x, y, m) on blocks of m <= Lanes(d) points converted to double lanes (a padded
/// copy: the kernels are dominated by their transcendentals, not by the loads), and writes
/// back the m results body returns, rounded to the batch's type.
template <class T, class Out, class F>
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

/// The inside test: |p - c|^2 against the proven bounds first (Curve::out2, in2), and
/// r(theta) only for the points between them, gathered into whole vectors: in a chaos game
/// most points lie far outside most sets. Each point's answer is the one r(theta) gives.
template <class T>
void inside_t(const Curve& c, fp::Points<const T> p, unsigned char* out) {
    const D d;
    const std::size_t N = hn::Lanes(d);
    const auto cx = hn::Set(d, c.cx), cy = hn::Set(d, c.cy), one = hn::Set(d, 1.0);
    constexpr std::size_t chunk = 256;
    std::uint32_t list[chunk];
    alignas(HWY_MAX_BYTES) double bx[HWY_MAX_BYTES / 8] = {}, by[HWY_MAX_BYTES / 8] = {};
    alignas(HWY_MAX_BYTES) double br[HWY_MAX_BYTES / 8];
    for (std::size_t i0 = 0; i0 < p.n; i0 += chunk) {
        const std::size_t n = std::min(chunk, p.n - i0);
        std::size_t m = 0;
        for (std::size_t k = 0; k < n; ++k) {
            const double qx = double(p.x[i0 + k]) - c.cx, qy = double(p.y[i0 + k]) - c.cy;
            const double q2 = qx * qx + qy * qy;
            const bool in = q2 < c.in2;
            out[i0 + k] = in ? 1 : 0;
            list[m] = std::uint32_t(i0 + k);
            m += (in || q2 >= c.out2) ? 0 : 1; // (NaN: listed)
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
/// the top of this file), stopping within 4 ulps of T. Each lane takes exactly the steps the
/// scalar method would; a lane that has stopped is frozen (masks), and the loop ends when
/// every lane has.
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
    const auto one = hn::Set(d, 1.0), minus_one = hn::Set(d, -1.0);
    auto side = zero;                 // -1: lo moved last, 1: hi moved last, 0: neither yet
    auto bisect = hn::Lt(zero, zero); // all false
    auto width_before = hn::Sub(hi, lo);
    auto active = ok, found = bisect;
    auto root = zero;
    for (int k = 0; k < 4 * std::numeric_limits<T>::digits; ++k) {
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
    const auto inf = hn::Set(d, std::numeric_limits<double>::infinity());
    return hn::IfThenElse(found, root, hn::IfThenElse(ok, hi, inf));
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

FIXPOINT_PLUGIN(fp::describe<Superformula>(fp::Kind::Shape, "superformula",
                                           "a curved star-shaped set bounded by Gielis' superformula",
                                           params))
#endif // HWY_ONCE
