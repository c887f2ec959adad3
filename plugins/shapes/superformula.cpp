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
// Inside: |p - c|^2 < r(theta)^2.
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
// Parameters giving a radius that is not finite and positive at any of the samples are
// refused (e.g. huge a and b, where both terms underflow to 0). A negative n2 or n3 makes r
// tend to 0 where its cosine or sine vanishes, usually between samples: such a set pinches
// to its centre there and is accepted as long as the centre stays inside the sampled kernel.
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
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
    explicit Superformula(const fp::ParamBag& p)
        : m4_(p.real("m") / 4), inv_n1_(1 / p.real("n1")), n2_(p.real("n2")), n3_(p.real("n3")),
          inv_a_(1 / p.real("a")), inv_b_(1 / p.real("b")), scale_(p.real("scale")), c_(p.vec2("centre")) {
        const double rot = p.real("rotation");
        cr_ = std::cos(rot);
        sr_ = std::sin(rot);

        // Radius bounds from dense samples, with a margin for what lies between samples.
        double lo = std::numeric_limits<double>::infinity(), hi = 0;
        for (std::size_t k = 0; k < bound_samples; ++k) {
            const double th = angle(k, bound_samples), r = radius(th);
            check(th, r);
            lo = std::min(lo, r);
            hi = std::max(hi, r);
        }
        r_lo_ = 0.99 * lo;
        r_hi_ = 1.01 * hi;
        size_ = 2 * r_hi_;

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
    }

    fp::Vec2 centre() const override { return c_; }

    bool in_kernel(fp::Vec2 o) const override {
        const double tol = 1e-12 * size_;
        for (std::size_t k = 0; k < kernel_samples; ++k)
            if (!(nx_[k] * (o.x - bx_[k]) + ny_[k] * (o.y - by_[k]) > tol)) return false;
        return true;
    }

    fp::Box bounds() const override { return {c_.x - r_hi_, c_.x + r_hi_, c_.y - r_hi_, c_.y + r_hi_}; }

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
        const T cx = T(c_.x), cy = T(c_.y);
        for (std::size_t i = 0; i < p.n; ++i) {
            const T qx = p.x[i] - cx, qy = p.y[i] - cy;
            const T r = radius(theta(qx, qy));
            out[i] = qx * qx + qy * qy < r * r ? 1 : 0;
        }
    }

    // w = o - c and f(0) are computed once per batch in double, then rounded to T.
    template <class T>
    void ray_t(fp::Vec2 o, fp::Points<const T> d, T* t) const {
        const double wxd = o.x - c_.x, wyd = o.y - c_.y;
        if (wxd == 0 && wyd == 0) {
            for (std::size_t i = 0; i < d.n; ++i) t[i] = from_centre(d.x[i], d.y[i]);
            return;
        }
        const double nwd = std::hypot(wxd, wyd);
        const Origin<T> w{T(wxd), T(wyd), T(nwd), T(nwd - radius(theta(wxd, wyd)))};
        for (std::size_t i = 0; i < d.n; ++i) t[i] = from_point(w, d.x[i], d.y[i]);
    }

    template <class T>
    T from_centre(T dx, T dy) const {
        const T dd = dx * dx + dy * dy;
        return dd > T(0) ? radius(theta(dx, dy)) / std::sqrt(dd) : std::numeric_limits<T>::infinity();
    }

    /// The ray's origin relative to the centre: w, |w| and f(0) = |w| - r(theta(w)) < 0.
    template <class T>
    struct Origin {
        T x, y, norm, f0;
    };

    template <class T>
    T from_point(const Origin<T>& w, T dx, T dy) const {
        const T dd = dx * dx + dy * dy;
        if (!(dd > T(0))) return std::numeric_limits<T>::infinity();
        const T nd = std::sqrt(dd);
        // f(t) = |w + t d| - r(theta(w + t d)): < 0 inside, >= 0 outside. A NaN radius gives
        // a NaN f, which every test below treats as outside.
        auto f = [&](T t) {
            const T qx = w.x + t * dx, qy = w.y + t * dy;
            return std::sqrt(qx * qx + qy * qy) - radius(theta(qx, qy));
        };
        // Bracket [lo, hi] with f(lo) < 0 <= f(hi), from r_lo <= r <= r_hi; each end is
        // checked, since the bounds come from samples.
        T hi = (w.norm + T(r_hi_)) / nd, fhi = f(hi);
        for (int k = 0; k < 64 && fhi < T(0); ++k) fhi = f(hi *= T(2));
        T lo = T(0), flo = w.f0;
        if (const T l = (T(r_lo_) - w.norm) / nd; l > T(0) && l < hi) {
            if (const T fl = f(l); fl < T(0)) lo = l, flo = fl;
        }
        // Illinois (regula falsi that halves the stale end's value), safeguarded: when two
        // steps have not halved the bracket, the next step bisects. Stops at an exact zero or
        // when the bracket is within 4 ulps of hi: the full precision of T, in 5 to 14
        // evaluations of r (mean 9) instead of some 52 for plain bisection in double.
        constexpr T rel = T(4) * std::numeric_limits<T>::epsilon();
        int side = 0;
        bool bisect = false;
        T width_before = hi - lo;
        for (int k = 0; k < 4 * std::numeric_limits<T>::digits; ++k) {
            const T width = hi - lo;
            if (!(width > rel * hi)) break;
            T x = bisect ? lo + width / T(2) : lo + width * (flo / (flo - fhi));
            // At least half the tolerance away from both ends (a regula falsi point that rounds
            // onto an end would otherwise stall the bracket, as in Brent's method).
            const T delta = rel * hi / T(2);
            if (!(x > lo + delta && x < hi - delta))
                x = x != x ? lo + width / T(2) : std::clamp(x, lo + delta, hi - delta);
            if (!(x > lo && x < hi)) break; // lo and hi are adjacent numbers
            const T fx = f(x);
            if (fx == T(0)) return x;
            if (fx < T(0)) {
                lo = x, flo = fx;
                if (side < 0) fhi /= T(2);
                side = -1;
            } else {
                hi = x, fhi = fx;
                if (side > 0) flo /= T(2);
                side = 1;
            }
            if (k % 2 == 1) {
                bisect = hi - lo > width_before / T(2);
                width_before = hi - lo;
            } else {
                bisect = false;
            }
        }
        return hi;
    }

    /// Polar angle of q in the shape's own frame, in (-pi, pi].
    template <class T>
    T theta(T qx, T qy) const {
        const T c = T(cr_), s = T(sr_);
        return std::atan2(c * qy - s * qx, c * qx + s * qy);
    }

    template <class T>
    T radius(T th) const {
        const T u = T(m4_) * th;
        const T A = std::pow(std::abs(std::cos(u) * T(inv_a_)), T(n2_));
        const T B = std::pow(std::abs(std::sin(u) * T(inv_b_)), T(n3_));
        return T(scale_) * std::pow(A + B, T(-inv_n1_));
    }

    /// The k-th of n sample angles, at the middles of n equal steps of (-pi, pi].
    static double angle(std::size_t k, std::size_t n) {
        return -std::numbers::pi + 2 * std::numbers::pi * (double(k) + 0.5) / double(n);
    }

    fp::Vec2 boundary(double th) const {
        const double r = radius(th), x = r * std::cos(th), y = r * std::sin(th);
        return {c_.x + cr_ * x - sr_ * y, c_.y + sr_ * x + cr_ * y};
    }

    static void check(double th, double r) {
        if (!(std::isfinite(r) && r > 0))
            throw fp::ParamError(
                "superformula radius must be finite and positive, but r(theta) = " + fp::number_text(r) +
                " at theta = " + short_num(th) + "; check m, n1, n2, n3, a and b");
    }

    double m4_, inv_n1_, n2_, n3_, inv_a_, inv_b_, scale_;
    fp::Vec2 c_;
    double cr_ = 1, sr_ = 0;
    double r_lo_ = 0, r_hi_ = 0, size_ = 0;
    std::vector<double> bx_, by_, nx_, ny_;
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Superformula>(fp::Kind::Shape, "superformula",
                                           "a curved star-shaped set bounded by Gielis' superformula",
                                           params))
