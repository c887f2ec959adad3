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
#include "combine.hpp"

namespace {

class PicardS final : public fp_iter::SchemeBase<PicardS> {
public:
    static constexpr const char* sequences[] = {"beta", "gamma"};
    using SchemeBase::SchemeBase;

    unsigned applications() const override { return 3; }

    template <class T>
    void kernel(fp_iter::Chunk<T>& c, const fp_iter::Coefs& k, std::uint64_t) const {
        const fp::Mat2 &beta = k[0], &gamma = k[1];
        fp_iter::Buf<T> tp, v;
        c.t(tp, c.p);                                        // T(p)
        c.lin(v, fp_iter::identity - gamma, c.p, gamma, tp); // v = (1 - gamma) p + gamma T(p)
        c.t(v, v);                                           // T(v)
        c.lin(v, fp_iter::identity - beta, tp, beta, v);     // u = (1 - beta) T(p) + beta T(v)
        c.t(c.p, v);                                         // p' = T(u)
    }
};

constexpr fp::ParamSpec params[] = {
    fp_iter::numbers_param,
    fp_iter::seq("beta", "0.5", "beta_n: weight of T(v_n) against T(p_n) in u_n"),
    fp_iter::seq("gamma", "0.5", "gamma_n: weight of T(p_n) in v_n"),
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<PicardS>(
    fp::Kind::IterationScheme, "picard-s",
    "the Picard-S hybrid iteration (Gürsoy-Karakaya 2014): p <- T(u), u = (1 - beta) T(p) "
    "+ beta T(v), v = (1 - gamma) p + gamma T(p)",
    params))
