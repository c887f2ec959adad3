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
#include "superformula/curve.hpp"

#define FIXPOINT_SUPERFORMULA_ONCE
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

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

    /// Bounds of r that hold for the kernels' r, for the inside test's shortcut (in a chaos
    /// game most points lie far from most sets): over every angle, and over each of the
    /// sectors of Curve::sectors. With c = |cos u| and s = |sin u| (u = m theta / 4), the
    /// terms (c / a)^n2 and (s / b)^n3 are monotonic in c and s, so ranges of c and s bound
    /// them (interval arithmetic); over every angle, c and s lie in [0, 1] and the larger is
    /// at least 1/sqrt(2), so with n2, n3 >= 0 one term is at least min((a sqrt 2)^-n2,
    /// (b sqrt 2)^-n3). r = scale (A + B)^(-1/n1) falls as A + B grows: bounds of A + B give
    /// bounds of r. A margin of 1e-3 of r covers the kernels' rounding (their transcendentals
    /// are good to about 1e-10 of r within the limits below, where the exponents stay
    /// moderate); outside those limits, or where a bound is not finite and positive, the
    /// test computes r(theta) for every point.
    void prove_bounds() {
        k_.out2 = std::numeric_limits<double>::infinity();
        k_.in2 = 0;
        for (std::size_t k = 0; k < fp_superformula::sector_count; ++k)
            k_.sectors[2 * k] = k_.in2, k_.sectors[2 * k + 1] = k_.out2; // (none: every point computes r)
        const double n2 = k_.n2, n3 = k_.n3;
        if (!(k_.inv_n1 <= 1e3 && std::abs(n2) <= 1e3 && std::abs(n3) <= 1e3 &&
              std::abs(k_.m4) * std::numbers::pi <= 1e5))
            return;
        const double h = std::numbers::sqrt2 / 2;
        double lo = 0, hi = 0; // A + B over every angle
        if (n2 >= 0 && n3 >= 0) lo = std::min(std::pow(k_.inv_a * h, n2), std::pow(k_.inv_b * h, n3));
        // The range [t0, t1] of (b inv)^n for b in [b0, b1]. With n < 0 the upper end grows
        // without bound as b0 nears 0, and the kernels' cos and sin, good to about 1e-16
        // there, would stray from it by more than the margin: below 1e-6 it is left open.
        const auto term = [](double b0, double b1, double inv, double n, double& t0, double& t1) {
            t0 = std::pow(n >= 0 ? b0 * inv : b1 * inv, n);
            t1 = n < 0 && b0 < 1e-6 ? std::numeric_limits<double>::infinity()
                                    : std::pow(n >= 0 ? b1 * inv : b0 * inv, n);
        };
        double a0, a1, b0, b1;
        term(0, 1, k_.inv_a, n2, a0, a1);
        term(0, 1, k_.inv_b, n3, b0, b1);
        lo = std::max(lo, a0 + b0), hi = a1 + b1;
        squared(lo, hi, k_.in2, k_.out2);
        // Per sector: the angles between the sector's ends (of the kernel's pseudo-angle,
        // inverted exactly here), widened by 1e-9 for the pseudo-angle's rounding.
        const auto angle_of = [](double a) { // the inverse of the pseudo-angle
            if (a >= -1 && a <= 1) return std::atan2(a, 1 - std::abs(a));
            return a > 1 ? std::atan2(2 - a, 1 - a) : std::atan2(-2 - a, 1 + a);
        };
        const double pi = std::numbers::pi;
        for (std::size_t k = 0; k < fp_superformula::sector_count; ++k) {
            double& in2 = k_.sectors[2 * k];
            double& out2 = k_.sectors[2 * k + 1];
            in2 = k_.in2, out2 = k_.out2;
            // (The two sectors at theta = +-pi keep the global bounds: the kernels' atan2
            // may give -pi or pi there, and r jumps there when m is not an integer.)
            if (k == 0 || k + 1 == fp_superformula::sector_count) continue;
            const double step = 4.0 / double(fp_superformula::sector_count);
            const double t0 = angle_of(-2 + step * double(k)) - 1e-9,
                         t1 = angle_of(-2 + step * double(k + 1)) + 1e-9;
            const double u0 = std::min(k_.m4 * t0, k_.m4 * t1), u1 = std::max(k_.m4 * t0, k_.m4 * t1);
            // Does [u0, u1] hold a multiple of pi (plus `off`)?
            const auto holds = [&](double off) {
                return std::floor((u1 - off) / pi) >= std::ceil((u0 - off) / pi);
            };
            const double c0 = std::abs(std::cos(u0)), c1 = std::abs(std::cos(u1));
            const double s0 = std::abs(std::sin(u0)), s1 = std::abs(std::sin(u1));
            const bool wide = u1 - u0 >= pi;
            const double cmin = wide || holds(pi / 2) ? 0 : std::min(c0, c1),
                         cmax = wide || holds(0) ? 1 : std::max(c0, c1);
            const double smin = wide || holds(0) ? 0 : std::min(s0, s1),
                         smax = wide || holds(pi / 2) ? 1 : std::max(s0, s1);
            term(cmin, cmax, k_.inv_a, n2, a0, a1);
            term(smin, smax, k_.inv_b, n3, b0, b1);
            double si, so;
            squared(a0 + b0, a1 + b1, si, so);
            in2 = std::max(in2, si), out2 = std::min(out2, so);
        }
    }

    /// Squared bounds of r with the margin from bounds [lo, hi] of A + B: in2 = 0 and
    /// out2 = +inf where a bound is not finite and positive (or A + B leaves the range where
    /// the kernels' pow stays accurate).
    void squared(double lo, double hi, double& in2, double& out2) const {
        const double r_max = k_.scale * std::pow(lo, -k_.inv_n1) * (1 + 1e-3);
        const double r_min = k_.scale * std::pow(hi, -k_.inv_n1) * (1 - 1e-3);
        const bool lo_ok = lo >= 1e-300 && lo <= 1e300, hi_ok = hi >= 1e-300 && hi <= 1e300;
        out2 = lo_ok && r_max > 0 && std::isfinite(r_max * r_max) ? r_max * r_max
                                                                  : std::numeric_limits<double>::infinity();
        in2 = hi_ok && r_min > 0 && std::isfinite(r_min * r_min) ? r_min * r_min : 0;
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

FIXPOINT_PLUGIN(fp::describe<Superformula>(fp::Kind::Shape, "superformula",
                                           "a curved star-shaped set bounded by Gielis' superformula",
                                           params))
