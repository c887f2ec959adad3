// s-iteration: the S-iteration (R. P. Agarwal, D. O'Regan, D. R. Sahu, Iterative construction
// of fixed points of nearly asymptotically nonexpansive mappings, J. Nonlinear Convex Anal. 8
// (2007) 61-79), paper 02 eq. (6) as in the original:
//
//     p_{n+1} = (1 - alpha_n) T(p_n) + alpha_n T(u_n),
//     u_n     = (1 - beta_n) p_n + beta_n T(p_n).
//
// The parameters are numbers of the scheme's number system (paper 02 Sec. 4, Fig. 9(a)), any
// real value. beta = 0 is Picard; alpha = 1 is the Picard-Mann hybrid (khan) with alpha = beta.
#include "combine.hpp"

namespace {

class SIteration final : public fp_iter::SchemeBase<SIteration> {
public:
    static constexpr const char* sequences[] = {"alpha", "beta"};
    using SchemeBase::SchemeBase;

    unsigned applications() const override { return 2; }

    template <class T>
    void kernel(fp_iter::Chunk<T>& c, const fp_iter::Coefs& k, std::uint64_t) const {
        const fp::Mat2 &alpha = k[0], &beta = k[1];
        fp_iter::Buf<T> tp, u;
        c.t(tp, c.p);                                        // T(p)
        c.lin(u, fp_iter::identity - beta, c.p, beta, tp);   // u = (1 - beta) p + beta T(p)
        c.t(u, u);                                           // T(u)
        c.lin(c.p, fp_iter::identity - alpha, tp, alpha, u); // p' = (1 - alpha) T(p) + alpha T(u)
    }
};

constexpr fp::ParamSpec params[] = {
    fp_iter::numbers_param,
    fp_iter::seq("alpha", "0.5", "alpha_n: weight of T(u_n) against T(p_n) in p_{n+1}"),
    fp_iter::seq("beta", "0.5", "beta_n: weight of T(p_n) in u_n (beta = 0 is Picard)"),
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<SIteration>(
    fp::Kind::IterationScheme, "s-iteration",
    "the S-iteration (Agarwal-O'Regan-Sahu 2007, paper 02 eq. (6)): p <- (1 - alpha) T(p) "
    "+ alpha T(u), u = (1 - beta) p + beta T(p)",
    params))
