// m-iteration: the M-iteration of K. Ullah and M. Arshad (Numerical reckoning fixed points
// for Suzuki's generalized nonexpansive mappings via new iteration process, Filomat 32 (2018)
// 187-196),
//
//     z_n     = (1 - a_n) p_n + a_n T(p_n),
//     y_n     = T(z_n),
//     p_{n+1} = T(y_n),
//
// with a_n a number of the scheme's number system: real, complex or q-system (paper 02 Sec. 4).
// The example of docs/writing-a-scheme.md, built out of tree by tests/external-scheme/run.sh.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

namespace {

struct MIteration final : fp::SchemeBase<MIteration> {
    // The coefficients, written once: one sequence each (describe below puts `numbers`, the
    // number system, in front; SchemeBase reads them all).
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("a", "0.5", "a_n: weight of T(p_n) in z_n = (1 - a_n) p_n + a_n T(p_n)"),
    };

    unsigned applications() const override { return 3; } // T(p), T(z), T(y)

    // One step of the points c.p of a chunk, in place; k holds the coefficients at step n as
    // matrices (multiplication by a_n in the scheme's number system).
    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t /*n*/) const {
        const fp::Mat2& a = k["a"];
        Buf<T> z;
        c.t(z, c.p);                       // T(p)
        c.lin(z, identity - a, c.p, a, z); // z = (1 - a) p + a T(p)
        c.t(z, z);                         // y = T(z)
        c.t(c.p, z);                       // p' = T(y)
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<MIteration>("m-iteration",
                                                 "the M-iteration (Ullah-Arshad 2018): p <- T(y), "
                                                 "y = T(z), z = (1 - a) p + a T(p)"))
