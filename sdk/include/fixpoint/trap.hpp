// Trap: regions that catch an orbit (orbit-trap renderers; paper 04).
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/object.hpp>

#include <cstddef>
#include <cstdint>

namespace fp {

/// A trap a renderer may test in its own fused loop instead of calling test() (orbit-trap does:
/// no virtual call, no store and reload of distances per point and trap). The contract is exact:
/// with T the batch's type (float or double), no FMA contraction, test() must give the same trap
/// and ratio as
///   euclidean_circles: for i = 0, 1, ..., n - 1 the first i with
///       dx = x - T(cx[i]), dy = y - T(cy[i]), k = dx * dx + dy * dy, k < key_T[i]
///     holds the point; its ratio is min(sqrt(k) / T(r[i]), the largest T below 1)
///     (key_T: key_f for float, key_d for double; sqrt correctly rounded).
/// The arrays belong to the trap and live as long as it does.
struct TrapKernel {
    enum class Kind : std::uint32_t { none, euclidean_circles };
    Kind kind = Kind::none;
    std::size_t n = 0;
    const double* cx = nullptr;
    const double* cy = nullptr;
    const double* r = nullptr;
    const float* key_f = nullptr;
    const double* key_d = nullptr;
};

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

    /// The trap as a known kernel (see TrapKernel), when it is one; the default is none.
    virtual TrapKernel kernel() const { return {}; }
};

} // namespace fp
