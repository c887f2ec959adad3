// chaos-game's kernels (kernels-inl.hpp: every stage of a step), compiled once per instruction set
// of the build and dispatched at run time: the functions kernels.hpp declares. Here the stages;
// the fused step in kernels_fused_f.cpp and kernels_fused_d.cpp (two cores share the three).
#define FP_CHAOS_ENTRIES 1
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "chaos-game/kernels-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "chaos-game/kernels-inl.hpp"

namespace fp_chaos {
HWY_EXPORT(draw_rules);
HWY_EXPORT(draw_alias);
HWY_EXPORT(group_f);
HWY_EXPORT(group_d);
HWY_EXPORT(scatter_f);
HWY_EXPORT(scatter_d);
HWY_EXPORT(bookkeep_f);
HWY_EXPORT(bookkeep_d);
HWY_EXPORT(deposit_colour);

void draw_by_rules(const DrawArgs& a) { HWY_DYNAMIC_DISPATCH(draw_rules)(a); }
void draw_by_alias(const DrawArgs& a) { HWY_DYNAMIC_DISPATCH(draw_alias)(a); }
void group(const GroupArgs<float>& a) { HWY_DYNAMIC_DISPATCH(group_f)(a); }
void group(const GroupArgs<double>& a) { HWY_DYNAMIC_DISPATCH(group_d)(a); }
void scatter(const float* gx, const float* gy, const uint32_t* gi, size_t n, float* x, float* y) {
    HWY_DYNAMIC_DISPATCH(scatter_f)(gx, gy, gi, n, x, y);
}
void scatter(const double* gx, const double* gy, const uint32_t* gi, size_t n, double* x, double* y) {
    HWY_DYNAMIC_DISPATCH(scatter_d)(gx, gy, gi, n, x, y);
}
Counts bookkeep(const BookArgs<float>& a, bool colour) { return HWY_DYNAMIC_DISPATCH(bookkeep_f)(a, colour); }
Counts bookkeep(const BookArgs<double>& a, bool colour) {
    return HWY_DYNAMIC_DISPATCH(bookkeep_d)(a, colour);
}
size_t deposit_colours(uint32_t* bins, const uint32_t* idx, const uint64_t* dep, size_t from, size_t nb,
                       uint32_t spill) {
    return HWY_DYNAMIC_DISPATCH(deposit_colour)(bins, idx, dep, from, nb, spill);
}
} // namespace fp_chaos
