// Shape: a star-shaped set in the plane (paper 01, Definition 3).
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/object.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <vector>

namespace fp {

class Shape : public Object {
public:
    ~Shape() override;

    /// A point strictly inside the kernel: the default centre of inversion.
    virtual Vec2 centre() const = 0;
    /// True when `o` lies strictly inside the kernel, so that every ray from `o` meets the
    /// boundary exactly once (paper 01, Sec. 3).
    virtual bool in_kernel(Vec2 o) const = 0;
    /// A box that holds the set.
    virtual Box bounds() const = 0;

    /// out[i] = 1 when p[i] lies in the interior of the set, else 0.
    virtual void inside(Points<const float> p, unsigned char* out) const = 0;
    virtual void inside(Points<const double> p, unsigned char* out) const = 0;

    /// For each direction d[i] (non-zero), t[i] > 0 such that o + t[i] d[i] lies on the
    /// boundary. `o` must be in the kernel. A zero direction gives t = +inf.
    virtual void ray_exit(Vec2 o, Points<const float> d, float* t) const = 0;
    virtual void ray_exit(Vec2 o, Points<const double> d, double* t) const = 0;

    /// The factor of star-shaped set inversion (paper 01, eq. (4)): s[i] = [d(o, b)]^2 / |d[i]|^2
    /// = t^2, where b = o + t d[i] is the boundary hit, so that I(p) = o + s (p - o) with
    /// d = p - o. The default squares ray_exit(); a shape that knows it in closed form
    /// overrides it (a circle about its own centre gives R^2 / |d|^2 exactly, eq. (2)).
    virtual void inversion_factor(Vec2 o, Points<const float> d, float* s) const;
    virtual void inversion_factor(Vec2 o, Points<const double> d, double* s) const;

    /// The boundary as a closed polyline of about `samples` points (polygons: their
    /// vertices), for drawing the sets and for tests.
    virtual std::vector<Vec2> outline(std::size_t samples) const = 0;

    /// True when the set is the open disc |p - centre|^2 < radius2 and inside() and
    /// inversion_factor() about `centre` compute exactly that and radius2 / |d|^2 (the values
    /// rounded to the batch's type, no FMA): an `inversion` about the centre then describes
    /// itself as a KnownKernel. The default is false.
    virtual bool as_circle(Vec2& centre, double& radius2) const;
};

} // namespace fp
