// khan: the Picard-Mann hybrid iteration (S. H. Khan, A Picard-Mann hybrid iterative process,
// Fixed Point Theory Appl. 2013:69), in its original form
//
//     p_{n+1} = T(u_n),
//     u_n     = (1 - a_n) p_n + a_n T(p_n),
//
// a Mann step followed by a Picard step. Khan writes alpha_n; we name the parameter `a`, as
// paper 02 does (Fig. 7(d): "Khan iteration with a_n = 0.3 + 0.5q"). a_n is a number of the
// scheme's number system (paper 02 Sec. 4), any real value. a = 0 is Picard, a = 1 is Picard
// twice; the S-iteration, eq. (6), with alpha = 1 and beta = a is this.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct Khan final : fp::SchemeBase<Khan> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("a", "0.5", "a_n: weight of T(p_n) in the Mann step u_n (Khan's alpha_n)"),
    };

    unsigned applications() const override { return 2; }

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        const fp::Mat2& a = k["a"];
        Buf<T> u;
        c.t(u, c.p);                       // T(p)
        c.lin(u, identity - a, c.p, a, u); // u = (1 - a) p + a T(p)
        c.t(c.p, u);                       // p' = T(u)
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<Khan>(
    "khan", "the Picard-Mann hybrid iteration (Khan 2013): p <- T(u), u = (1 - a) p + a T(p)"))
