// `fixpoint export`: a chaos-game config as a flam3 genome (docs/flam3.md). Checked: import,
// export and import again give the same config (the same lines but for comments, and numbers
// to 1e-12: the view goes through flam3's centre and scale); a config of fixpoint's own
// (affine maps, a variation, a palette of its own) exported renders in flam3-render as fixpoint
// renders it (SSIM); what a genome cannot hold gets one positioned line and exit 2.
#include "cli.hpp"
#include "ssim.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

bool have(const char* tool) {
    return std::system((std::string("command -v ") + tool + " >/dev/null 2>&1").c_str()) == 0;
}

/// A config's lines without comments and blank lines.
std::vector<std::string> lines(const std::string& yaml) {
    std::vector<std::string> out;
    std::istringstream in(yaml);
    for (std::string l; std::getline(in, l);) {
        const std::size_t c = l.find("  #");
        if (l.rfind('#', 0) == 0) continue;
        if (c != std::string::npos) l.erase(c);
        if (l.find_first_not_of(' ') == std::string::npos || l.find_first_not_of(' ') == l.find('#'))
            continue;
        out.push_back(l);
    }
    return out;
}

/// The same line but that each number may differ by 1e-12 relative.
bool same_line(const std::string& a, const std::string& b) {
    static const std::regex number(R"(-?[0-9][0-9.e+-]*)");
    const std::string ta = std::regex_replace(a, number, "N"), tb = std::regex_replace(b, number, "N");
    if (ta != tb) return false;
    std::sregex_iterator ia(a.begin(), a.end(), number), ib(b.begin(), b.end(), number), end;
    for (; ia != end && ib != end; ++ia, ++ib) {
        const double x = std::stod(ia->str()), y = std::stod(ib->str());
        if (std::fabs(x - y) > 1e-12 * std::max({1.0, std::fabs(x), std::fabs(y)})) return false;
    }
    return true;
}

TEST(Flam3Export, ImportExportImportIsTheSameConfig) {
    const std::string dir = scratch_dir("flam3_export_round");
    const std::string fx = fp::test::source_dir() + "/tests/fixtures/flam3/";
    for (const std::string g :
         {"genome-3", "genome-7", "genome-19", "parity/genome-002", "parity/genome-011"}) {
        const auto a = run_cli({"import", fx + g + ".flam3"});
        ASSERT_EQ(a.rc, 0) << a.err;
        write_file(dir + "/a.yaml", a.out);
        const auto e = run_cli({"export", "--quiet", dir + "/a.yaml", "-o", dir + "/b.flam3", "--force"});
        ASSERT_EQ(e.rc, 0) << e.err;
        EXPECT_EQ(e.err, "") << g; // nothing that the genome cannot hold
        const auto b = run_cli({"import", dir + "/b.flam3"});
        ASSERT_EQ(b.rc, 0) << b.err;
        const auto la = lines(a.out), lb = lines(b.out);
        ASSERT_EQ(la.size(), lb.size()) << g << "\n" << b.out;
        for (std::size_t i = 0; i < la.size(); ++i)
            EXPECT_TRUE(same_line(la[i], lb[i])) << g << "\n" << la[i] << "\n" << lb[i];
    }
}

// fixpoint's own config: Sierpinski's maps (affine), one of them a julia variation, a palette of
// its own, flam3's tone.
const char* own = R"(renderer:
  type: chaos-game
  width: 100
  height: 100
  view: [-0.2, 1.2, -0.2, 1.2]
  y_axis: down
  points: 10000
  estimator_radius: 4
  colourer: {type: flame, density: flam3, brightness: 3, gamma: 3, palette: sunset}
  maps:
    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0], color: 0}
    - {type: affine, coefficients: [0.5, 0.1, 0, 0.5, 0.5, 0], color: 0.5, weight: 2}
    - {type: julia, julia: 0.4, coefs: [0.5, 0, 0, 0.5, 0.25, 0.5], color: 1, color_speed: 0.3}
)";

TEST(Flam3Export, AnExportedConfigRendersInFlam3AsInFixpoint) {
    if (!have("flam3-render")) GTEST_SKIP() << "flam3-render (Debian's flam3-utils) is not installed";
    const std::string dir = scratch_dir("flam3_export_render");
    write_file(dir + "/own.yaml", own);
    const auto e = run_cli({"export", "--quiet", dir + "/own.yaml", "-o", dir + "/own.flam3"});
    ASSERT_EQ(e.rc, 0) << e.err;
    const std::string cmd = "cd " + dir + " && env ss=2 qs=100 nthreads=1 isaac_seed=one out=flam3.png " +
                            "flam3-render < own.flam3 >/dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const auto r =
        run_cli({"render", "--quiet", dir + "/own.yaml", "-o", dir + "/ours.png", "--set",
                 "renderer.width=200", "--set", "renderer.height=200", "--set", "renderer.points=4000000"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const fp::Image f = fp::host::read_image(dir + "/flam3.png"), o = fp::host::read_image(dir + "/ours.png");
    ASSERT_EQ(f.width, o.width);
    EXPECT_GT(ssim(grey(f), grey(o), o.width, o.height), 0.9);
}

TEST(Flam3Export, WhatAGenomeCannotHoldIsRefused) {
    const std::string dir = scratch_dir("flam3_export_bad");
    std::string inv = own;
    inv.replace(inv.find("{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]"), 51,
                "{type: inversion, shape: {type: circle}");
    write_file(dir + "/inv.yaml", inv);
    const auto a = run_cli({"export", dir + "/inv.yaml", "-o", dir + "/inv.flam3"});
    EXPECT_EQ(a.rc, 2);
    EXPECT_NE(a.err.find("inv.yaml:11:7: maps[0]: a genome holds xforms, flam3's variations and affine maps"),
              std::string::npos)
        << a.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/inv.flam3"));
    std::string mann = own;
    mann.replace(mann.find("  maps:"), 7, "  iteration: {type: mann, alpha: 0.5}\n  maps:");
    write_file(dir + "/mann.yaml", mann);
    const auto b = run_cli({"export", dir + "/mann.yaml"});
    EXPECT_EQ(b.rc, 2);
    EXPECT_NE(b.err.find("mann.yaml:10:"), std::string::npos) << b.err;
    EXPECT_NE(b.err.find("flam3 iterates its maps (Picard)"), std::string::npos) << b.err;
    // An existing genome is kept without --force.
    write_file(dir + "/own.yaml", own);
    write_file(dir + "/own.flam3", "keep");
    const auto c = run_cli({"export", dir + "/own.yaml", "-o", dir + "/own.flam3"});
    EXPECT_EQ(c.rc, 2);
    EXPECT_EQ(read_file(dir + "/own.flam3"), "keep");
}

} // namespace

// What a genome cannot hold is said, not dropped: flam3 chooses its kernels from the hits as
// they are, so estimator_quality is a warning (and the estimate itself is carried over).
TEST(Flam3Export, EstimatorQualityIsAWarning) {
    const std::string dir = scratch_dir("flam3_export_quality");
    write_file(dir + "/own.yaml", own);
    const auto e = run_cli({"export", dir + "/own.yaml", "-o", dir + "/own.flam3", "--set",
                            "renderer.estimator_radius=3", "--set", "renderer.estimator_quality=4"});
    ASSERT_EQ(e.rc, 0) << e.err;
    EXPECT_NE(e.err.find("warning: " + dir +
                         "/own.yaml: estimator_quality: flam3 chooses its kernels from the "
                         "hits as they are"),
              std::string::npos)
        << e.err;
    EXPECT_NE(read_file(dir + "/own.flam3").find("estimator_radius=\"3\""), std::string::npos);
}
