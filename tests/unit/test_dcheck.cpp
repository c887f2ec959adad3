// FP_DCHECK (fixpoint/check.hpp): with NDEBUG undefined (the Debug and sanitizer builds) a false
// condition aborts with the file, the line and the condition on stderr; with NDEBUG defined
// (Release) the condition is not evaluated at all. Both forms are checked here, whatever the
// build, since the header follows NDEBUG at each inclusion as <cassert> does.
#include <gtest/gtest.h>

namespace {

int evaluated = 0;
bool counted(bool v) {
    ++evaluated;
    return v;
}

#undef NDEBUG
#include <fixpoint/check.hpp>

void active_true() { FP_DCHECK(counted(true)); }
void active_false() { FP_DCHECK(counted(1 + 1 == 3)); }

#define NDEBUG
#include <fixpoint/check.hpp>

void inactive_false() { FP_DCHECK(counted(false)); }

TEST(DCheck, ActiveWithoutNdebugAbortsNamingTheCondition) {
    evaluated = 0;
    active_true();
    EXPECT_EQ(evaluated, 1);
    EXPECT_DEATH(active_false(), "test_dcheck.cpp:[0-9]+: FP_DCHECK\\(counted\\(1 \\+ 1 == 3\\)\\) failed");
}

TEST(DCheck, CompiledOutWithNdebug) {
    evaluated = 0;
    inactive_false();
    EXPECT_EQ(evaluated, 0);
}

} // namespace
