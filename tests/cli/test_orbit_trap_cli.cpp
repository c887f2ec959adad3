// The orbit-trap pipeline through the CLI (paper 04): a small render is written and its recipe
// renders the same bytes; bad input of the metrics, the circles trap, the colour map and the
// renderer ends with one golden error line, exit code 2, and nothing written.
#include "cli.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

// Gumowski-Mira as the map: the pipeline does not depend on the wallpaper transform here.
const std::string base = R"(renderer:
  type: orbit-trap
  width: 32
  height: 32
  samples: 1
  max_iterations: 20
  mapping: {type: gumowski-mira}
  traps: {type: circles, preset: fig-3b}
  colourer: {type: colour-map, preset: fig-4a}
)";

struct Case {
    const char* name;
    std::string yaml;
    std::string expected;
};

std::vector<Case> cases() {
    return {
        {"lp_p_below_one",
         replace_once(base, "preset: fig-3b}", "metric: {type: lp, p: 0.5}, preset: fig-3b}"),
         "bad.yaml:8:48: renderer.traps.metric.p: the lp metric needs p >= 1 (for p < 1 the triangle "
         "inequality "
         "fails), got 0.5"},
        {"rickman_gamma",
         replace_once(base, "preset: fig-3b}", "metric: {type: rickman, gamma: 1.5}, preset: fig-3b}"),
         "bad.yaml:8:57: renderer.traps.metric.gamma: Rickman's rug metric needs gamma in the open interval "
         "(0, 1), "
         "got 1.5"},
        {"colour_map_E", replace_once(base, "preset: fig-4a}", "preset: fig-4a, E: 0}"),
         "bad.yaml:9:51: renderer.colourer.E: must be > 0, got 0"},
        {"ratios_not_increasing",
         replace_once(base, "preset: fig-4a}",
                      "colours: [0, 0, 0, 255, 0, 0, 9, 9, 9], ratios: [0, 0.8, 0.7]}"),
         "bad.yaml:9:80: renderer.colourer.ratios: the ratios must increase strictly: ratios[2] = 0.7 is not "
         "above "
         "ratios[1] = 0.8"},
        {"ratio_outside",
         replace_once(base, "preset: fig-4a}", "colours: [0, 0, 0, 255, 0, 0], ratios: [0, 1.2]}"),
         "bad.yaml:9:75: renderer.colourer.ratios[1]: must be in [0, 1], got 1.2"},
        {"Nc_below_two", replace_once(base, "preset: fig-4a}", "preset: fig-4a, Nc: 1}"),
         "bad.yaml:9:52: renderer.colourer.Nc: must be in [2, 16777216], got 1"},
        {"no_traps", replace_once(base, "{type: circles, preset: fig-3b}", "{type: circles}"),
         "bad.yaml:8:10: renderer.traps: no traps: give centres and radii, or a preset (fig-1a, fig-1b, "
         "fig-1c, "
         "fig-1d, fig-3a, fig-3b, fig-3c)"},
        {"radius_zero", replace_once(base, "preset: fig-3b}", "centres: [[0, 0], [1, 1]], radii: [1, 0]}"),
         "bad.yaml:8:64: renderer.traps.radii[1]: must be > 0, got 0"},
        {"colourer_without_traps",
         replace_once(base, "{type: colour-map, preset: fig-4a}", "{type: density}"),
         "bad.yaml:9:13: renderer.colourer: this colourer cannot colour orbit-trap hits (use colour-map)"},
        {"samples_three", replace_once(base, "samples: 1", "samples: 3"),
         "bad.yaml:5:12: renderer.samples: expected 1, 8 or a square number (4, 9, 16, ...) of samples: "
         "patterns "
         "closed under the square's symmetries, got 3"},
    };
}

class OrbitTrapBadInput : public testing::TestWithParam<Case> {};

TEST_P(OrbitTrapBadInput, OneLineExitTwoNoOutput) {
    const Case& c = GetParam();
    EXPECT_EQ(fp::test::run_bad_input(std::string("orbit_trap_bad_") + c.name, c.yaml), c.expected);
}

INSTANTIATE_TEST_SUITE_P(Cli, OrbitTrapBadInput, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

TEST(OrbitTrapCli, RendersAndItsRecipeRendersTheSameBytes) {
    const std::string dir = fp::test::scratch_dir("orbit_trap_recipe");
    fp::test::write_file(dir + "/ot.yaml", base);
    auto r = run_cli({"render", "--quiet", dir + "/ot.yaml", "-o", dir + "/a.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = run_cli({"recipe", dir + "/a.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    fp::test::write_file(dir + "/again.yaml", r.out);
    r = run_cli({"render", "--quiet", dir + "/again.yaml", "-o", dir + "/b.png", "--threads", "1"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(fp::test::read_file(dir + "/a.png"), fp::test::read_file(dir + "/b.png"));
}

} // namespace
