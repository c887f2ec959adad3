// q-system: the q-system numbers Q_{A,B} of Levin (1994), a + qb with q^2 = A + 2B q (paper 02
// eqs. (10)-(15)). Addition and subtraction are componentwise (eqs. (12)-(13)); multiplication
// and division are eqs. (14) and (15), in qsystem.hpp. Multiplying by a fixed a + qb is the
// matrix [[a, A b], [b, a + 2B b]] acting on (x, y) = x + qy: eq. (14) with c + qd = x + qy
// has real part a x + (A b) y and q part b x + (a + 2B b) y. The schemes turn each parameter
// into this matrix once per step. A = -1, B = 0 (the default) is the complex numbers.
#include "qsystem.hpp"

namespace {

class QSystemNumbers final : public fp_numbers::QSystem {
public:
    explicit QSystemNumbers(const fp::ParamBag& p) : QSystem(p.real("A"), p.real("B")) {}
};

constexpr fp::ParamSpec params[] = {
    fp::param::real("A", "A in q^2 = A + 2B q (eq. (11)); any real").def("-1"),
    fp::param::real("B", "B in q^2 = A + 2B q (eq. (11)); any real").def("0"),
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<QSystemNumbers>(fp::Kind::NumberSystem, "q-system",
                                 "q-system numbers a + qb with q^2 = A + 2B q (paper 02 eq. (11))", params)
        .with_example("{A: -1.5, B: 0.2}"))
