// suantai: the three-step iteration of S. Suantai (Weak and strong convergence criteria of
// Noor iteration for asymptotically nonexpansive mappings, J. Math. Anal. Appl. 311 (2005)
// 506-517), paper 02 eq. (5):
//
//     v_n     = (1 - gamma_n) p_n + gamma_n T(p_n),
//     u_n     = (1 - a_n - b_n) p_n + a_n T(v_n) + b_n T(p_n),
//     p_{n+1} = (1 - alpha_n - beta_n) p_n + alpha_n T(u_n) + beta_n T(v_n),
//
// with the five parameters numbers of the scheme's number system (paper 02 Sec. 4; products
// are 2x2 matrices, see fixpoint/scheme.hpp). Any real value is accepted: the paper drops the bounds
// (alpha + beta, a + b in [0, 1]) on purpose. Three applications of T per step (T(p), T(v),
// T(u)), all with the same map. (Suantai's paper states the scheme for asymptotically
// nonexpansive maps with T^n in place of T; paper 02 uses T, as here.)
//
// Reductions (tests/unit/test_schemes_b.cpp): beta = b = 0 is Noor (alpha, a, gamma);
// alpha = 0 is Ishikawa with (alpha, a) = (beta, gamma); a = b = gamma = 0 is
// Mann(alpha + beta).
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct Suantai final : fp::SchemeBase<Suantai> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq(
            "alpha", "0.5",
            "alpha_n: weight of T(u_n) in p_{n+1} = (1 - alpha_n - beta_n) p_n + alpha_n T(u_n) + beta_n "
            "T(v_n)"),
        fp::scheme::seq("beta", "0.2", "beta_n: weight of T(v_n) in p_{n+1}"),
        fp::scheme::seq("gamma", "0.5",
                        "gamma_n: weight of T(p_n) in v_n = (1 - gamma_n) p_n + gamma_n T(p_n)"),
        fp::scheme::seq("a", "0.5",
                        "a_n: weight of T(v_n) in u_n = (1 - a_n - b_n) p_n + a_n T(v_n) + b_n T(p_n)"),
        fp::scheme::seq("b", "0.2", "b_n: weight of T(p_n) in u_n"),
    };

    unsigned applications() const override { return 3; }

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        const fp::Mat2 &alpha = k["alpha"], &beta = k["beta"], &gamma = k["gamma"], &a = k["a"], &b = k["b"];
        Buf<T> tp, tv, u;
        c.t(tp, c.p);                                                 // T(p)
        c.lin(tv, identity - gamma, c.p, gamma, tp);                  // v
        c.t(tv, tv);                                                  // T(v)
        c.lin(u, identity - a - b, c.p, a, tv, b, tp);                // u
        c.t(u, u);                                                    // T(u)
        c.lin(c.p, identity - alpha - beta, c.p, alpha, u, beta, tv); // p_{n+1}
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<Suantai>(
    "suantai", "the Suantai three-step iteration (2005, paper 02 eq. (5)): p <- (1 - alpha "
               "- beta) p + alpha T(u) + beta T(v), u = (1 - a - b) p + a T(v) + b T(p), "
               "v = (1 - gamma) p + gamma T(p)"))
