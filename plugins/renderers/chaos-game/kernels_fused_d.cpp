// chaos-game's fused step in double (kernels-inl.hpp), compiled once per instruction set of the
// build and dispatched at run time: a translation unit of its own, so that two cores share the
// plugin's kernels (kernels.cpp has the stages).
#define FP_CHAOS_ENTRIES 3
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "chaos-game/kernels-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "chaos-game/kernels-inl.hpp"

namespace fp_chaos {
HWY_EXPORT(fused_d);
HWY_EXPORT(fused_run_d);

Counts fused(const FusedArgs<double>& a) { return HWY_DYNAMIC_DISPATCH(fused_d)(a); }
RunCounts fused_run(const FusedArgs<double>& a, uint64_t steps) {
    return HWY_DYNAMIC_DISPATCH(fused_run_d)(a, steps);
}
} // namespace fp_chaos
