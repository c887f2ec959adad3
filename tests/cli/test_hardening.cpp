// Regression tests for the defects a fuzzing run of the CLI found (issue "Hardening"): each
// failed before its fix. Bad input still ends in one escaped, positioned line, exit 2 and no
// output; nothing crashes, hangs or overwrites what it was not asked to.
#include "cli.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

using fp::test::run_bad_input;
using fp::test::run_cli;

namespace {

const std::string base = R"(renderer:
  type: chaos-game
  width: 64
  height: 64
  points: 20000
  chains: 64
  maps:
    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}
    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}
    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, 0.5]}
)";

const std::string hint = " (a '#' after a space starts a comment: quote colours, as in \"#ff6b6b\")";

// A YAML error with a long run of blanks after ':', ',' or '[' once overflowed the stack in the
// regex that looks for an unquoted colour.
TEST(Hardening, LongBlankRunInABadConfigIsAnErrorNotACrash) {
    for (const char* c : {":", ",", "["}) {
        const std::string yaml =
            "renderer: {type: chaos-game" + std::string(c) + std::string(30000, ' ') + "[1, 2\n";
        const std::string line = run_bad_input(std::string("blank_run_") + (c[0] == ':'   ? "colon"
                                                                            : c[0] == ',' ? "comma"
                                                                                          : "bracket"),
                                               yaml, {"validate", "bad.yaml"});
        EXPECT_EQ(line.rfind("bad.yaml:", 0), 0u) << line;
    }
}

TEST(Hardening, LongBlankRunInASetValueIsAnErrorNotACrash) {
    const auto r = run_cli({"validate", "x.yaml", "--set", "a=[1," + std::string(30000, ' ') + "[2"});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// An unquoted colour in block style: the value is empty, and the error once pointed at the next
// line without the hint.
TEST(Hardening, UnquotedColourInBlockStylePointsAtItsKeyWithTheHint) {
    EXPECT_EQ(
        run_bad_input("colour_block",
                      fp::test::replace_once(base, "  chains: 64\n", "  chains: 64\n  background: #102030\n"),
                      {"validate", "bad.yaml"}),
        "bad.yaml:7:3: renderer.background: expected a colour [r, g, b] with components in [0, 1] or "
        "\"#rrggbb\", got nothing" +
            hint);
    EXPECT_EQ(
        run_bad_input(
            "colour_item",
            base + "    - type: affine\n      coefficients: [0.5, 0, 0, 0.5, 0, 0]\n      colour: #ff0000\n",
            {"validate", "bad.yaml"}),
        "bad.yaml:13:7: renderer.maps[3].colour: expected a colour [r, g, b] with components in [0, 1] "
        "or \"#rrggbb\", got nothing" +
            hint);
}

// Error lines quote input as a short escaped excerpt: no newline, no escape sequence, no
// megabytes of text.
TEST(Hardening, ErrorLinesQuoteAnEscapedExcerpt) {
    const std::string dir = fp::test::scratch_dir("excerpt");
    fp::test::write_file(dir + "/bad.yaml", base);
    const std::string bad = dir + "/bad.yaml";
    auto r = run_cli({"validate", bad, "--set", "renderer.width=\"1\n2\x1b[31m\""});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "--set renderer.width=\"1\\n2\\x1b[31m\": renderer.width: expected an integer, got '1 "
                     "2\\x1b[31m'\n");
    r = run_cli({"validate", bad, "--set", "renderer.width=\"" + std::string(100000, 'w') + "\""});
    EXPECT_EQ(r.rc, 2);
    EXPECT_LT(r.err.size(), 300u);
    EXPECT_EQ(r.err, "--set renderer.width=\"" + std::string(58, 'w') +
                         "...: renderer.width: expected an integer, got '" + std::string(48, 'w') + "...'\n");
    // A C1 control (U+009B, a terminal's CSI) and a byte that is not UTF-8.
    r = run_cli({"validate", bad, "--set",
                 "renderer.wi\xc2\x9b"
                 "dth\xff=3"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("unknown parameter 'wi\\u009bdth\\xff' for chaos-game"), std::string::npos) << r.err;
}

// A mapping made by --set from nothing once stood at "<input>:0:0".
TEST(Hardening, SetMadeMappingsHaveAPosition) {
    EXPECT_EQ(
        run_bad_input("set_position", "", {"validate", "bad.yaml", "--set", "renderer.type=chaos-game"}),
        "--set renderer.type=chaos-game: renderer: missing required parameter 'maps' for chaos-game");
    EXPECT_EQ(run_bad_input("set_position_null", "renderer:\n",
                            {"validate", "bad.yaml", "--set", "renderer.type=chaos-game"}),
              "bad.yaml:1:1: renderer: missing required parameter 'maps' for chaos-game");
}

} // namespace
