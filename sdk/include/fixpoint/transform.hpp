// Transform: a map of the plane, applied in place to batches of points.
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/object.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <vector>

namespace fp {

class Transform : public Object {
public:
    ~Transform() override;

    /// p[i] <- T(p[i]) for every active point; inactive points stay as they are.
    virtual void apply(Points<float> p, Mask mask) const = 0;
    virtual void apply(Points<double> p, Mask mask) const = 0;

    /// Maps defined by a set (inversions) report it, so that a renderer can apply the
    /// inversion rules of paper 01's Algorithm 1 ("not a map whose set holds the point").
    virtual bool has_region() const;
    /// out[i] = 1 when p[i] lies inside the map's set (only called when has_region()).
    virtual void contains(Points<const float> p, unsigned char* out) const;
    virtual void contains(Points<const double> p, unsigned char* out) const;
    /// The set's boundary, for drawing (empty without a region).
    virtual std::vector<Vec2> region_outline(std::size_t samples) const;

    /// T(T(p)) = p: the conformance suite checks it; renderers may use it.
    virtual bool is_involution() const;
    /// Where finite input must give finite output (conformance suite samples this box).
    virtual Box sample_domain() const;
};

} // namespace fp
