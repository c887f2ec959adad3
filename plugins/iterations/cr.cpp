// cr: the CR iteration (R. Chugh, V. Kumar, S. Kumar, Strong convergence of a new three step
// iterative scheme in Banach spaces, Amer. J. Comput. Math. 2 (2012) 345-357), paper 02 eq. (7):
//
//     v_n     = (1 - gamma_n) p_n + gamma_n T(p_n),
//     u_n     = (1 - beta_n) T(p_n) + beta_n T(v_n),
//     p_{n+1} = (1 - alpha_n) u_n + alpha_n T(u_n),
//
// with alpha_n, beta_n, gamma_n numbers of the scheme's number system (paper 02 Sec. 4, eq.
// (20): the products are q-system products, computed as 2x2 matrices; see fixpoint/scheme.hpp). Any
// real value is accepted: the paper drops the [0, 1] bounds on purpose. Three applications of
// T per step, all with the same map.
//
// Reductions (tests/unit/test_schemes_b.cpp): alpha = 0 is the S-iteration (eq. (6)) with
// (alpha, beta) = (beta, gamma); alpha = 1 is Picard-S with (beta, gamma); beta = 0 (any
// gamma) is Mann(alpha) applied to T(p): (1 - alpha) T(p) + alpha T(T(p)).
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct Cr final : fp::SchemeBase<Cr> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("alpha", "0.5",
                        "alpha_n: weight of T(u_n) in p_{n+1} = (1 - alpha_n) u_n + alpha_n T(u_n)"),
        fp::scheme::seq("beta", "0.5",
                        "beta_n: weight of T(v_n) in u_n = (1 - beta_n) T(p_n) + beta_n T(v_n)"),
        fp::scheme::seq("gamma", "0.5",
                        "gamma_n: weight of T(p_n) in v_n = (1 - gamma_n) p_n + gamma_n T(p_n)"),
    };

    unsigned applications() const override { return 3; }

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        const fp::Mat2 &alpha = k["alpha"], &beta = k["beta"], &gamma = k["gamma"];
        Buf<T> tp, v;
        c.t(tp, c.p);                               // T(p)
        c.lin(v, identity - gamma, c.p, gamma, tp); // v
        c.t(v, v);                                  // T(v)
        c.lin(tp, identity - beta, tp, beta, v);    // u (in place of T(p))
        c.t(v, tp);                                 // T(u)
        c.lin(c.p, identity - alpha, tp, alpha, v); // p_{n+1}
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<Cr>(
    "cr", "the CR iteration (Chugh-Kumar-Kumar 2012, paper 02 eq. (7)): p <- (1 - alpha) u "
          "+ alpha T(u), u = (1 - beta) T(p) + beta T(v), v = (1 - gamma) p + gamma T(p)"))
