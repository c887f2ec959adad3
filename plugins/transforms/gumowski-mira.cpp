// gumowski-mira — the Gumowski–Mira map GM(alpha, mu) (paper 03, eq. (1)):
//
//     f(x)  = mu x + 2 (1 - mu) x^2 / (1 + x^2),
//     x'    = y + alpha (1 - 0.05 y^2) y + f(x),
//     y'    = -x + f(x').
//
// The constant 0.05 is the paper's fixed sigma (Gumowski and Mira's damping term
// alpha (1 - sigma y^2) y, with sigma = 0.05 in paper 03); it is not a parameter because the
// paper never varies it. Note that y' uses the new x', not x.
//
// With alpha = 0 the map preserves area (its Jacobian determinant is f'(x) f'(x') -
// (f'(x) f'(x') - 1) = 1): an orbit neither converges nor spreads over an attractor; it
// stays on its own invariant curve or chaotic band, so the picture depends on the start
// point (paper 03 Fig. 1 starts at (0, 0.5)). As a map of one orbit, render it with
// chaos-game, one map, `start` and `skip: 0`; several GM maps with weights are the GM
// superfractal algorithm of paper 03 Sec. III.
//
// Render single orbits in double (chaos-game `precision: double`): in float the orbit is
// one of the rounded map, which falls into a cycle (GM(0, -0.15) from (0, 0.5) repeats
// itself after 14 839 float steps, the other Fig. 1 parameters after 2.6 M to 128 M steps;
// in double none shows in 3e8 steps).
//
// The map is defined and finite at every finite point (1 + x^2 >= 1), so the sample
// domain is any box; [-20, 20]^2 is where the orbits of the paper's figures spend most of
// their time. Orbits can still run away: with alpha != 0 the term -0.05 alpha y^3 grows
// without bound for large |y| (GM(0.5, -0.31) from (0, 30) overflows in a few steps); the
// renderer counts non-finite points and restarts their chains.
//
// Per point (the kernels below): two evaluations of f, evaluated in the order written, no
// FMA contraction. alpha = 0 adds an exact 0, so GM(0, mu) is exactly x' = y + f(x).
#include <fixpoint/fixpoint.hpp>

// The batch loops are in the per-target section below (fixpoint/simd-inl.hpp), dispatched
// at run time; the coefficients travel as an array of doubles, rounded to the batch's type.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "gumowski-mira.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include <fixpoint/simd-inl.hpp>

HWY_BEFORE_NAMESPACE();
namespace fp_gm::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace fs = fp::simd::HWY_NAMESPACE;

/// k = {alpha, mu, 2 (1 - mu)}: f(x) = mu x + 2 (1 - mu) x^2 / (1 + x^2);
/// x' = y + alpha (1 - 0.05 y y) y + f(x), y' = -x + f(x'), in the order written.
template <class T>
void apply_t(const double* k, fp::Points<T> p, fp::Mask mask) {
    const hn::ScalableTag<T> d;
    const auto alpha = hn::Set(d, T(k[0])), mu = hn::Set(d, T(k[1])), tomm = hn::Set(d, T(k[2]));
    const auto one = hn::Set(d, T(1)), sigma = hn::Set(d, T(0.05));
    const auto f = [&](auto x) {
        const auto x2 = hn::Mul(x, x);
        return hn::Add(hn::Mul(mu, x), hn::Div(hn::Mul(tomm, x2), hn::Add(one, x2)));
    };
    fs::map_points(d, p, mask, [&](auto& x, auto& y) {
        const auto damp = hn::Mul(hn::Mul(alpha, hn::Sub(one, hn::Mul(hn::Mul(sigma, y), y))), y);
        const auto nx = hn::Add(hn::Add(y, damp), f(x));
        const auto ny = hn::Add(hn::Neg(x), f(nx));
        x = nx;
        y = ny;
    });
}
void apply_f(const double* k, fp::Points<float> p, fp::Mask mask) { apply_t(k, p, mask); }
void apply_d(const double* k, fp::Points<double> p, fp::Mask mask) { apply_t(k, p, mask); }

} // namespace fp_gm::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp_gm {
HWY_EXPORT(apply_f);
HWY_EXPORT(apply_d);
} // namespace fp_gm

namespace {
// (HWY_DYNAMIC_DISPATCH names the kernels unqualified; a build with static dispatch only
// resolves them as N_<target>::name from here.)
using namespace fp_gm;

class GumowskiMira final : public fp::Transform {
public:
    explicit GumowskiMira(const fp::ParamBag& p)
        : alpha_(p.real("alpha")), mu_(p.real("mu")),
          two_one_minus_mu_(2 * (1 - mu_)), k_{alpha_, mu_, two_one_minus_mu_} {}

    void apply(fp::Points<float> p, fp::Mask mask) const override {
        HWY_DYNAMIC_DISPATCH(apply_f)(k_, p, mask);
    }
    void apply(fp::Points<double> p, fp::Mask mask) const override {
        HWY_DYNAMIC_DISPATCH(apply_d)(k_, p, mask);
    }

    fp::KnownKernel kernel() const override {
        fp::KnownKernel k;
        k.kind = fp::KnownKernel::Kind::gumowski_mira;
        for (int i = 0; i < 3; ++i) k.c[i] = k_[i];
        return k;
    }

    fp::Box sample_domain() const override { return {-20, 20, -20, 20}; }

private:
    double alpha_, mu_, two_one_minus_mu_;
    double k_[3]; ///< {alpha, mu, 2 (1 - mu)} for the kernels
};

constexpr fp::ParamSpec params[] = {
    fp::param::real("alpha", "alpha of eq. (1): weight of the damping term alpha (1 - 0.05 y^2) y").def("0"),
    fp::param::real("mu", "mu of eq. (1): f(x) = mu x + 2 (1 - mu) x^2 / (1 + x^2)").def("-0.31"),
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<GumowskiMira>(fp::Kind::Transform, "gumowski-mira",
                                           "the Gumowski-Mira map GM(alpha, mu), paper 03 eq. (1)", params)
                    .with_example("{alpha: 0.008, mu: -0.7501}"))
#endif // HWY_ONCE
