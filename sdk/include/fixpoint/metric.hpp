// Metric: a distance on the plane (lp, Chebyshev, Rickman's rug; paper 04).
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/object.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>

namespace fp {

class Metric : public Object {
public:
    ~Metric() override;

    /// out[i] = d(p[i], c).
    virtual void distance(Points<const float> p, Vec2 c, float* out) const = 0;
    virtual void distance(Points<const double> p, Vec2 c, double* out) const = 0;

    /// Comparisons without the expensive part (orbit-trap tests run one per point, trap and
    /// step): out[i] = g(d(p[i], c)) for a strictly increasing g >= 0 of the metric's choice
    /// (the Euclidean metric: g(d) = d^2, no square root), key(r) = g(r), and from_key() turns
    /// keys back into distances in place, so that from_key(distance_key(p)) gives exactly the
    /// bits of distance(p). Defaults: g the identity.
    virtual void distance_key(Points<const float> p, Vec2 c, float* out) const { distance(p, c, out); }
    virtual void distance_key(Points<const double> p, Vec2 c, double* out) const { distance(p, c, out); }
    virtual double key(double d) const { return d; }
    virtual void from_key(float*, std::size_t) const {}
    virtual void from_key(double*, std::size_t) const {}

    /// The metric as a known formula, for traps that compute it inline (circles reports its
    /// circles to renderers as TrapKernel data). The contract is exact: with T the batch's type
    /// and c rounded to T first, no FMA contraction,
    ///   euclidean: distance_key = dx * dx + dy * dy (dx = x - c.x, dy = y - c.y), key(d) = d * d,
    ///              from_key = the correctly rounded square root (std::sqrt);
    /// `other` promises nothing. The default is other.
    enum class Kind { other, euclidean };
    virtual Kind kind() const { return Kind::other; }
};

} // namespace fp
