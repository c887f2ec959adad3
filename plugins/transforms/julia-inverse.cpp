// julia-inverse — a branch of the inverse of the quadratic map f(z) = z^2 + c:
//
//     branch 0:  z -> +sqrt(z - c)       branch 1:  z -> -sqrt(z - c),
//
// sqrt the principal square root (real part >= 0). The two branches are the inverse iteration
// method's IFS (paper 03's closing remark: "similar results can be obtained for other types of
// fractals, e.g. Julia or Mandelbrot sets"): f maps the Julia set J_c onto itself twice over,
// so J_c is invariant under both branches, and away from the critical value c they contract
// near J_c (|d sqrt(w)/dw| = 1 / (2 |sqrt w|)): the chaos game over the two, each with weight
// 1/2, draws J_c, densest where the inverse iteration lingers (its points are distributed by
// the harmonic measure of J_c, as for the Julia sets of every polynomial). Two such pairs of
// nearby c values, as two IFS of the superfractal renderer (`ifs: 0` and `ifs: 1`), give
// V-variable Julia children, as paper 03 does with its Gumowski-Mira maps; any of paper 02's
// iteration schemes runs over the branches in the chaos game (a Mann iteration of the inverse
// maps draws another set, which need not lie on J_c).
//
// The square root of w = a + i b, stably in both half-planes (no difference of nearly equal
// numbers): with t = sqrt((|w| + |a|) / 2),
//
//     a >= 0:  sqrt w = t + i b / (2 t)        a < 0:  sqrt w = |b| / (2 t) + i copysign(t, b),
//
// and sqrt 0 = 0. Every operation is IEEE (square roots and quotients correctly rounded, no
// FMA): the same bits on every instruction set, in float and double. (|w| is sqrt(a^2 + b^2):
// it overflows only for |w| beyond 1e154 in double, 1e19 in float, far outside any Julia set;
// such a point becomes infinite and the renderer restarts its chain.)
#include <fixpoint/fixpoint.hpp>

#include <cmath>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "julia-inverse.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include <fixpoint/simd-inl.hpp>

HWY_BEFORE_NAMESPACE();
namespace fp_julia::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace fs = fp::simd::HWY_NAMESPACE;

/// z <- s sqrt(z - c), s = +1 or -1, on the active points.
template <class T>
void apply_t(T cr, T ci, bool negative, fp::Points<T> p, fp::Mask mask) {
    const hn::ScalableTag<T> d;
    const auto vcr = hn::Set(d, cr), vci = hn::Set(d, ci), zero = hn::Zero(d), half = hn::Set(d, T(0.5)),
               two = hn::Set(d, T(2));
    fs::map_points(d, p, mask, [&](auto& x, auto& y) {
        const auto a = hn::Sub(x, vcr), b = hn::Sub(y, vci);
        const auto r = hn::Sqrt(hn::Add(hn::Mul(a, a), hn::Mul(b, b)));
        const auto t = hn::Sqrt(hn::Mul(hn::Add(r, hn::Abs(a)), half));
        const auto q = hn::Div(b, hn::Mul(two, t)); // b / 2t (NaN where w = 0: not kept)
        const auto right = hn::Ge(a, zero);
        auto re = hn::IfThenElse(right, t, hn::Abs(q));
        auto im = hn::IfThenElse(right, q, hn::CopySign(t, b));
        const auto origin = hn::Eq(t, zero);
        re = hn::IfThenElse(origin, zero, re);
        im = hn::IfThenElse(origin, zero, im);
        x = negative ? hn::Neg(re) : re;
        y = negative ? hn::Neg(im) : im;
    });
}
void apply_f(float cr, float ci, bool negative, fp::Points<float> p, fp::Mask mask) {
    apply_t(cr, ci, negative, p, mask);
}
void apply_d(double cr, double ci, bool negative, fp::Points<double> p, fp::Mask mask) {
    apply_t(cr, ci, negative, p, mask);
}

} // namespace fp_julia::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp_julia {
HWY_EXPORT(apply_f);
HWY_EXPORT(apply_d);
} // namespace fp_julia

namespace {
// (HWY_DYNAMIC_DISPATCH names the kernels unqualified; a build with static dispatch only
// resolves them as N_<target>::name from here.)
using namespace fp_julia;

class JuliaInverse final : public fp::Transform {
public:
    explicit JuliaInverse(const fp::ParamBag& p) : c_(p.vec2("c")), negative_(p.integer("branch") == 1) {
        // J_c lies in the disc |z| <= max(2, |c|) (outside it |f(z)| > |z| grows to infinity).
        const double R = std::fmax(2.0, std::hypot(c_.x, c_.y));
        domain_ = {-R, R, -R, R};
    }

    void apply(fp::Points<float> p, fp::Mask mask) const override {
        HWY_DYNAMIC_DISPATCH(apply_f)(float(c_.x), float(c_.y), negative_, p, mask);
    }
    void apply(fp::Points<double> p, fp::Mask mask) const override {
        HWY_DYNAMIC_DISPATCH(apply_d)(c_.x, c_.y, negative_, p, mask);
    }

    fp::Box sample_domain() const override { return domain_; }

private:
    fp::Vec2 c_;
    bool negative_;
    fp::Box domain_;
};

constexpr fp::ParamSpec params[] = {
    fp::param::vec2("c", "c of f(z) = z^2 + c, as [re, im]: the Julia set J_c the two branches draw")
        .def("[-0.123, 0.745]"),
    fp::param::integer("branch", "which inverse of f: 0 is +sqrt(z - c) (real part >= 0), 1 is -sqrt(z - c)")
        .def("0")
        .min(0)
        .max(1),
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<JuliaInverse>(fp::Kind::Transform, "julia-inverse",
                                           "a branch of the inverse of z^2 + c (the inverse iteration "
                                           "method's IFS: both branches draw the Julia set J_c)",
                                           params)
                    .with_example("{c: [-0.123, 0.745], branch: 1}"))
#endif
