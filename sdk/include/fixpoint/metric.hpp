// Metric: a distance on the plane (lp, Chebyshev, Rickman's rug; paper 04).
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/object.hpp>
#include <fixpoint/types.hpp>

namespace fp {

class Metric : public Object {
public:
    ~Metric() override;

    /// out[i] = d(p[i], c).
    virtual void distance(Points<const float> p, Vec2 c, float* out) const = 0;
    virtual void distance(Points<const double> p, Vec2 c, double* out) const = 0;
};

} // namespace fp
