// picard-s: the Picard-S hybrid iteration (F. Gürsoy, V. Karakaya, A Picard-S hybrid type
// iteration method for solving a differential equation with retarded argument, 2014,
// arXiv:1403.2546),
//
//     p_{n+1} = T(u_n),
//     u_n     = (1 - beta_n) T(p_n) + beta_n T(v_n),
//     v_n     = (1 - gamma_n) p_n + gamma_n T(p_n),
//
// a Picard step after an S-iteration step. The parameters are named as paper 02 uses them
// (Fig. 6(e): beta = 1.5, gamma = 0.8; Fig. 10(b)), which follows the CR iteration, eq. (7):
// Gürsoy and Karakaya's alpha_n is beta here and their beta_n is gamma. They are numbers of the
// scheme's number system, any real value. Picard-S(beta, gamma) = T o S(alpha = beta,
// beta = gamma); it is CR with alpha = 1; gamma = 0 gives T(T(p)) (for an inversion, an
// involution, that is p again up to rounding).
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct PicardS final : fp::SchemeBase<PicardS> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("beta", "0.5", "beta_n: weight of T(v_n) against T(p_n) in u_n"),
        fp::scheme::seq("gamma", "0.5", "gamma_n: weight of T(p_n) in v_n"),
    };

    unsigned applications() const override { return 3; }

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        const fp::Mat2 &beta = k["beta"], &gamma = k["gamma"];
        Buf<T> tp, v;
        c.t(tp, c.p);                               // T(p)
        c.lin(v, identity - gamma, c.p, gamma, tp); // v = (1 - gamma) p + gamma T(p)
        c.t(v, v);                                  // T(v)
        c.lin(v, identity - beta, tp, beta, v);     // u = (1 - beta) T(p) + beta T(v)
        c.t(c.p, v);                                // p' = T(u)
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<PicardS>(
    "picard-s", "the Picard-S hybrid iteration (Gürsoy-Karakaya 2014): p <- T(u), u = (1 - beta) T(p) "
                "+ beta T(v), v = (1 - gamma) p + gamma T(p)"))
