// The polygon shapes' batch kernels, dispatched at run time: polygon-inl.hpp compiled for
// every SIMD target of the build. Included (through polygon_core.hpp) by each plugin that
// uses PolygonShape; each plugin is one translation unit, so each gets its own copy.
#pragma once

#include <fixpoint/batch.hpp>

#include <cstddef>

namespace fp_shapes {

/// Per-edge data of a polygon in one precision, relative to a reference point: vx, vy hold
/// n + 1 entries (the first repeated at the end), the others n.
template <class T>
struct EdgeView {
    std::size_t n = 0;
    const T *vx = nullptr, *vy = nullptr, *ex = nullptr, *ey = nullptr, *sx = nullptr, *s_lo = nullptr,
            *s_hi = nullptr;
};

} // namespace fp_shapes

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shapes/polygon-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "shapes/polygon-inl.hpp"

namespace fp_shapes {
HWY_EXPORT(inside_f);
HWY_EXPORT(inside_d);
HWY_EXPORT(ray_f);
HWY_EXPORT(ray_d);

// (HWY_DYNAMIC_DISPATCH names the kernels unqualified: a build with static dispatch only
// resolves them as N_<target>::name from this namespace.)
inline void polygon_inside(const EdgeView<float>& e, float rx, float ry, fp::Points<const float> p,
                           unsigned char* out) {
    HWY_DYNAMIC_DISPATCH(inside_f)(e, rx, ry, p, out);
}
inline void polygon_inside(const EdgeView<double>& e, double rx, double ry, fp::Points<const double> p,
                           unsigned char* out) {
    HWY_DYNAMIC_DISPATCH(inside_d)(e, rx, ry, p, out);
}
inline void polygon_ray(const EdgeView<float>& e, float ox, float oy, fp::Points<const float> d, float* t) {
    HWY_DYNAMIC_DISPATCH(ray_f)(e, ox, oy, d, t);
}
inline void polygon_ray(const EdgeView<double>& e, double ox, double oy, fp::Points<const double> d,
                        double* t) {
    HWY_DYNAMIC_DISPATCH(ray_d)(e, ox, oy, d, t);
}
} // namespace fp_shapes
