// picard — the Picard iteration p_{n+1} = T(p_n) (paper 02, Sec. 3): the plain step of the
// chaos game and of escape-time orbits, and the reference the other schemes reduce to
// (Mann with alpha = 1, Ishikawa with alpha = beta = 1, ...).
#include <fixpoint/fixpoint.hpp>

namespace {

class Picard final : public fp::IterationScheme {
public:
    explicit Picard(const fp::ParamBag&) {}

    void step(const fp::Transform& t, fp::Points<float> p, fp::Mask mask, std::uint64_t) const override {
        t.apply(p, mask);
    }
    void step(const fp::Transform& t, fp::Points<double> p, fp::Mask mask, std::uint64_t) const override {
        t.apply(p, mask);
    }
    bool is_picard() const override { return true; }
    /// One map instruction (a switching process with a Picard child runs it as a program).
    bool program(const fp::Transform&, std::uint64_t, bool, fp::SchemeProgram& out) const override {
        out.size = 1;
        out.regs = 1;
        out.code[0].op = fp::SchemeProgram::Op::map;
        out.code[0].dst = out.code[0].u = 0;
        return true;
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Picard>(fp::Kind::IterationScheme, "picard",
                                     "the Picard iteration (Picard 1890, paper 02 Sec. 3): p <- T(p)"))
