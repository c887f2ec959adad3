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
#include <fixpoint/kernels.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

// The inside test and the inversion factor are the SDK's kernels (fixpoint/kernels.hpp); the ray
// exit from another point is in the per-target section below (fixpoint/simd-inl.hpp), compiled
// for every instruction set of the build and dispatched at run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "circle.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include <fixpoint/kernels-inl.hpp>
#include <fixpoint/simd-inl.hpp>

HWY_BEFORE_NAMESPACE();
namespace fp_circle::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace fs = fp::simd::HWY_NAMESPACE;

/// The ray exit from o (w = o - c, c0 = w.w - R^2): a = d.d, h = w.d, s = sqrt(h^2 - a c0),
/// t = (s - h) / a when h <= 0, else -c0 / (h + s); +inf for a zero direction. Both branches
/// are computed and one kept (the other's division by zero, if any, is discarded).
template <class T>
void ray_t(T wx, T wy, T c0, fp::Points<const T> dd, T* t) {
    const hn::ScalableTag<T> d;
    const auto vwx = hn::Set(d, wx), vwy = hn::Set(d, wy), vc0 = hn::Set(d, c0), zero = hn::Zero(d);
    const auto inf = hn::Set(d, std::numeric_limits<T>::infinity());
    fs::eval_points(d, dd, t, [&](auto dx, auto dy) {
        const auto a = fp::kernels::HWY_NAMESPACE::sq_norm(dx, dy);
        const auto h = hn::Add(hn::Mul(vwx, dx), hn::Mul(vwy, dy));
        const auto s = hn::Sqrt(hn::Sub(hn::Mul(h, h), hn::Mul(a, vc0)));
        const auto r =
            hn::IfThenElse(hn::Le(h, zero), hn::Div(hn::Sub(s, h), a), hn::Div(hn::Neg(vc0), hn::Add(h, s)));
        return hn::IfThenElse(hn::Gt(a, zero), r, inf);
    });
}
void ray_f(float wx, float wy, float c0, fp::Points<const float> dd, float* t) { ray_t(wx, wy, c0, dd, t); }
void ray_d(double wx, double wy, double c0, fp::Points<const double> dd, double* t) {
    ray_t(wx, wy, c0, dd, t);
}

} // namespace fp_circle::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp_circle {
HWY_EXPORT(ray_f);
HWY_EXPORT(ray_d);
} // namespace fp_circle

namespace {
// (HWY_DYNAMIC_DISPATCH names the kernels unqualified; a build with static dispatch only
// resolves them as N_<target>::name from here.)
using namespace fp_circle;

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
    // The SDK's circle kernels (fixpoint/kernels.hpp): the formulas a renderer's fused loop runs.
    void inside_t(fp::Points<const float> p, unsigned char* out) const {
        fp::kernels::in_circle(float(c_.x), float(c_.y), float(r2_), p, out);
    }
    void inside_t(fp::Points<const double> p, unsigned char* out) const {
        fp::kernels::in_circle(c_.x, c_.y, r2_, p, out);
    }

    // w = o - c and c0 are computed once per batch in double and only then rounded to T, so
    // the float path keeps its precision for a small circle far from the origin.
    void ray_t(fp::Vec2 o, fp::Points<const float> d, float* t) const {
        const double wxd = o.x - c_.x, wyd = o.y - c_.y;
        HWY_DYNAMIC_DISPATCH(ray_f)
        (float(wxd), float(wyd), float((wxd * wxd + wyd * wyd) - r2_), d, t);
    }
    void ray_t(fp::Vec2 o, fp::Points<const double> d, double* t) const {
        const double wxd = o.x - c_.x, wyd = o.y - c_.y;
        HWY_DYNAMIC_DISPATCH(ray_d)(wxd, wyd, (wxd * wxd + wyd * wyd) - r2_, d, t);
    }

    template <class T>
    void factor_t(fp::Vec2 o, fp::Points<const T> d, T* s) const {
        if (o.x != c_.x || o.y != c_.y) {
            ray_t(o, d, s);
            for (std::size_t i = 0; i < d.n; ++i) s[i] *= s[i];
            return;
        }
        fp::kernels::inversion_factor(T(r2_), d, s);
    }

    fp::Vec2 c_;
    double r_, r2_;
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Circle>(fp::Kind::Shape, "circle", "the disc of given centre and radius",
                                     params))
#endif // HWY_ONCE
