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
// Per point (the SDK's kernel, fixpoint/kernels.hpp): two evaluations of f, evaluated in the
// order written, no FMA contraction. alpha = 0 adds an exact 0, so GM(0, mu) is exactly x' = y + f(x).
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/kernels.hpp>

namespace {

class GumowskiMira final : public fp::Transform {
public:
    explicit GumowskiMira(const fp::ParamBag& p)
        : alpha_(p.real("alpha")), mu_(p.real("mu")),
          two_one_minus_mu_(2 * (1 - mu_)), k_{alpha_, mu_, two_one_minus_mu_} {}

    // The SDK's Gumowski-Mira kernel (fixpoint/kernels.hpp): the formula a renderer's fused loop
    // runs.
    void apply(fp::Points<float> p, fp::Mask mask) const override { fp::kernels::gumowski_mira(k_, p, mask); }
    void apply(fp::Points<double> p, fp::Mask mask) const override {
        fp::kernels::gumowski_mira(k_, p, mask);
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
