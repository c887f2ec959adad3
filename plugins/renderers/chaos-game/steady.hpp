// chaos-game's bookkeeping of a step (what it computes; the kernel is in kernels-inl.hpp) and
// the steady runs of the fused step, which skip the part of it that cannot change and settle
// it when they end. Only chaos-game.cpp includes it.
#pragma once

#include "state.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace fp_chaos {

// ---------------------------------------------------------------- bookkeeping of a step
// After a step (kernels-inl.hpp's bookkeep_t, or the fused step with a colourer that needs no
// colour): for each chain, whether it moved, whether its point is finite (else: a bad value
// and a restart), whether it plots (moved, finite, past `skip`); its age, previous map, idle
// count, points left and activity; its bin (the last one, outside the image, when not plotted
// or outside the view: x in [xmin, xmax), y in (ymin, ymax], y = ymax the top row, indices
// clamped in case the products round up to width or height); and its colour packed
// {1, r, g, b} in 16 bits each (round(c * colour_scale), c clamped to [0, 1], NaN to 0).

// ---------------------------------------------------------------- steady runs
/// Whether a block may run steady (fp_chaos::fused_rules_step<true, true>): `budget` steps
/// when every active chain is past its skip, fewer than the fewest points any of them has
/// left (so that none runs out during the run); 0 otherwise. `wait`: steps before asking
/// again can help, when some chain is still young (its age grows by at most one a step), so
/// that a block full of restarting chains is not scanned at every step.
struct SteadyCheck {
    uint64_t budget = 0, wait = 0;
};

template <class T>
SteadyCheck steady_budget(const Scratch<T>& s, size_t nb, uint32_t skip) {
    const uint32_t* age = s.age.get();
    const uint32_t* active = s.active.get();
    const uint64_t* left = s.left.get();
    uint64_t fewest = UINT64_MAX;
    uint32_t youngest = skip; // the smallest age of an active chain, capped at skip
    for (size_t i = 0; i < nb; ++i) {
        const bool a = active[i] != 0;
        youngest = std::min(youngest, a ? age[i] : skip);
        fewest = std::min(fewest, a ? left[i] : UINT64_MAX);
    }
    if (youngest < skip) return {0, skip - youngest - 1};
    return {fewest == UINT64_MAX ? 0 : fewest - 1, 0};
}

/// The end of a steady run of `steps` steps: every active chain plotted at each step but the
/// last when that one restarted it (no allowed map, or a point not finite: restart[i] set),
/// so its points left and idle count become what the step-by-step bookkeeping would have
/// made them. Returns the points plotted.
template <class T>
uint64_t settle_steady(Scratch<T>& s, size_t nb, uint64_t steps) {
    const uint32_t* active = s.active.get();
    const uint32_t* restart = s.restart.get();
    uint64_t* left = s.left.get();
    uint32_t* idle = s.idle.get();
    uint64_t plotted = 0;
    for (size_t i = 0; i < nb; ++i) {
        if (!active[i]) continue;
        const uint64_t p = steps - (restart[i] ? 1 : 0);
        // A run longer than steady_budget allows would have plotted past a chain's last point
        // (and the chain would never finish): say so rather than spin.
        if (p >= left[i]) throw fp::InternalError("chaos-game: a steady run outlived a chain's points");
        left[i] -= p;
        if (p) idle[i] = 0;
        plotted += p;
    }
    return plotted;
}

} // namespace fp_chaos
