// schu: the iteration of J. Schu (Weak and strong convergence to fixed points of
// asymptotically nonexpansive mappings, Bull. Austral. Math. Soc. 43 (1991) 153-159), paper 02
// eq. (21):
//
//     p_{n+1} = (1 - alpha_n) p_n + alpha_n T^{n+1}(p_n),
//
// T^{n+1} the (n+1)-fold composition of T, n the step index passed to step() (counted from
// 0, as in paper 02: p_1 = (1 - alpha_0) p_0 + alpha_0 T(p_0)). alpha_n is a number of the
// scheme's number system (fixpoint/scheme.hpp); any real value is accepted.
//
// Involutions (Transform::is_involution(): the inversions of the chaos game). T^2 = id, so
// T^k = T for odd k and id for even k (eq. (22)). With k = n + 1:
//     n even (k odd):  p_{n+1} = (1 - alpha_n) p_n + alpha_n T(p_n)   (a Mann step),
//     n odd  (k even): p_{n+1} = (1 - alpha_n) p_n + alpha_n p_n = p_n (nothing moves).
// This is what the paper's worked elements show (p_1, p_3, p_5 are Mann steps with alpha_0,
// alpha_2, alpha_4; p_2 = p_1, p_4 = p_3). Eqs. (23)-(24) as printed say the opposite (a Mann
// step for odd n, beta_n = alpha_n for odd n): they contradict eq. (21) and those elements,
// and hold only if their n is read as the index of the point produced (p_n is a Mann step from
// p_{n-1} when n is odd).
// We implement eq. (21) exactly, so with step() indexed by n from 0:
//     Schu(alpha) = Mann(beta),  beta_n = alpha_n for even n, 0 for odd n,
// and on an involution step() does exactly that without composing T: one application of T
// at even n (the same arithmetic as the mann plugin, so the results are bitwise equal), none
// at odd n. This is automatic: the chaos game over inversions gets the cheap form without
// any setting.
//
// Other maps (affine, ...): step n applies T n + 1 times, so a chain of N steps costs
// N (N + 1) / 2 applications of T: O(N^2), against N for Mann. A chaos game runs chains of
// points / chains steps (plus skip and restarts), so the cost is unbounded in the chain length;
// `max_compositions` bounds it: a step that needs more compositions of a map that is not an
// involution throws fp::InputError (one line, naming the step, the limit and the remedies)
// instead of running for hours. The compositions are applied in place on the chunk, so the
// cost is time only, never memory. Note that T^{n+1} of a contraction quickly converges to
// its fixed point, so for large n Schu on such a map is Mann towards the fixed point of T.
// applications() keeps the default 1: exact on involutions (at most one, none at odd n); for
// other maps step n takes n + 1.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

#include <string>

namespace {

struct Schu final : fp::SchemeBase<Schu> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("alpha", "0.5",
                        "alpha_n: weight of T^{n+1}(p_n) in p_{n+1} = (1 - alpha_n) p_n + alpha_n "
                        "T^{n+1}(p_n)"),
        fp::param::integer(
            "max_compositions",
            "most applications of T one step may take when the map is not an involution (step n "
            "needs n + 1); a step needing more is refused. Involutions (inversions) need at most 1")
            .def("1000")
            .min(1),
    };

    explicit Schu(const fp::ParamBag& p)
        : SchemeBase(p), max_compositions_(std::uint64_t(p.integer("max_compositions"))) {}

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t n) const {
        std::uint64_t compositions = n + 1;
        if (c.map.is_involution()) {
            if (compositions % 2 == 0) return; // T^{n+1} = id: p_{n+1} = p_n
            compositions = 1;                  // T^{n+1} = T: a Mann step
        } else if (compositions > max_compositions_) {
            too_long(n);
        }
        Buf<T> tp;
        c.t(tp, c.p);
        for (std::uint64_t i = 1; i < compositions; ++i) c.t(tp, tp);
        const fp::Mat2& alpha = k["alpha"];
        c.lin(c.p, identity - alpha, c.p, alpha, tp);
    }

    void check_steps(const fp::Transform& t, std::uint64_t last_n) const override {
        if (!t.is_involution() && last_n + 1 > max_compositions_) too_long(last_n);
    }

private:
    [[noreturn]] void too_long(std::uint64_t n) const {
        throw fp::InputError(
            "schu: step n = " + std::to_string(n) + " needs T composed " + std::to_string(n + 1) +
            " times, above max_compositions = " + std::to_string(max_compositions_) +
            " (the map is not an involution, so a chain of N steps costs N(N+1)/2 applications of T); "
            "use shorter chains (more chains, fewer points), raise max_compositions, or use mann");
    }

    std::uint64_t max_compositions_;
};

} // namespace

FIXPOINT_PLUGIN(fp::scheme::describe<Schu>(
    "schu", "the Schu iteration (1991, paper 02 eq. (21)): p_{n+1} <- (1 - alpha_n) p_n + "
            "alpha_n T^{n+1}(p_n); on an involution, Mann with alpha_n at even n and no move "
            "at odd n"))
