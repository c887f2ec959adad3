// The mfs renderer from the command line (paper 05): bad input (one line, exit 2, nothing
// written), SVG and PDF output, `fixpoint addresses`, and every config of configs/mfs.
#include "cli.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

const std::string tri =
    "{type: subdivision, points: [[0, 0], [1, 0], [0.5, 0.6666666666666666]], divisor: 2, "
    "S: [2, 0, 0, 1, 1, 0, 1, 0, 1]}";
const std::string tri3 = "    - " + tri + "\n    - " + tri + "\n    - " + tri + "\n";

struct Case {
    const char* name;
    std::string yaml;
    std::string expected; // the whole stderr line
    std::vector<std::string> args = {"render", "--quiet", "bad.yaml", "-o", "out.png"};
};

std::string systems_yaml(const std::string& systems) {
    return "renderer:\n  type: mfs\n  path: [0]\n  maps:\n    - {type: subdivision, systems: [" + systems +
           "], points: [[0, 0], [1, 0], [0, 1]], S: [1, 0, 0, 0, 1, 0, 0, 0, 1]}\n";
}

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

std::vector<Case> cases() {
    return {
        {"singular_P",
         "renderer:\n  type: mfs\n  path: [0]\n  maps:\n    - {type: subdivision, points: [[0, 0], [1, 0], "
         "[2, 0]], "
         "S: [1, 0, 0, 0, 1, 0, 0, 0, 1]}\n",
         "bad.yaml:5:35: renderer.maps[0].points: the P of these control points is singular: f(A) = A P^-1 S "
         "P "
         "needs affinely independent (lifted) points (these three lie on one line)"},
        {"S_size",
         "renderer:\n  type: mfs\n  path: [0]\n  maps:\n    - {type: subdivision, points: [[0, 0], [1, 0], "
         "[0, 1]], "
         "S: [1, 0, 0, 0, 1, 0, 0, 0, 1, 0]}\n",
         "bad.yaml:5:64: renderer.maps[0].S: S has 10 entries; 3 control points need a 3 x 3 matrix (9 "
         "entries, "
         "row major)"},
        {"S_rows",
         "renderer:\n  type: mfs\n  path: [0]\n  maps:\n    - {type: subdivision, points: [[0, 0], [1, 0], "
         "[0, 1]], "
         "divisor: 2, S: [2, 0, 0, 1, 1, 0, 1, 0, 0]}\n",
         "bad.yaml:5:76: renderer.maps[0].S: row 3 of S sums to 0.5 (after dividing by the divisor 2), not "
         "1: a "
         "subdivision rule takes affine combinations"},
        {"path_ifs", "renderer:\n  type: mfs\n  path: [0, 2]\n  maps:\n" + tri3,
         "bad.yaml:3:9: renderer.path: path[1]: IFS 2 does not exist: the maps' systems make IFS 0 only"},
        {"too_deep",
         "renderer:\n  type: mfs\n  path: [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]\n  "
         "maps:\n" +
             tri3,
         "bad.yaml:3:9: renderer.path: the path makes 3486784401 polygons at its last level (822.9 GB): more "
         "than "
         "the 50000000 a render may hold; shorten the path"},
        {"too_many_placed",
         "renderer:\n  type: mfs\n  path: [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]\n  maps:\n" +
             tri3 +
             "  placements:\n    - {type: mfs, at: \"1; 2; 3; 1.1; 1.2\", path: [0, 0, 0, 0, 0, 0, 0, 0, 0, "
             "0, 0, 0, "
             "0, 0, 0, 0], maps: [" +
             tri + ", " + tri + ", " + tri + "]}\n",
         "bad.yaml:9:5: renderer.placements: the structures make 258280326 polygons in all (56.8 GB): more "
         "than the "
         "50000000 a render may hold"},
        // An IFS index is user input: once used unchecked as an index (a crash at 4294967295, 48 GB
        // at 2e9, 2.4 GB and 6 s at 1e8 before the error).
        {"systems_huge", systems_yaml("4294967295"),
         "bad.yaml:5:5: renderer.maps: maps[0].systems: IFS 4294967295 is out of range: the maps' systems "
         "must number the IFSs 0, 1, 2, ..."},
        {"systems_1e300", systems_yaml("1e300"),
         "bad.yaml:5:5: renderer.maps: maps[0].systems: IFS 1e+300 is out of range: the maps' systems must "
         "number the IFSs 0, 1, 2, ..."},
        {"systems_1e8", systems_yaml("1e8"),
         "bad.yaml:5:5: renderer.maps: IFS 0 has no maps: the maps' systems must cover 0 to 100000000"},
        {"systems_fraction", systems_yaml("0.5"),
         "bad.yaml:5:5: renderer.maps: maps[0].systems: IFS indices are whole numbers from 0, got 0.5"},
        {"systems_empty", systems_yaml(""),
         "bad.yaml:5:5: renderer.maps: no map belongs to an IFS: give the maps' systems"},
        {"address_map", "renderer:\n  type: mfs\n  path: [0, 0]\n  only: \"1.4\"\n  maps:\n" + tri3,
         "bad.yaml:4:9: renderer.only: address 1.4 does not exist: there are 3 maps, f1 to f3"},
        {"address_level",
         "renderer:\n  type: mfs\n  path: [0, 0]\n  only: \"1.2\"\n  maps:\n    - " + tri +
             "\n    - {type: subdivision, systems: [1], points: [[0, 0], [1, 0], [0, 1]], S: [1, 0, 0, 0, 1, "
             "0, 0, 0, "
             "1]}\n",
         "bad.yaml:4:9: renderer.only: address 1.2 does not exist at level 2: IFS 0 (path[1]) has no f2"},
        {"placement_address",
         "renderer:\n  type: mfs\n  path: [0]\n  maps:\n    - " + tri +
             "\n  placements:\n    - {type: mfs, at: \"2\", path: [0], maps: [" + tri + "]}\n",
         "bad.yaml:7:5: renderer.placements: address 2 does not exist: there is 1 map, f1"},
        {"not_a_plane_map",
         "renderer:\n  type: chaos-game\n  maps:\n    - {type: subdivision, points: [[0, 0], [1, 0], [0, 1], "
         "[1, 1]], divisor: 4, S: [4, 0, 0, 0, 0, 4, 0, 0, 0, 0, 4, 0, 1, 1, 1, 1]}\n",
         "bad.yaml:4:5: renderer.maps: maps[0]: this subdivision map is no map of the plane (its lifted "
         "coordinates feed x and y): use it in the mfs renderer, which subdivides vertex sets",
         {"validate", "bad.yaml"}},
        {"no_vector_output",
         "renderer:\n  type: chaos-game\n  maps:\n    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, "
         "0]}\n",
         "bad.yaml:2:3: renderer: this renderer has no vector output: write 'out.svg' as .png, .exr or .tif "
         "instead",
         {"render", "--quiet", "bad.yaml", "-o", "out.svg"}},
        {"addresses_level",
         "renderer:\n  type: mfs\n  path: [0, 0]\n  maps:\n" + tri3,
         "bad.yaml:2:3: renderer: level 3 does not exist: the path has 2 levels (0 to 2)",
         {"addresses", "bad.yaml", "--level", "3"}},
    };
}

class MfsBadInput : public testing::TestWithParam<Case> {};

TEST_P(MfsBadInput, OneLineExitTwoNoOutput) {
    const Case& c = GetParam();
    EXPECT_EQ(fp::test::run_bad_input(std::string("mfs_bad_") + c.name, c.yaml, c.args), c.expected);
}

INSTANTIATE_TEST_SUITE_P(Cases, MfsBadInput, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

std::size_t count(const std::string& s, const std::string& what) {
    std::size_t n = 0;
    for (auto at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
    return n;
}

// SVG: an XML document with one <path> per run of one colour (9 quads, 9 colours), the recipe
// in <metadata>, written atomically (an old file is replaced, no temporary left). PDF: the same
// bytes for the same recipe.
TEST(MfsCli, VectorOutput) {
    const std::string dir = fp::test::scratch_dir("mfs_vector");
    const std::string cfg = dir + "/nine.yaml";
    fp::test::write_file(
        cfg, "renderer:\n  type: mfs\n  width: 90\n  height: 90\n  path: [0]\n  colour_by: "
             "address\n  maps:\n" +
                 [] {
                     const char* S[] = {"[9, 0, 0, 0, 6, 3, 0, 0, 6, 0, 3, 0, 4, 2, 2, 1]",
                                        "[6, 3, 0, 0, 3, 6, 0, 0, 4, 2, 2, 1, 2, 4, 1, 2]",
                                        "[3, 6, 0, 0, 0, 9, 0, 0, 2, 4, 1, 2, 0, 6, 0, 3]",
                                        "[6, 0, 3, 0, 4, 2, 2, 1, 3, 0, 6, 0, 2, 1, 4, 2]",
                                        "[4, 2, 2, 1, 2, 4, 1, 2, 2, 1, 4, 2, 1, 2, 2, 4]",
                                        "[2, 4, 1, 2, 0, 6, 0, 3, 1, 2, 2, 4, 0, 3, 0, 6]",
                                        "[3, 0, 6, 0, 2, 1, 4, 2, 0, 0, 9, 0, 0, 0, 6, 3]",
                                        "[2, 1, 4, 2, 1, 2, 2, 4, 0, 0, 6, 3, 0, 0, 3, 6]",
                                        "[1, 2, 2, 4, 0, 3, 0, 6, 0, 0, 3, 6, 0, 0, 0, 9]"};
                     std::string m;
                     for (const char* s : S)
                         m += "    - {type: subdivision, divisor: 9, points: [[0, 0], [1, 0], [0, "
                              "1], [1, 1]], S: " +
                              std::string(s) + "}\n";
                     return m;
                 }());
    const std::string svg = dir + "/nine.svg";
    fp::test::write_file(svg, "old");
    auto r = run_cli({"render", "--quiet", cfg, "-o", svg});
    ASSERT_EQ(r.rc, 0) << r.err;
    const std::string doc = fp::test::read_file(svg);
    EXPECT_EQ(doc.rfind("<?xml", 0), 0u);
    EXPECT_EQ(count(doc, "<svg"), 1u);
    EXPECT_EQ(count(doc, "<path"), 9u);
    EXPECT_NE(doc.find("<metadata id=\"fixpoint-recipe\"><![CDATA["), std::string::npos);
    EXPECT_NE(doc.find("type: mfs"), std::string::npos);
    EXPECT_NE(doc.find("</svg>"), std::string::npos);
    r = run_cli({"render", "--quiet", cfg, "-o", dir + "/a.pdf"});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = run_cli({"render", "--quiet", cfg, "-o", dir + "/b.pdf"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const std::string a = fp::test::read_file(dir + "/a.pdf");
    EXPECT_EQ(a.rfind("%PDF", 0), 0u);
    EXPECT_EQ(a, fp::test::read_file(dir + "/b.pdf"));
    for (const auto& e : std::filesystem::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
    // A collection is not written as SVG.
    r = run_cli({"render", "--quiet", cfg, "-o", dir + "/c.svg", "--vary", "renderer.width=10,20"});
    EXPECT_EQ(r.rc, 2);
}

// Algorithm 1: the nine places of Fig. 4 (middle) with their vertices.
TEST(MfsCli, Addresses) {
    const auto r =
        run_cli({"addresses", fp::test::source_dir() + "/configs/mfs/fig4-middle.yaml", "--level", "1"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(count(r.out, "\n"), 9u);
    EXPECT_EQ(r.out.substr(0, r.out.find('\n')), "1 (0, 0) (0.333333, 0) (0, 0.333333) (0.333333, 0.333333)");
    EXPECT_NE(r.out.find("\n5 (0.333333, 0.333333) (0.666667, 0.333333) (0.333333, 0.666667) (0.666667, "
                         "0.666667)\n"),
              std::string::npos);
}

// Every config of configs/mfs validates: in particular every S matrix has rows summing to 1
// (the subdivision map refuses any other) and every address exists.
TEST(MfsCli, ConfigsValidate) {
    std::size_t n = 0;
    for (const auto& e : std::filesystem::directory_iterator(fp::test::source_dir() + "/configs/mfs")) {
        if (e.path().extension() != ".yaml") continue;
        ++n;
        const auto r = run_cli({"validate", "--quiet", e.path().string()});
        EXPECT_EQ(r.rc, 0) << e.path() << ": " << r.err;
    }
    EXPECT_GE(n, 10u);
}

} // namespace
