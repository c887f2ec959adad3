// NumberSystem: the arithmetic iterations compute in (real, complex, q-system; paper 02).
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/object.hpp>
#include <fixpoint/types.hpp>

namespace fp {

class NumberSystem : public Object {
public:
    ~NumberSystem() override;

    /// Multiplication by the fixed number `a` (as a point of the plane) is a linear map of the
    /// plane; schemes turn each parameter into this matrix once per step.
    virtual Mat2 multiplier(Vec2 a) const = 0;
    /// out[i] = u[i] * v[i] in this number system.
    virtual void multiply(Points<const double> u, Points<const double> v, Points<double> out) const = 0;
    /// u / v; false where the division is undefined (zero denominator), `out` then untouched.
    virtual bool divide(Vec2 u, Vec2 v, Vec2& out) const = 0;
    /// True for the real numbers: parameters must then have b = 0, and a list of two plain
    /// numbers is a periodic sequence rather than one q-number (Sequence::resolve).
    virtual bool is_real() const;
};

} // namespace fp
