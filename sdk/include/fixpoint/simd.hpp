// The SIMD layer's host side: which instruction set the dispatched kernels run on, and a way
// to pin it (tests, benchmarks, `fixpoint --simd`).
//
// Kernels are written once with Google Highway in a per-target header (see simd-inl.hpp) and
// compiled for every target of the build (SSE4, AVX2, AVX-512 on x86; NEON, SVE on ARM; a
// portable 128-bit emulation everywhere); at run time each call goes to the best target the
// CPU has. Highway's choice is process-wide (it lives in libhwy, which the host and every
// plugin share), so pinning a target here pins it for every plugin.
//
// Renders do not depend on the target: kernels use no fused multiply-add (the build has
// -ffp-contract=off and no kernel calls MulAdd), no approximate reciprocal or square root,
// and only IEEE-exact operations (+, -, *, /, sqrt, comparisons, conversions), so every lane
// width rounds alike; tests/unit/test_simd_targets.cpp renders recipes on every target.
#pragma once

#include <string>
#include <string_view>
#include <vector>

/// For the per-point functions of plugins that use FIXPOINT_SIMD_SHAPE:
/// inlined into the loops compiled per target (a call per point would also keep them scalar).
#define FIXPOINT_INLINE [[gnu::always_inline]] inline

// A shape written per point (inside_pt, ray_exit_pt, as for fp::ShapeBase), its batch loops
// compiled per target. In the plugin's file, after the class (which declares the four batch
// overrides with FIXPOINT_SIMD_SHAPE_OVERRIDES) and outside any namespace:
//
//   #undef HWY_TARGET_INCLUDE
//   #define HWY_TARGET_INCLUDE "my-shape.cpp"   // this file
//   #include <hwy/foreach_target.h>
//   #include <fixpoint/simd-inl.hpp>
//   FIXPOINT_SIMD_SHAPE(my_shape, MyShape)      // per target: the loops
//   #if HWY_ONCE
//   FIXPOINT_SIMD_SHAPE_DISPATCH(my_shape, MyShape)
//   FIXPOINT_PLUGIN(...)
//   #endif
//
// The class itself must be compiled once only: keep it above, inside #ifndef MY_SHAPE_CLASS /
// #define MY_SHAPE_CLASS ... #endif (foreach_target compiles the file once per target).
// tests/external-plugin/ellipse.cpp is a complete example.
#define FIXPOINT_SIMD_SHAPE_OVERRIDES                                                                        \
    void inside(fp::Points<const float> p, unsigned char* out) const override;                               \
    void inside(fp::Points<const double> p, unsigned char* out) const override;                              \
    void ray_exit(fp::Vec2 o, fp::Points<const float> d, float* t) const override;                           \
    void ray_exit(fp::Vec2 o, fp::Points<const double> d, double* t) const override;

#define FIXPOINT_SIMD_SHAPE(ns, Class)                                                                       \
    HWY_BEFORE_NAMESPACE();                                                                                  \
    namespace ns::HWY_NAMESPACE {                                                                            \
    void inside_f(const Class& s, fp::Points<const float> p, unsigned char* out) {                           \
        fp::simd::HWY_NAMESPACE::shape_inside(s, p, out);                                                    \
    }                                                                                                        \
    void inside_d(const Class& s, fp::Points<const double> p, unsigned char* out) {                          \
        fp::simd::HWY_NAMESPACE::shape_inside(s, p, out);                                                    \
    }                                                                                                        \
    void ray_f(const Class& s, fp::Vec2 o, fp::Points<const float> d, float* t) {                            \
        fp::simd::HWY_NAMESPACE::shape_ray_exit(s, o, d, t);                                                 \
    }                                                                                                        \
    void ray_d(const Class& s, fp::Vec2 o, fp::Points<const double> d, double* t) {                          \
        fp::simd::HWY_NAMESPACE::shape_ray_exit(s, o, d, t);                                                 \
    }                                                                                                        \
    }                                                                                                        \
    HWY_AFTER_NAMESPACE();

#define FIXPOINT_SIMD_SHAPE_DISPATCH(ns, Class)                                                              \
    namespace ns {                                                                                           \
    HWY_EXPORT(inside_f);                                                                                    \
    HWY_EXPORT(inside_d);                                                                                    \
    HWY_EXPORT(ray_f);                                                                                       \
    HWY_EXPORT(ray_d);                                                                                       \
    }                                                                                                        \
    void Class::inside(fp::Points<const float> p, unsigned char* out) const {                                \
        using namespace ns; /* N_<target>:: with static dispatch */                                          \
        HWY_DYNAMIC_DISPATCH(inside_f)(*this, p, out);                                                       \
    }                                                                                                        \
    void Class::inside(fp::Points<const double> p, unsigned char* out) const {                               \
        using namespace ns; /* N_<target>:: with static dispatch */                                          \
        HWY_DYNAMIC_DISPATCH(inside_d)(*this, p, out);                                                       \
    }                                                                                                        \
    void Class::ray_exit(fp::Vec2 o, fp::Points<const float> d, float* t) const {                            \
        using namespace ns; /* N_<target>:: with static dispatch */                                          \
        HWY_DYNAMIC_DISPATCH(ray_f)(*this, o, d, t);                                                         \
    }                                                                                                        \
    void Class::ray_exit(fp::Vec2 o, fp::Points<const double> d, double* t) const {                          \
        using namespace ns; /* N_<target>:: with static dispatch */                                          \
        HWY_DYNAMIC_DISPATCH(ray_d)(*this, o, d, t);                                                         \
    }

namespace fp::simd {

/// The target the dispatched kernels use now, in Highway's words ("AVX3", "AVX2", "SSE4",
/// "EMU128", "NEON", "SVE", ...).
std::string active_target();

/// The targets this CPU supports among those the SDK was compiled for, best first.
std::vector<std::string> supported_targets();

/// Dispatch to `name` (one of supported_targets(), case-insensitive) from now on; "" or
/// "best" returns to the best one. False, and nothing changed, when the name is not one of
/// them. Call it before rendering, not while kernels run on other threads.
bool force_target(std::string_view name);

} // namespace fp::simd
