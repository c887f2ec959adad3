// switching: the switching process of paper 02, eq. (26). Given m iteration schemes
// P_0, ..., P_{m-1},
//
//     p_{n+1} = P_{n mod m}(p_n),
//
// so step n runs schemes[n mod m] with the same map T and the same step index n (a child's
// parameter sequences are indexed by the global n: a child with alpha: [0.7, 0.9] under a
// switching of two schemes sees only alpha_n for the n it runs at). One child is that child.
//
// Switching between q-systems (paper 02, eq. (27): p_{n+1} = P^{A_{n mod m}, B_{n mod m}}(p_n))
// is the same process over copies of one scheme that differ only in their `numbers:`, e.g.
// Fig. 12(c), Ishikawa with alpha = 1 + 0.1q, a = 0.1q switching between Q_{-3,0} and Q_{3,0}:
//
//     iteration:
//       type: switching
//       schemes:
//         - {type: ishikawa, alpha: 1+0.1q, a: 0.1q, numbers: {type: q-system, A: -3, B: 0}}
//         - {type: ishikawa, alpha: 1+0.1q, a: 0.1q, numbers: {type: q-system, A: 3, B: 0}}
//
// and both kinds mix freely (any scheme, any numbers, in any order; a child may itself be a
// switching). An empty list is refused by the host ("the list of iteration-schemes is empty").
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace {

class Switching final : public fp::IterationScheme {
public:
    explicit Switching(const fp::ParamBag& p) {
        const auto& items = p.objects("schemes");
        if (items.empty()) throw fp::ParamError("schemes", "the list of schemes is empty");
        for (std::size_t i = 0; i < items.size(); ++i) {
            auto s = fp::as<fp::IterationScheme>(items[i]);
            if (!s)
                throw fp::InternalError("switching: schemes[" + std::to_string(i) +
                                        "] is not an iteration scheme");
            schemes_.push_back(std::move(s));
        }
    }

    void step(const fp::Transform& t, fp::Points<float> p, fp::Mask mask, std::uint64_t n) const override {
        at(n).step(t, p, mask, n);
    }
    void step(const fp::Transform& t, fp::Points<double> p, fp::Mask mask, std::uint64_t n) const override {
        at(n).step(t, p, mask, n);
    }

    /// Step n's child's program (none where that child has none).
    bool program(const fp::Transform& t, std::uint64_t n, bool dbl, fp::SchemeProgram& out) const override {
        return at(n).program(t, n, dbl, out);
    }
    /// The most any child takes (a bound on the cost per step).
    void check_steps(const fp::Transform& t, std::uint64_t last_n) const override {
        for (const auto& s : schemes_) s->check_steps(t, last_n);
    }

    unsigned applications() const override {
        unsigned most = 0;
        for (const auto& s : schemes_) most = std::max(most, s->applications());
        return most;
    }

private:
    const fp::IterationScheme& at(std::uint64_t n) const { return *schemes_[n % schemes_.size()]; }

    std::vector<std::shared_ptr<const fp::IterationScheme>> schemes_;
};

constexpr fp::ParamSpec params[] = {
    fp::param::objects("schemes", fp::Kind::IterationScheme,
                       "P_0, ..., P_{m-1}: step n uses schemes[n mod m] (eq. (26)); to switch q-systems (eq. "
                       "(27)), list one scheme several times with different numbers:")
        .min_len(1),
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<Switching>(fp::Kind::IterationScheme, "switching",
                            "the switching process (paper 02 eqs. (26)-(27)): step n uses schemes[n "
                            "mod m]; switch q-systems with copies of one scheme differing in numbers:",
                            params)
        .with_example("{schemes: [{type: mann, alpha: 0.7}, {type: picard}]}"))
