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
};

} // namespace fp
