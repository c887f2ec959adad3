// ishikawa: the Ishikawa iteration (S. Ishikawa, Fixed points by a new iteration method,
// Proc. Amer. Math. Soc. 44 (1974) 147-150), in the original two-step form
//
//     p_{n+1} = (1 - alpha_n) p_n + alpha_n T(u_n),
//     u_n     = (1 - a_n) p_n + a_n T(p_n),
//
// with the paper's names alpha_n, a_n (paper 02 Sec. 6, Fig. 5; Ishikawa wrote alpha_n, beta_n).
// The parameters are numbers of the scheme's number system (paper 02 Sec. 4), any real value
// (the paper drops the [0, 1] bounds on purpose). a = 0 is Mann; alpha = 1, a = 0 is Picard.
#include "combine.hpp"

namespace {

class Ishikawa final : public fp_iter::SchemeBase<Ishikawa> {
public:
    static constexpr const char* sequences[] = {"alpha", "a"};
    using SchemeBase::SchemeBase;

    unsigned applications() const override { return 2; }

    template <class T>
    void kernel(fp_iter::Chunk<T>& c, const fp_iter::Coefs& k, std::uint64_t) const {
        const fp::Mat2 &alpha = k[0], &a = k[1];
        fp_iter::Buf<T> u;
        c.t(u, c.p);                                          // T(p)
        c.lin(u, fp_iter::identity - a, c.p, a, u);           // u = (1 - a) p + a T(p)
        c.t(u, u);                                            // T(u)
        c.lin(c.p, fp_iter::identity - alpha, c.p, alpha, u); // p' = (1 - alpha) p + alpha T(u)
    }
};

constexpr fp::ParamSpec params[] = {
    fp_iter::numbers_param,
    fp_iter::seq("alpha", "0.5", "alpha_n: weight of T(u_n) in p_{n+1}"),
    fp_iter::seq("a", "0.5", "a_n: weight of T(p_n) in u_n (a = 0 is Mann)"),
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Ishikawa>(
    fp::Kind::IterationScheme, "ishikawa",
    "the Ishikawa iteration (Ishikawa 1974): p <- (1 - alpha) p + alpha T(u), u = (1 - a) p + a T(p)",
    params))
