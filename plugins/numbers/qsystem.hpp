// The arithmetic of the q-system numbers Q_{A,B} (Levin 1994; paper 02 eqs. (10)-(15)),
// shared by the `q-system` plugin and by `complex`, which is literally these formulas with
// A = -1, B = 0 (q^2 = -1: paper 02 notes that Q_{-1,0} is the complex numbers).
//
// A number a + qb is stored as the point (a, b) of the plane; the mappings R and Q of eqs.
// (18)-(19) are then the identity.
//
// Multiplication, eq. (14):  (a + qb)(c + qd) = (ac + A bd) + q(bc + ad + 2B bd).
// For a fixed factor a + qb this is linear in (c, d):
//     real part:  a c + (A b) d
//     q part:     b c + (a + 2B b) d
// so multiplying by a + qb is the matrix
//     M(a + qb) = [ a      A b      ]
//                 [ b   a + 2B b    ]
// acting on (x, y) = x + qy. multiply() evaluates exactly this matrix product (the same
// grouping), so multiplier() and multiply() agree bitwise; with A = -1, B = 0 it is
// (ac - bd) + q(bc + ad) rounded as std::complex<double> rounds it (A b = -b and
// a + 0 b = a are exact, and the build has no contraction into FMA).
//
// Division, eq. (15):
//     (a + qb) / (c + qd) = (ac + 2B ad - A bd) / D + q (cb - ad) / D,   D = c^2 + 2B cd - A d^2,
// undefined (false) where D = 0, which for A + B^2 > 0 happens on whole lines through 0
// (zero divisors), not only at 0.
#pragma once

#include <fixpoint/fixpoint.hpp>

namespace fp_numbers {

class QSystem : public fp::NumberSystem {
public:
    QSystem(double A, double B) : A_(A), B_(B) {}

    fp::Mat2 multiplier(fp::Vec2 u) const override { return {u.x, A_ * u.y, u.y, u.x + 2 * B_ * u.y}; }

    void multiply(fp::Points<const double> u, fp::Points<const double> v,
                  fp::Points<double> out) const override {
        for (std::size_t i = 0; i < u.n; ++i) {
            const double a = u.x[i], b = u.y[i], c = v.x[i], d = v.y[i];
            const double m01 = A_ * b, m11 = a + 2 * B_ * b; // M(a + qb), see above
            out.x[i] = a * c + m01 * d;
            out.y[i] = b * c + m11 * d;
        }
    }

    bool divide(fp::Vec2 u, fp::Vec2 v, fp::Vec2& out) const override {
        const double a = u.x, b = u.y, c = v.x, d = v.y;
        const double den = c * c + 2 * B_ * c * d - A_ * d * d;
        if (den == 0) return false;
        out = {(a * c + 2 * B_ * a * d - A_ * b * d) / den, (c * b - a * d) / den};
        return true;
    }

    double A() const { return A_; }
    double B() const { return B_; }

private:
    double A_, B_;
};

} // namespace fp_numbers
