// Issue 43, item 9: a streamed PNG cancelled before its first rows are written says fixpoint's
// one line alone; libpng's own line ("libpng error: No IDATs written into file", printed as
// the unfinished encoder is dropped) is not printed before it (framework/image/oiio.cpp).
#include "cli.hpp"

#include <gtest/gtest.h>

TEST(Cancel, AStreamedPngSaysOnlyFixpointsLine) {
    const auto dir = fp::test::scratch_dir("cancel_png");
    // In strips (--memory), each strip iterates every chain: the first takes seconds at 2e9
    // points, and the signal comes while no row is written. A signal before the handler is in
    // place would kill it without the line, which fails the test rather than passing it.
    const std::string render = fp::test::fixpoint_bin() + " render " + fp::test::source_dir() +
                               "/configs/inversion/fig6a.yaml -o big.png --memory 24M --threads 1 --set "
                               "renderer.width=4000 --set renderer.height=4000 --set renderer.points=2e9";
    const auto r = fp::test::shell(dir, render + " & pid=$!; sleep 1.5; kill -INT $pid; wait $pid");
    EXPECT_EQ(r.rc, 130);
    EXPECT_EQ(r.err, "fixpoint: interrupted; no image written\n");
    EXPECT_TRUE(fp::test::files_in(dir).empty());
}
