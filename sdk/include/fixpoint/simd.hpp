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
