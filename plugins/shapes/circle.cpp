// circle — the disc |p - c| < R (paper 01, Sec. 2 and 3).
//
// The classical set of circle inversion fractals. Its kernel is the whole open disc, so any
// interior point may serve as the centre of inversion o (paper 01, Fig. 4: moving o deforms
// the fractal).
//
// Ray exit: with w = o - c, the boundary hit o + t d solves |w + t d|^2 = R^2, i.e.
//
//     a t^2 + 2 h t + c0 = 0,   a = d.d,  h = w.d,  c0 = w.w - R^2 < 0 (o inside).
//
// The roots have product c0 / a < 0, so exactly one is positive: t = (-h + sqrt(h^2 - a c0)) / a.
// When h > 0 the numerator -h + sqrt(...) cancels (o near the far side, d pointing outwards
// along w), so we use the equivalent t = -c0 / (h + sqrt(h^2 - a c0)) there, as in the
// stable form of the quadratic formula. Both forms then add quantities of one sign only.
// With o = c this gives t = R / |d|, and the inversion reduces to eq. (2); inversion_factor()
// then returns R^2 / |d|^2 directly (no square root, no squaring), so that inversion in a
// circle about its own centre is eq. (2) to the last bit.
//
// as_circle() reports (c, R^2) with R^2 = radius * radius in double, the value inside() and
// inversion_factor() round to the batch's type: a renderer's fused loop for inversions in
// circles (chaos-game) computes the same bits from it. Keep the three in step.
#include <fixpoint/fixpoint.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace {

constexpr fp::ParamSpec params[] = {
    fp::param::vec2("centre", "centre of the circle").def("[0, 0]"),
    fp::param::real("radius", "radius of the circle").def("1").above(0),
};

class Circle final : public fp::Shape {
public:
    explicit Circle(const fp::ParamBag& p) : c_(p.vec2("centre")), r_(p.real("radius")), r2_(r_ * r_) {}

    fp::Vec2 centre() const override { return c_; }

    bool as_circle(fp::Vec2& centre, double& radius2) const override {
        centre = c_;
        radius2 = r2_;
        return true;
    }

    bool in_kernel(fp::Vec2 o) const override {
        const double wx = o.x - c_.x, wy = o.y - c_.y;
        return wx * wx + wy * wy < r2_;
    }

    fp::Box bounds() const override { return {c_.x - r_, c_.x + r_, c_.y - r_, c_.y + r_}; }

    std::vector<fp::Vec2> outline(std::size_t samples) const override {
        const std::size_t n = samples < 8 ? 8 : samples;
        std::vector<fp::Vec2> out(n);
        for (std::size_t k = 0; k < n; ++k) {
            const double a = 2 * std::numbers::pi * double(k) / double(n);
            out[k] = {c_.x + r_ * std::cos(a), c_.y + r_ * std::sin(a)};
        }
        return out;
    }

    void inside(fp::Points<const float> p, unsigned char* out) const override { inside_t(p, out); }
    void inside(fp::Points<const double> p, unsigned char* out) const override { inside_t(p, out); }
    void ray_exit(fp::Vec2 o, fp::Points<const float> d, float* t) const override { ray_t(o, d, t); }
    void ray_exit(fp::Vec2 o, fp::Points<const double> d, double* t) const override { ray_t(o, d, t); }
    void inversion_factor(fp::Vec2 o, fp::Points<const float> d, float* s) const override {
        factor_t(o, d, s);
    }
    void inversion_factor(fp::Vec2 o, fp::Points<const double> d, double* s) const override {
        factor_t(o, d, s);
    }

private:
    template <class T>
    void inside_t(fp::Points<const T> p, unsigned char* out) const {
        const T cx = T(c_.x), cy = T(c_.y), r2 = T(r2_);
        for (std::size_t i = 0; i < p.n; ++i) {
            const T dx = p.x[i] - cx, dy = p.y[i] - cy;
            out[i] = dx * dx + dy * dy < r2 ? 1 : 0;
        }
    }

    // w = o - c and c0 are computed once per batch in double and only then rounded to T, so
    // the float path keeps its precision for a small circle far from the origin.
    template <class T>
    void ray_t(fp::Vec2 o, fp::Points<const T> d, T* t) const {
        const double wxd = o.x - c_.x, wyd = o.y - c_.y;
        const T wx = T(wxd), wy = T(wyd), c0 = T((wxd * wxd + wyd * wyd) - r2_);
        for (std::size_t i = 0; i < d.n; ++i) t[i] = ray_pt(wx, wy, c0, d.x[i], d.y[i]);
    }

    template <class T>
    void factor_t(fp::Vec2 o, fp::Points<const T> d, T* s) const {
        if (o.x != c_.x || o.y != c_.y) {
            ray_t(o, d, s);
            for (std::size_t i = 0; i < d.n; ++i) s[i] *= s[i];
            return;
        }
        const T r2 = T(r2_);
        for (std::size_t i = 0; i < d.n; ++i) s[i] = r2 / (d.x[i] * d.x[i] + d.y[i] * d.y[i]);
    }

    template <class T>
    static T ray_pt(T wx, T wy, T c0, T dx, T dy) {
        const T a = dx * dx + dy * dy;
        const T h = wx * dx + wy * dy;
        const T s = std::sqrt(h * h - a * c0);
        const T t = h <= T(0) ? (s - h) / a : -c0 / (h + s);
        return a > T(0) ? t : std::numeric_limits<T>::infinity();
    }

    fp::Vec2 c_;
    double r_, r2_;
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Circle>(fp::Kind::Shape, "circle", "the disc of given centre and radius",
                                     params))
