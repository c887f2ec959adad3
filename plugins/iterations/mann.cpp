// mann: the Mann iteration (W. R. Mann, Mean value methods in iteration, 1953),
//
//     p_{n+1} = (1 - alpha_n) p_n + alpha_n T(p_n),
//
// with alpha_n a number of the scheme's number system (paper 02, eq. (9) and Sec. 4). Any
// real value is accepted: the paper drops the [0, 1] bounds on purpose. alpha = 1 is Picard.
#include "combine.hpp"

namespace {

class Mann final : public fp_iter::SchemeBase<Mann> {
public:
    static constexpr const char* sequences[] = {"alpha"};
    using SchemeBase::SchemeBase;

    template <class T>
    void kernel(fp_iter::Chunk<T>& c, const fp_iter::Coefs& k, std::uint64_t) const {
        fp_iter::Buf<T> tp;
        c.t(tp, c.p);
        c.lin(c.p, fp_iter::identity - k[0], c.p, k[0], tp);
    }
};

constexpr fp::ParamSpec params[] = {
    fp_iter::numbers_param,
    fp_iter::seq("alpha", "0.5", "alpha_n: weight of T(p_n)"),
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Mann>(fp::Kind::IterationScheme, "mann",
                                   "the Mann iteration p <- (1 - alpha) p + alpha T(p)", params))
