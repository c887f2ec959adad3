// karakaya: the three-step iteration of V. Karakaya, K. Dogan, F. Gursoy, M. Erturk (Fixed
// point of a new three-step iteration algorithm under contractive-like operators over normed
// spaces, Abstr. Appl. Anal. 2013, 560258), paper 02 eq. (8):
//
//     v_n     = (1 - gamma_n) p_n + gamma_n T(p_n),
//     u_n     = (1 - a_n - b_n) v_n + a_n T(v_n) + b_n T(p_n),
//     p_{n+1} = (1 - alpha_n - beta_n) u_n + alpha_n T(u_n) + beta_n T(v_n),
//
// with the five parameters numbers of the scheme's number system (paper 02 Sec. 4; products
// are 2x2 matrices, see fixpoint/scheme.hpp). Any real value is accepted: the paper drops the bounds
// (alpha + beta, a + b in [0, 1]) on purpose. Three applications of T per step (T(p), T(v),
// T(u)), all with the same map.
//
// Reductions (tests/unit/test_schemes_b.cpp): beta = b = 0 is SP (alpha, a, gamma);
// alpha = beta = a = b = 0 is Mann(gamma); a = b = 0 is Mann(gamma) followed by
// Mann(alpha + beta).
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct Karakaya final : fp::SchemeBase<Karakaya> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq(
            "alpha", "0.5",
            "alpha_n: weight of T(u_n) in p_{n+1} = (1 - alpha_n - beta_n) u_n + alpha_n T(u_n) + beta_n "
            "T(v_n)"),
        fp::scheme::seq("beta", "0.2", "beta_n: weight of T(v_n) in p_{n+1}"),
        fp::scheme::seq("gamma", "0.5",
                        "gamma_n: weight of T(p_n) in v_n = (1 - gamma_n) p_n + gamma_n T(p_n)"),
        fp::scheme::seq("a", "0.5",
                        "a_n: weight of T(v_n) in u_n = (1 - a_n - b_n) v_n + a_n T(v_n) + b_n T(p_n)"),
        fp::scheme::seq("b", "0.2", "b_n: weight of T(p_n) in u_n"),
    };

    unsigned applications() const override { return 3; }

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        const fp::Mat2 &alpha = k["alpha"], &beta = k["beta"], &gamma = k["gamma"], &a = k["a"], &b = k["b"];
        Buf<T> tp, v, tv;
        c.t(tp, c.p);                                                // T(p)
        c.lin(v, identity - gamma, c.p, gamma, tp);                  // v
        c.t(tv, v);                                                  // T(v)
        c.lin(v, identity - a - b, v, a, tv, b, tp);                 // u (in place of v)
        c.t(tp, v);                                                  // T(u) (in place of T(p))
        c.lin(c.p, identity - alpha - beta, v, alpha, tp, beta, tv); // p_{n+1}
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<Karakaya>(
    "karakaya", "the Karakaya et al. three-step iteration (2013, paper 02 eq. (8)): p <- "
                "(1 - alpha - beta) u + alpha T(u) + beta T(v), u = (1 - a - b) v + a T(v) "
                "+ b T(p), v = (1 - gamma) p + gamma T(p)"))
