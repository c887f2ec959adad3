// Xaos in the chaos game (a map item's `chaos`, flam3's; docs/flam3.md): after map i, map j's
// weight is multiplied by chaos_ij. Checked: on Sierpinski's triangle, forbidding 0 after 0
// leaves the triangle's corner of address 00 empty and every other corner of two letters lit;
// the render is the same bytes on 1 and 3 threads; with paper 01's rules on, a matrix that never
// goes to four of the eight circles of its Fig. 4a gives the picture of the other four; and a row
// of zeros gets one positioned line.
#include "cli.hpp"
#include "ssim.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace fp::test;

namespace {

std::string sierpinski(const std::string& chaos0) {
    return "renderer:\n  type: chaos-game\n  width: 64\n  height: 64\n  view: [0, 1, 0, 1]\n  points: "
           "400000\n"
           "  chains: 256\n  colourer: {type: density}\n  maps:\n"
           "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]" +
           chaos0 +
           "}\n"
           "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}\n"
           "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, 0.5]}\n";
}

/// Whether any pixel of the image's square [x0, x0 + 16) x [y0, y0 + 16) (in pixels of the
/// view [0, 1]^2 at 64 x 64, y up) is lit.
bool lit(const fp::Image& im, int x0, int y0) {
    for (int y = y0; y < y0 + 16; ++y)
        for (int x = x0; x < x0 + 16; ++x) {
            const int row = im.height - 1 - y;
            if (im.pixels[(std::size_t(row) * std::size_t(im.width) + std::size_t(x)) * 3] > 0) return true;
        }
    return false;
}

TEST(Xaos, ForbiddingATransitionEmptiesItsAddress) {
    const std::string dir = scratch_dir("xaos_address");
    write_file(dir + "/x.yaml", sierpinski(", chaos: [0]"));
    for (const char* t : {"1", "3"}) {
        const auto r =
            run_cli({"render", "--quiet", "--threads", t, dir + "/x.yaml", "-o", dir + "/x" + t + ".png"});
        ASSERT_EQ(r.rc, 0) << r.err;
    }
    EXPECT_EQ(read_file(dir + "/x1.png"), read_file(dir + "/x3.png"));
    const fp::Image im = fp::host::read_image(dir + "/x1.png");
    // Address ij (map i applied last): the quarter-size triangle at A_i A_j's corner. Corner of
    // A_0 A_0: [0, 1/4)^2, empty but for the chains' first points (skipped); A_1 A_0 = [1/2, 3/4) x
    // [0, 1/4) and A_0 A_1 = [1/4, 1/2) x [0, 1/4) lit.
    EXPECT_FALSE(lit(im, 0, 0));
    EXPECT_TRUE(lit(im, 32, 0));
    EXPECT_TRUE(lit(im, 16, 0));
    // Without xaos the corner is lit.
    write_file(dir + "/plain.yaml", sierpinski(""));
    const auto r = run_cli({"render", "--quiet", dir + "/plain.yaml", "-o", dir + "/plain.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(lit(fp::host::read_image(dir + "/plain.png"), 0, 0));
}

/// Paper 01's Fig. 4a (eight circles: four large, four small) under its rules; with `xaos`,
/// every map's `chaos` that row; with `large`, the four large circles alone.
std::string circles(const char* xaos, bool large = false) {
    const char* c[] = {"[1, 1], radius: 1",
                       "[-1, 1], radius: 1",
                       "[-1, -1], radius: 1",
                       "[1, -1], radius: 1",
                       "[0.30667, 0], radius: 0.21685",
                       "[0, 0.30667], radius: 0.21685",
                       "[-0.30667, 0], radius: 0.21685",
                       "[0, -0.30667], radius: 0.21685"};
    std::string s =
        "renderer:\n  type: chaos-game\n  width: 160\n  height: 160\n  view: [-1.75, 1.75, -1.75, 1.75]\n"
        "  points: 3000000\n  colourer: {type: density}\n  maps:\n";
    for (int j = 0; j < (large ? 4 : 8); ++j)
        s += std::string("    - {type: inversion, shape: {type: circle, centre: ") + c[j] + "}" +
             (xaos ? std::string(", chaos: ") + xaos : std::string()) + "}\n";
    return s;
}

TEST(Xaos, TheMatrixGoesWithPaper01sRules) {
    const std::string dir = scratch_dir("xaos_rules");
    // Never to a small circle (but at a chain's first step, which its skip hides): the picture of
    // the four large ones, the set rule still on (a 0 at a map's own place would be the rule
    // "not the previous map"; for circles the set rule implies it).
    write_file(dir + "/xaos.yaml", circles("[1, 1, 1, 1, 0, 0, 0, 0]"));
    write_file(dir + "/large.yaml", circles(nullptr, true));
    write_file(dir + "/all.yaml", circles(nullptr));
    for (const char* n : {"xaos", "large", "all"}) {
        const auto r = run_cli({"render", "--quiet", dir + "/" + n + ".yaml", "-o", dir + "/" + n + ".png"});
        ASSERT_EQ(r.rc, 0) << r.err;
    }
    const auto g = [&](const char* n) { return grey(fp::host::read_image(dir + "/" + n + ".png")); };
    const double same = ssim(g("large"), g("xaos"), 160, 160), other = ssim(g("large"), g("all"), 160, 160);
    EXPECT_GT(same, 0.95) << "all eight: " << other;
    EXPECT_GT(same, other + 0.05);
}

TEST(Xaos, ARowOfZerosIsRefused) {
    const std::string dir = scratch_dir("xaos_bad");
    write_file(dir + "/bad.yaml", sierpinski(", chaos: [0, 0, 0]"));
    const auto r = run_cli({"render", dir + "/bad.yaml", "-o", dir + "/bad.png"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("bad.yaml:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("maps[0].chaos: 0 for every map"), std::string::npos) << r.err;
    write_file(dir + "/long.yaml", sierpinski(", chaos: [1, 1, 1, 1]"));
    const auto l = run_cli({"render", dir + "/long.yaml", "-o", dir + "/long.png"});
    EXPECT_EQ(l.rc, 2);
    EXPECT_NE(l.err.find("4 entries for 3 maps"), std::string::npos) << l.err;
}

} // namespace
