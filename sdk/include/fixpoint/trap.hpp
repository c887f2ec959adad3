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
    /// out[i] = index of the first trap that holds p[i], or -1.
    virtual void test(Points<const float> p, std::int32_t* out) const = 0;
    virtual void test(Points<const double> p, std::int32_t* out) const = 0;
};

} // namespace fp
