// ishikawa: the Ishikawa iteration (S. Ishikawa, Fixed points by a new iteration method,
// Proc. Amer. Math. Soc. 44 (1974) 147-150), in the original two-step form
//
//     p_{n+1} = (1 - alpha_n) p_n + alpha_n T(u_n),
//     u_n     = (1 - a_n) p_n + a_n T(p_n),
//
// with the paper's names alpha_n, a_n (paper 02 Sec. 6, Fig. 5; Ishikawa wrote alpha_n, beta_n).
// The parameters are numbers of the scheme's number system (paper 02 Sec. 4), any real value
// (the paper drops the [0, 1] bounds on purpose). a = 0 is Mann; alpha = 1, a = 0 is Picard.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct Ishikawa final : fp::SchemeBase<Ishikawa> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("alpha", "0.5", "alpha_n: weight of T(u_n) in p_{n+1}"),
        fp::scheme::seq("a", "0.5", "a_n: weight of T(p_n) in u_n (a = 0 is Mann)"),
    };

    unsigned applications() const override { return 2; }

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        const fp::Mat2 &alpha = k["alpha"], &a = k["a"];
        Buf<T> u;
        c.t(u, c.p);                                 // T(p)
        c.lin(u, identity - a, c.p, a, u);           // u = (1 - a) p + a T(p)
        c.t(u, u);                                   // T(u)
        c.lin(c.p, identity - alpha, c.p, alpha, u); // p' = (1 - alpha) p + alpha T(u)
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<Ishikawa>(
    "ishikawa",
    "the Ishikawa iteration (Ishikawa 1974): p <- (1 - alpha) p + alpha T(u), u = (1 - a) p + a T(p)"))
