// mann: the Mann iteration (W. R. Mann, Mean value methods in iteration, 1953),
//
//     p_{n+1} = (1 - alpha_n) p_n + alpha_n T(p_n),
//
// with alpha_n a number of the scheme's number system (paper 02, eq. (9) and Sec. 4). Any
// real value is accepted: the paper drops the [0, 1] bounds on purpose. alpha = 1 is Picard.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct Mann final : fp::SchemeBase<Mann> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("alpha", "0.5", "alpha_n: weight of T(p_n)"),
    };

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        const fp::Mat2& alpha = k["alpha"];
        Buf<T> tp;
        c.t(tp, c.p);                                 // T(p)
        c.lin(c.p, identity - alpha, c.p, alpha, tp); // p' = (1 - alpha) p + alpha T(p)
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<Mann>("mann",
                                           "the Mann iteration (Mann 1953): p <- (1 - alpha) p + alpha T(p)"))
