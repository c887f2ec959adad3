// chaos-game's kernels on the SIMD layer: every stage of a block step, compiled once per
// instruction set of the build (by chaos-game/kernels.cpp, which dispatches to them at run time,
// and by tests/unit/test_chaos_kernel.cpp, which calls them directly). What the stages compute is
// described in chaos-game.cpp's header; kernels.hpp holds their arguments. In parts, each a
// concern of its own, included here inside the per-target namespace (they are not headers of
// their own), each using the parts above it:
//   lanes-inl.hpp   lanes of 32-bit data, pcg32, points left, the maps' parameters per lane
//   choose-inl.hpp  the draw of a map per chain (paper 01's rules, Walker's alias table) and the
//                   grouping by map
//   book-inl.hpp    the bookkeeping, the bin index, the packed colours and their deposit
//   fused-inl.hpp   the fused step: every map a known kernel of one kind, steps 1-5 in one pass
//   lean-inl.hpp    lean runs of the fused step for a few chains
// then the entry points, one function per stage and precision.
//
// Each kernel works on whole vectors of chains: the block arrays hold block_size entries (a
// multiple of every target's lane count), so the lanes past the block's last chain are computed
// too (their values are never read) and only the counts are masked to the block. Integer lanes
// have the width of the chains' type (U = uint32_t for float, uint64_t for double), so that a
// chain's coordinates and its integer state share one lane layout; the 32-bit arrays are widened
// on load and narrowed on store for double, the 64-bit ones (pcg32 states, points left) are split
// in two for float. Floating point: + - * / and comparisons only, in the order of the scalar
// descriptions (no MulAdd), so every target gives the bits of the others
// (tests/unit/test_simd_targets.cpp).

#if defined(FP_CHAOS_KERNELS_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef FP_CHAOS_KERNELS_INL_HPP_
#undef FP_CHAOS_KERNELS_INL_HPP_
#else
#define FP_CHAOS_KERNELS_INL_HPP_
#endif

#include "kernels.hpp"

#include <fixpoint/check.hpp>
#include <fixpoint/kernels-inl.hpp>
#include <fixpoint/simd-inl.hpp>

#include <hwy/cache_control.h>
#include <hwy/highway.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

HWY_BEFORE_NAMESPACE();
namespace fp_chaos::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace fk = fp::kernels::HWY_NAMESPACE;
using std::size_t;
using std::uint32_t;
using std::uint64_t;

// Lanes of 32-bit data, pcg32, points left, the maps' parameters per lane.
#include "lanes-inl.hpp"
// The draw of a map per chain and the grouping by map.
#include "choose-inl.hpp"
// The bookkeeping and the deposit.
#include "book-inl.hpp"
// The fused step.
#include "fused-inl.hpp"
// Lean runs of the fused step.
#include "lean-inl.hpp"

// ---------------------------------------------------------------- the entry points
// Compiled in three translation units, so that two cores share the plugin's heaviest code
// (FP_CHAOS_ENTRIES: 1 the stages, kernels.cpp; 2 the fused step in float, kernels_fused_f.cpp;
// 3 in double, kernels_fused_d.cpp); undefined, all of them (the kernel tests).
#if !defined(FP_CHAOS_ENTRIES) || FP_CHAOS_ENTRIES == 1
void draw_rules(const fp_chaos::DrawArgs& a) { draw_rules_t(hn::ScalableTag<uint32_t>(), a); }
void draw_alias(const fp_chaos::DrawArgs& a) { draw_alias_t(a); }

void group_f(const fp_chaos::GroupArgs<float>& a) { group_t(a); }
void group_d(const fp_chaos::GroupArgs<double>& a) { group_t(a); }
void scatter_f(const float* gx, const float* gy, const uint32_t* gi, size_t n, float* x, float* y) {
    scatter_t(gx, gy, gi, n, x, y);
}
void scatter_d(const double* gx, const double* gy, const uint32_t* gi, size_t n, double* x, double* y) {
    scatter_t(gx, gy, gi, n, x, y);
}

fp_chaos::Counts bookkeep_f(const fp_chaos::BookArgs<float>& a, bool colour) { return bookkeep_t(a, colour); }
fp_chaos::Counts bookkeep_d(const fp_chaos::BookArgs<double>& a, bool colour) {
    return bookkeep_t(a, colour);
}
size_t deposit_colour(uint32_t* bins, const uint32_t* idx, const uint64_t* dep, size_t from, size_t nb,
                      uint32_t spill) {
    return deposit_colour_t(bins, idx, dep, from, nb, spill);
}

#endif
#if !defined(FP_CHAOS_ENTRIES) || FP_CHAOS_ENTRIES == 2
fp_chaos::Counts fused_f(const fp_chaos::FusedArgs<float>& f) { return fused_any(f); }
fp_chaos::RunCounts fused_run_f(const fp_chaos::FusedArgs<float>& f, uint64_t steps) {
    return fused_run_any(f, steps);
}
#endif
#if !defined(FP_CHAOS_ENTRIES) || FP_CHAOS_ENTRIES == 3
fp_chaos::Counts fused_d(const fp_chaos::FusedArgs<double>& f) { return fused_any(f); }
fp_chaos::RunCounts fused_run_d(const fp_chaos::FusedArgs<double>& f, uint64_t steps) {
    return fused_run_any(f, steps);
}
#endif

} // namespace fp_chaos::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif // per-target include guard
