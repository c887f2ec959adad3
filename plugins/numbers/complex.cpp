// complex: the complex numbers a + ib, computed as the q-system Q_{-1,0} (q^2 = -1; paper 02
// Sec. 4): the very formulas of qsystem.hpp with A = -1 and B = 0, so that `complex` and
// `{type: q-system, A: -1, B: 0}` give the same bits. Multiplying by a + ib is the rotation-
// scaling [[a, -b], [b, a]].
#include "qsystem.hpp"

namespace {

class Complex final : public fp_numbers::QSystem {
public:
    explicit Complex(const fp::ParamBag&) : QSystem(-1, 0) {}
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Complex>(fp::Kind::NumberSystem, "complex",
                                      "the complex numbers, i.e. the q-system with A = -1, B = 0"))
