// sp: the SP iteration (W. Phuengrattana, S. Suantai, On the rate of convergence of Mann,
// Ishikawa, Noor and SP iterations for continuous functions on an arbitrary interval,
// J. Comput. Appl. Math. 235 (2011) 3006-3014), the three-step form
//
//     p_{n+1} = (1 - alpha_n) u_n + alpha_n T(u_n),
//     u_n     = (1 - a_n) v_n + a_n T(v_n),
//     v_n     = (1 - gamma_n) p_n + gamma_n T(p_n),
//
// three Mann steps in a row, with the paper's names alpha_n, a_n, gamma_n (paper 02 Sec. 6,
// Fig. 7(b)-(c); Phuengrattana and Suantai wrote alpha_n, beta_n, gamma_n). This is the Karakaya
// iteration, eq. (8), with beta = b = 0 (paper 02 Fig. 4). The parameters are numbers of the
// scheme's number system, any real value. a = gamma = 0 is Mann.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct Sp final : fp::SchemeBase<Sp> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("alpha", "0.5", "alpha_n: weight of T(u_n) in p_{n+1}"),
        fp::scheme::seq("a", "0.5", "a_n: weight of T(v_n) in u_n"),
        fp::scheme::seq("gamma", "0.5", "gamma_n: weight of T(p_n) in v_n (a = gamma = 0 is Mann)"),
    };

    unsigned applications() const override { return 3; }

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        const fp::Mat2 &alpha = k["alpha"], &a = k["a"], &gamma = k["gamma"];
        Buf<T> w;
        c.t(w, c.p);                                 // T(p)
        c.lin(c.p, identity - gamma, c.p, gamma, w); // v = (1 - gamma) p + gamma T(p)
        c.t(w, c.p);                                 // T(v)
        c.lin(c.p, identity - a, c.p, a, w);         // u = (1 - a) v + a T(v)
        c.t(w, c.p);                                 // T(u)
        c.lin(c.p, identity - alpha, c.p, alpha, w); // p' = (1 - alpha) u + alpha T(u)
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<Sp>(
    "sp", "the SP iteration (Phuengrattana-Suantai 2011): p <- (1 - alpha) u + alpha T(u), "
          "u = (1 - a) v + a T(v), v = (1 - gamma) p + gamma T(p)"))
