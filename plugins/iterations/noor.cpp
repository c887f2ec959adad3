// noor: the Noor iteration (M. A. Noor, New approximation schemes for general variational
// inequalities, J. Math. Anal. Appl. 251 (2000) 217-229), the three-step form
//
//     p_{n+1} = (1 - alpha_n) p_n + alpha_n T(u_n),
//     u_n     = (1 - a_n) p_n + a_n T(v_n),
//     v_n     = (1 - gamma_n) p_n + gamma_n T(p_n),
//
// with the paper's names alpha_n, a_n, gamma_n (paper 02 Sec. 6, Fig. 7(e)). This is the
// Suantai iteration, eq. (5), with beta = b = 0 (paper 02 Fig. 4). The parameters are numbers
// of the scheme's number system, any real value. gamma = 0 is Ishikawa.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct Noor final : fp::SchemeBase<Noor> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("alpha", "0.5", "alpha_n: weight of T(u_n) in p_{n+1}"),
        fp::scheme::seq("a", "0.5", "a_n: weight of T(v_n) in u_n"),
        fp::scheme::seq("gamma", "0.5", "gamma_n: weight of T(p_n) in v_n (gamma = 0 is Ishikawa)"),
    };

    unsigned applications() const override { return 3; }

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        const fp::Mat2 &alpha = k["alpha"], &a = k["a"], &gamma = k["gamma"];
        Buf<T> w;
        c.t(w, c.p);                                 // T(p)
        c.lin(w, identity - gamma, c.p, gamma, w);   // v = (1 - gamma) p + gamma T(p)
        c.t(w, w);                                   // T(v)
        c.lin(w, identity - a, c.p, a, w);           // u = (1 - a) p + a T(v)
        c.t(w, w);                                   // T(u)
        c.lin(c.p, identity - alpha, c.p, alpha, w); // p' = (1 - alpha) p + alpha T(u)
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<Noor>(
    "noor", "the Noor iteration (Noor 2000): p <- (1 - alpha) p + alpha T(u), u = (1 - a) p + a T(v), "
            "v = (1 - gamma) p + gamma T(p)"))
