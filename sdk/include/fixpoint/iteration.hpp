// IterationScheme: one step of a fixed-point iteration process that replaces the Picard
// step p <- T(p) (paper 02). Every application of T inside one step uses the same map.
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/object.hpp>
#include <fixpoint/scheme_program.hpp>
#include <fixpoint/transform.hpp>

#include <cstdint>

namespace fp {

class IterationScheme : public Object {
public:
    ~IterationScheme() override;

    /// One step of the process at step index `n` (counted from 0; parameter sequences are
    /// indexed by it) for every active point of the batch, in place.
    virtual void step(const Transform& t, Points<float> p, Mask mask, std::uint64_t n) const = 0;
    virtual void step(const Transform& t, Points<double> p, Mask mask, std::uint64_t n) const = 0;

    /// Applications of T per step (the cost relative to Picard).
    virtual unsigned applications() const;

    /// Called by renderers before they start, for each map, with the largest step index a
    /// render will reach when nothing restarts: a scheme whose cost grows with n (Schu on maps
    /// that are not involutions) throws fp::InputError here, so that `validate` refuses what
    /// the render would. The default accepts everything.
    virtual void check_steps(const Transform& t, std::uint64_t last_n) const;

    /// True when step() is exactly t.apply(p, mask) at every n (the Picard iteration): a
    /// renderer may then run a Transform's KnownKernel in its own fused loop. The conformance
    /// suite checks the promise bit for bit. The default is false.
    virtual bool is_picard() const;

    /// Step n on map t as a SchemeProgram (scheme_program.hpp), for a renderer that runs it in
    /// its own vectorised loop: true and `out` filled when step() at n on t is exactly
    /// run_program(out, t, .) for every point, in the precision asked for (`dbl`: double, else
    /// float); false when the step is not such a program (the renderer calls step()). The
    /// conformance suite checks the promise bit for bit. fp::SchemeBase records it from the
    /// kernel; the default is false.
    virtual bool program(const Transform& t, std::uint64_t n, bool dbl, SchemeProgram& out) const;
};

} // namespace fp
