// FP_DCHECK(cond): an assertion for the hot paths (pbrt-v4's DCHECK). Active where NDEBUG is not
// defined (the Debug and sanitizer builds), compiled out in Release, where it costs nothing: the
// condition is not evaluated, only checked by the compiler.
//
// Why not assert(): a failed assert prints only the expression; FP_DCHECK names the file and line
// of the kernel that broke its invariant and aborts, so that the sanitizer build's report (and a
// core dump) stops at the first wrong index rather than at the memory it went on to corrupt.
// Use it for the invariants a kernel relies on and cannot afford to test in Release: indices in
// range, lane counts, bin and map indices. Bad input is never a DCHECK: it is an fp::InputError.
//
// Like <cassert>, this header may be included again after NDEBUG changes: the macro follows
// NDEBUG as it stands at each inclusion (tests/unit/test_dcheck.cpp checks both forms).

#ifndef FIXPOINT_CHECK_HPP_
#define FIXPOINT_CHECK_HPP_

#include <cstdio>
#include <cstdlib>

namespace fp::detail {

/// Reports a broken FP_DCHECK and aborts. Out of line and cold: the check's branch stays small in
/// the loops it guards.
[[noreturn, gnu::cold, gnu::noinline]] inline void dcheck_failed(const char* cond, const char* file,
                                                                 int line) {
    std::fprintf(stderr, "%s:%d: FP_DCHECK(%s) failed\n", file, line, cond);
    std::fflush(stderr);
    std::abort();
}

} // namespace fp::detail

#endif // FIXPOINT_CHECK_HPP_

#undef FP_DCHECK
#ifdef NDEBUG
// (sizeof: the condition still compiles, so a check cannot rot in Release, but is never run.)
#define FP_DCHECK(cond) static_cast<void>(sizeof(static_cast<bool>(cond)))
#else
#define FP_DCHECK(cond)                                                                                      \
    (__builtin_expect(static_cast<bool>(cond), 1) ? static_cast<void>(0)                                     \
                                                  : ::fp::detail::dcheck_failed(#cond, __FILE__, __LINE__))
#endif
