// Trap: regions that catch an orbit (orbit-trap renderers; paper 04).
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/object.hpp>

#include <cstddef>
#include <cstdint>

namespace fp {

class Trap : public Object {
public:
    ~Trap() override;

    /// Number of traps held.
    virtual std::size_t count() const = 0;
    /// trap[i] = index of the first trap that holds p[i], or -1; where trap[i] >= 0,
    /// ratio[i] = d(p[i], c) / r of that trap, in [0, 1) (paper 04, Algorithm 3 line 16 colours
    /// by it). ratio[i] is unspecified where trap[i] = -1.
    virtual void test(Points<const float> p, std::int32_t* trap, float* ratio) const = 0;
    virtual void test(Points<const double> p, std::int32_t* trap, double* ratio) const = 0;
};

} // namespace fp
