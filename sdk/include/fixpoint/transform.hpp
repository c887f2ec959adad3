// Transform: a map of the plane, applied in place to batches of points.
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/object.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace fp {

/// A map a renderer may run in its own fused, vectorised loop instead of calling apply()
/// and contains() on batches (chaos-game does, when every map of a recipe is of one kind).
/// The contract is exact: with T the batch's type (float or double), every value below
/// rounded to T first and no FMA contraction, the Transform's apply() and contains() must
/// give the same bits as
///   circle_inversion: d = p - (cx, cy); s = r2 / (d.x * d.x + d.y * d.y);
///                     T(p) = (cx + s * d.x, cy + s * d.y);
///                     contains(p) = d.x * d.x + d.y * d.y < r2
///                     (inversion in the circle of centre (cx, cy) and squared radius r2,
///                     paper 01 eq. (2));
///   affine:           with c = {a, b, c, d, e, f}: T(p) = ((a x + b y) + e, (c x + d y) + f),
///                     no set (has_region() is false);
///   gumowski_mira:    with c = {alpha, mu, m2} (m2 = 2 (1 - mu)), f(u) = mu u + (m2 u u) / (1 + u u)
///                     with u u computed once: x' = (y + (alpha (1 - (0.05 y) y)) y) + f(x),
///                     y' = -x + f(x'), no set (paper 03 eq. (1));
/// so that a render is the same image whichever way the renderer runs the map.
struct KnownKernel {
    enum class Kind : std::uint32_t { none, circle_inversion, affine, gumowski_mira };
    Kind kind = Kind::none;
    double cx = 0, cy = 0, r2 = 0; ///< circle_inversion
    double c[6] = {};              ///< affine, gumowski_mira: the coefficients above
};

/// The translations a periodic map forgets: T(p + m a + n b) = T(p) for all integers m, n (in
/// real arithmetic; floating point agrees up to rounding), and the smallest rectangle whose
/// sides (width, 0) and (0, height) are such translations: one period of any picture that
/// depends on p only through T(p), as a rectangular image tile.
struct PeriodLattice {
    Vec2 a, b;
    double width = 0, height = 0;
};

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
    /// The point drawn with the set (an inversion's centre of inversion, paper 01's figures);
    /// none by default.
    virtual std::optional<Vec2> region_centre() const;

    /// T(T(p)) = p: the conformance suite checks it; renderers may use it.
    virtual bool is_involution() const;
    /// Where finite input must give finite output (conformance suite samples this box).
    virtual Box sample_domain() const;

    /// Empty when apply() maps points of the plane (the default); otherwise why not (a
    /// subdivision rule whose lifted coordinates feed x and y maps whole vertex sets only).
    /// Renderers that call apply() refuse such a map when they are built, so that `validate`
    /// refuses it too; apply() throws fp::InputError with the same text.
    virtual std::string plane_map_problem() const;

    /// The map as a known kernel (see KnownKernel), when it is one; the default is none.
    virtual KnownKernel kernel() const;

    /// True when apply() draws random numbers (flam3's julia, blur, ...): from the batch's keys
    /// (fp::Points::key), which a chain-game renderer then fills from the chains' streams
    /// (fp::map_key), else from the points' bits. The default is false.
    virtual bool uses_random() const;

    /// The map's lattice of periods (see PeriodLattice), when it is periodic (the wallpaper
    /// maps); the default is none. `fixpoint render --tile` renders one rectangular period.
    virtual std::optional<PeriodLattice> periods() const;
};

} // namespace fp
