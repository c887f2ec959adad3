// `fixpoint addresses --where`: paper 05's Algorithm 1 by a predicate instead of by eye. On
// configs/mfs/fig4-middle.yaml, level 1 is the unit square cut into 3 x 3 quads of side 1/3,
// addressed 1 2 3 (bottom row, y up), 4 5 6, 7 8 9: the expected lines follow by hand.
#include "cli.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

std::string addresses(const std::vector<std::string>& where) {
    std::vector<std::string> args = {"addresses", fp::test::source_dir() + "/configs/mfs/fig4-middle.yaml",
                                     "--level", "1"};
    for (const auto& w : where) args.insert(args.end(), {"--where", w});
    const auto r = run_cli(args);
    EXPECT_EQ(r.rc, 0) << r.err;
    return r.out;
}

} // namespace

TEST(AddressesWhere, CentreInABoxFindsTheMiddleQuad) {
    EXPECT_EQ(addresses({"centre in [0.4, 0.6, 0.4, 0.6]"}),
              "5 (0.333333, 0.333333) (0.666667, 0.333333) (0.333333, 0.666667) (0.666667, 0.666667)\n");
}

TEST(AddressesWhere, MeetsInsideAndTheirConjunction) {
    // The top right corner: only quad 9 has a vertex there.
    EXPECT_EQ(addresses({"meets [0.9, 1, 0.9, 1]"}),
              "9 (0.666667, 0.666667) (1, 0.666667) (0.666667, 1) (1, 1)\n");
    // The bottom row lies inside y <= 0.34; of it, centre x >= 0.51 keeps quad 3 alone (2's is 0.5).
    const std::string bottom = addresses({"inside [0, 1, 0, 0.34]"});
    EXPECT_EQ(bottom.substr(0, 2), "1 ");
    EXPECT_EQ(std::count(bottom.begin(), bottom.end(), '\n'), 3);
    EXPECT_EQ(addresses({"inside [0, 1, 0, 0.34]", "centre in [0.51, 1, 0, 1]"}),
              "3 (0.666667, 0) (1, 0) (0.666667, 0.333333) (1, 0.333333)\n");
    // The whole square holds all nine; a box beside it none.
    const std::string all = addresses({"inside [0, 1, 0, 1]"});
    EXPECT_EQ(std::count(all.begin(), all.end(), '\n'), 9);
    EXPECT_EQ(addresses({"meets [2, 3, 2, 3]"}), "");
}

namespace {

// `addresses --where CONDITION` at the default level.
CliResult where(const std::string& condition) {
    return run_cli(
        {"addresses", fp::test::source_dir() + "/configs/mfs/fig4-middle.yaml", "--where", condition});
}

} // namespace

TEST(AddressesWhere, BadConditionsAreRefusedBeforeTheWork) {
    const auto r = where("centre near [0, 1, 0, 1]");
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err,
              "--where 'centre near [0, 1, 0, 1]': expected 'centre in [x0, x1, y0, y1]', 'inside [...]' or "
              "'meets [...]'\n");
    const auto b = where("inside [1, 0, 0, 1]");
    EXPECT_EQ(b.rc, 2);
    EXPECT_EQ(b.err,
              "--where 'inside [1, 0, 0, 1]': expected a box [x0, x1, y0, y1] of four finite numbers with x0 "
              "<= x1 and y0 <= y1\n");
}
