// orbit-trap's passes over its batch (orbit-trap/kernels-inl.hpp), compiled once per
// instruction set of the build and dispatched at run time: the functions batch.hpp declares.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "orbit-trap/kernels-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "orbit-trap/kernels-inl.hpp"

namespace fp_orbit_trap {
HWY_EXPORT(retire_f);
HWY_EXPORT(retire_d);
HWY_EXPORT(test_retire_f);
HWY_EXPORT(test_retire_d);
HWY_EXPORT(tile_starts_f);
HWY_EXPORT(tile_starts_d);
HWY_EXPORT(tile_mean_all);

void tile_starts(const TileFrame& f, Scratch<float>& s, size_t p0, size_t np) {
    HWY_DYNAMIC_DISPATCH(tile_starts_f)(f, s, p0, np);
}
void tile_starts(const TileFrame& f, Scratch<double>& s, size_t p0, size_t np) {
    HWY_DYNAMIC_DISPATCH(tile_starts_d)(f, s, p0, np);
}
void tile_mean(const float* rgb, uint32_t* q, uint64_t* sum, size_t np, size_t ns, float* out) {
    HWY_DYNAMIC_DISPATCH(tile_mean_all)(rgb, q, sum, np, ns, out);
}

size_t retire(Scratch<float>& s, size_t live, uint32_t it) {
    return HWY_DYNAMIC_DISPATCH(retire_f)(s, live, it);
}
size_t retire(Scratch<double>& s, size_t live, uint32_t it) {
    return HWY_DYNAMIC_DISPATCH(retire_d)(s, live, it);
}
size_t test_retire(const KnownCircles<float>& c, Scratch<float>& s, size_t live, uint32_t it, Reduction red,
                   bool check, bool& outside) {
    return HWY_DYNAMIC_DISPATCH(test_retire_f)(c, s, live, it, red, check, outside);
}
size_t test_retire(const KnownCircles<double>& c, Scratch<double>& s, size_t live, uint32_t it, Reduction red,
                   bool check, bool& outside) {
    return HWY_DYNAMIC_DISPATCH(test_retire_d)(c, s, live, it, red, check, outside);
}
} // namespace fp_orbit_trap
