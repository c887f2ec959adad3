// VertexMap: a Transform that is also a subdivision rule on sets of control points (paper 05,
// eq. (3.1): f(A) = A P^-1 S P).
//
// A renderer that works on whole vertex sets (the `mfs` renderer) asks a map for its rule
// instead of mapping points: the child of a set V of n control points (rows) is S V, every
// new vertex an affine combination of the parent's vertices (rows of S sum to 1). So the
// first two coordinates of the children follow from the parent's first two coordinates and
// S alone, whatever the lift of the points into the (n - 1)-dimensional hyperplane.
// The class lives in the SDK library (key function in sdk.cpp) so that a renderer in another
// plugin library can dynamic_cast a nested Transform to it.
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/transform.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <vector>

namespace fp {

class VertexMap : public Transform {
public:
    ~VertexMap() override;

    /// n: the number of control points of a set (the order of S and P).
    virtual std::size_t vertex_count() const = 0;
    /// The control points P was built from (P's first two columns), in P's row order.
    virtual std::vector<Vec2> control_points() const = 0;
    /// For every set of n points of `parent` (set s at indices [s n, (s + 1) n)), write its
    /// child S V to the same indices of `child` (parent.n == child.n, a multiple of n).
    virtual void subdivide(Points<const double> parent, Points<double> child) const = 0;
};

} // namespace fp
