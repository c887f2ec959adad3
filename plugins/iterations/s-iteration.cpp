// s-iteration: the S-iteration (R. P. Agarwal, D. O'Regan, D. R. Sahu, Iterative construction
// of fixed points of nearly asymptotically nonexpansive mappings, J. Nonlinear Convex Anal. 8
// (2007) 61-79), paper 02 eq. (6) as in the original:
//
//     p_{n+1} = (1 - alpha_n) T(p_n) + alpha_n T(u_n),
//     u_n     = (1 - beta_n) p_n + beta_n T(p_n).
//
// The parameters are numbers of the scheme's number system (paper 02 Sec. 4, Fig. 9(a)), any
// real value. beta = 0 is Picard; alpha = 1 is the Picard-Mann hybrid (khan) with alpha = beta.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct SIteration final : fp::SchemeBase<SIteration> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("alpha", "0.5", "alpha_n: weight of T(u_n) against T(p_n) in p_{n+1}"),
        fp::scheme::seq("beta", "0.5", "beta_n: weight of T(p_n) in u_n (beta = 0 is Picard)"),
    };

    unsigned applications() const override { return 2; }

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        const fp::Mat2 &alpha = k["alpha"], &beta = k["beta"];
        Buf<T> tp, u;
        c.t(tp, c.p);                               // T(p)
        c.lin(u, identity - beta, c.p, beta, tp);   // u = (1 - beta) p + beta T(p)
        c.t(u, u);                                  // T(u)
        c.lin(c.p, identity - alpha, tp, alpha, u); // p' = (1 - alpha) T(p) + alpha T(u)
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<SIteration>(
    "s-iteration", "the S-iteration (Agarwal-O'Regan-Sahu 2007, paper 02 eq. (6)): p <- (1 - alpha) T(p) "
                   "+ alpha T(u), u = (1 - beta) p + beta T(p)"))
