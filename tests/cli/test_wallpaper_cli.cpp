// Bad wallpaper coefficients through the CLI: one error line naming the place, exit code 2,
// nothing written. The messages are golden (users see them). The map sits in a chaos-game, the
// smallest renderer that takes a transform; `render` checks everything before it renders.
#include "cli.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

struct Case {
    const char* name;
    std::string map; // the map's keys beside `type: wallpaper`, one per line, indented by 6
    std::string expected;
};

std::string config(const std::string& map) {
    return "renderer:\n"
           "  type: chaos-game\n"
           "  width: 16\n"
           "  height: 16\n"
           "  points: 1000\n"
           "  maps:\n"
           "    - type: wallpaper\n" +
           map;
}

std::vector<Case> cases() {
    const std::string fig8_head = "      group: p4m\n"
                                  "      P03: [0, -0.234602]\n"
                                  "      P23: [0, 0.429163]\n";
    return {
        {"unknown_group", "      group: p5\n      seed: 1\n",
         "bad.yaml:8:14: renderer.maps[0].group: must be one of 'p1', 'p2', 'pm', 'pg', 'cm', 'pmm', 'cmm', "
         "'pmg', 'pgg', 'p4', 'p4m', 'p4g', 'p3', 'p3m1', 'p31m', 'p6' or 'p6m', got 'p5'"},
        {"matrix_shape",
         "      group: p1\n      P: [[1, 0], [0, 1], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], "
         "[0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], "
         "[0, 0], [0, 0], [0, 0]]\n",
         "bad.yaml:9:10: renderer.maps[0].P: P must be the 5 x 5 matrix of pairs [x, y], row by row (25 "
         "pairs, "
         "P00 ... P04, P10, ...), got 24 pairs"},
        {"fig8_misprint", fig8_head + "      P30: [-0.234602, 0]\n      P32: [0.422963, 0]\n",
         "bad.yaml:12:12: renderer.maps[0].P32: P32 = [0.422963, 0] breaks p4m's P32.x = P23.y (0.429163)"},
        {"must_vanish", "      group: pm\n      P13: [0.5, 0.25]\n",
         "bad.yaml:9:12: renderer.maps[0].P13: P13 = [0.5, 0.25] breaks pm's P13.x = 0"},
        {"hexagonal_with_P", "      group: p3m1\n      P03: [0, 1]\n",
         "bad.yaml:9:12: renderer.maps[0].P03: P03 is for the square-lattice groups (p1 ... p4g); p3m1 takes "
         "G "
         "and H (or G_v0 ... H_v2)"},
        {"square_with_G", "      group: p4\n      G_v1: [0, 1]\n",
         "bad.yaml:9:13: renderer.maps[0].G_v1: G_v1 is for the hexagonal groups (p3, p3m1, p31m, p6, p6m); "
         "p4 "
         "takes P (or P00 ... P44)"},
        {"G_shape", "      group: p6m\n      G: [[0, 1], [1, 0]]\n",
         "bad.yaml:9:10: renderer.maps[0].G: G must be [G_v0, G_v1, G_v2] (3 pairs [x, y]), got 2 pairs"},
        {"seed_and_coefficients", "      group: p4\n      seed: 3\n      P03: [0, 1]\n",
         "bad.yaml:9:13: renderer.maps[0].seed: give either a seed (random coefficients) or the "
         "coefficients, "
         "not both"},
        {"no_coefficients", "      group: cmm\n",
         "bad.yaml:7:7: renderer.maps[0]: give the coefficients (P, or P00 ... P44) or a seed"},
        {"reduction", "      group: p2\n      seed: 1\n      reduction: mod\n",
         "bad.yaml:10:18: renderer.maps[0].reduction: must be one of 'fmod', 'centred', 'floor', 'none' or "
         "'hexagonal', got 'mod'"},
        {"hexagonal_on_square", "      group: p4m\n      seed: 1\n      reduction: hexagonal\n",
         "bad.yaml:10:18: renderer.maps[0].reduction: hexagonal is for the hexagonal groups (p3, "
         "p3m1, p31m, p6, p6m), whose lattice of periods is hexagonal; p4m's is the square lattice 2 pi Z^2 "
         "(use fmod, centred, floor or none)"},
    };
}

class WallpaperBadInput : public testing::TestWithParam<Case> {};

TEST_P(WallpaperBadInput, OneLineExitTwoNoOutput) {
    const Case& c = GetParam();
    EXPECT_EQ(fp::test::run_bad_input(std::string("wallpaper_bad_") + c.name, config(c.map)), c.expected);
}

INSTANTIATE_TEST_SUITE_P(Cli, WallpaperBadInput, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

TEST(WallpaperCli, EvalMatchesTheHandValue) {
    // f = P00 + P13 cos x sin y with P00 = (0.5, -0.25), P13 = (1, 2): f(0, pi/2) = (1.5, 1.75).
    const auto r = run_cli({"eval", "{type: wallpaper, group: p1, P00: [0.5, -0.25], P13: [1, 2]}"},
                           "0 1.5707963267948966\n");
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(r.out, "1.5 1.75\n");
}

} // namespace
