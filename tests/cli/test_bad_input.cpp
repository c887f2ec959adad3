// Bad input ends with exactly one error line naming the place, exit code 2, and no output
// file. The messages are golden: a change to one is a change users see.
#include "cli.hpp"
#include "configs.hpp"

#include <gtest/gtest.h>

#include <filesystem>

using namespace fp::test;

namespace {

// Three circles around the origin, the smallest pipeline that renders.
const std::string base =
    chaos_game({"width: 64", "height: 64", "points: 20000", "chains: 64"}, three_circles("0.9"));

struct Case {
    const char* name;
    std::string yaml;
    std::string expected; // the whole stderr line, with "bad.yaml" for the file
    std::vector<std::string> extra_args = {};
};

std::vector<Case> cases() {
    const std::string b = base;
    const std::string circle0 = "{type: circle, centre: [1, 0], radius: 0.9}";
    // The base with `iteration: SCHEME` on line 7, after the chains.
    const auto with_iteration = [&](const std::string& scheme) {
        return replace_once(b, "  chains: 64\n", "  chains: 64\n  iteration: " + scheme + "\n");
    };
    return {
        {"syntax", "renderer: [1, 2\n", "bad.yaml:2:1: YAML syntax error: end of sequence flow not found"},
        {"lone_comma", ",", "bad.yaml:1:1: YAML syntax error: unexpected ','"},
        {"duplicate_key", replace_once(b, "  height: 64\n", "  height: 64\n  width: 32\n"),
         "bad.yaml:5:3: duplicate key 'width'"},
        {"unquoted_hex_colour", replace_once(b, "radius: 0.9}}\n", "radius: 0.9}, colour: #ff6b6b}\n"),
         "bad.yaml:9:5: YAML syntax error: illegal block entry (a '#' after a space starts a comment: quote "
         "colours, as "
         "in \"#ff6b6b\")"},
        // output.tiled: a value it does not take, and tiles for a PNG (which has none).
        {"tiled_value", b + "output: {tiled: maybe}\n",
         "bad.yaml:11:17: output.tiled: must be auto, true or false, got 'maybe'"},
        {"tiled_png", b + "output: {tiled: true}\n",
         "bad.yaml:11:17: output.tiled: 'out.png': only TIFF and EXR images have tiles (write .tif or .exr)"},
        // The same for a collection's children, before any child renders.
        {"tiled_png_vary",
         b + "output: {tiled: true}\n",
         "bad.yaml:11:17: output.tiled: 'out-1.png': only TIFF and EXR images have tiles (write .tif or "
         ".exr)",
         {"--vary", "renderer.seed=1,2"}},
        {"alias", "a: &x 1\nrenderer: *x\n",
         "bad.yaml:1:4: YAML anchors are not supported: write the value out"},
        {"second_document", b + "---\nrenderer: {}\n",
         "bad.yaml:11:1: a second YAML document is not supported (one pipeline per file)"},
        {"nesting", "renderer: " + std::string(80, '[') + std::string(80, ']') + "\n",
         "bad.yaml:1:74: nesting deeper than 64 levels"},
        {"unknown_plugin", replace_once(b, "type: circle, centre: [1, 0]", "type: circel, centre: [1, 0]"),
         "bad.yaml:8:39: renderer.maps[0].shape.type: unknown shape 'circel' (did you mean 'circle'?)"},
        {"unknown_parameter",
         replace_once(b, "radius: 0.9}}\n    - {type: inversion, shape: {type: circle, centre: [-0.5, 0.866]",
                      "radus: 0.9}}\n    - {type: inversion, shape: {type: circle, centre: [-0.5, 0.866]"),
         "bad.yaml:8:63: renderer.maps[0].shape: unknown parameter 'radus' for circle (did you mean "
         "'radius'?)"},
        // A typo in a map item's own keys is suggested from them, not blamed on the map's plugin.
        {"unknown_item_key",
         replace_once(
             b, "radius: 0.9}}\n    - {type: inversion, shape: {type: circle, centre: [-0.5, 0.866]",
             "radius: 0.9}, wieght: 2}\n    - {type: inversion, shape: {type: circle, centre: [-0.5, 0.866]"),
         "bad.yaml:8:77: renderer.maps[0]: unknown key 'wieght': not a parameter of inversion nor a key of "
         "the "
         "item (weight, colour, color, color_speed, chaos, opacity, colour_map) (did you mean 'weight'?)"},
        {"missing_parameter", replace_once(b, "shape: " + circle0, "centre: [0.1, 0]"),
         "bad.yaml:8:7: renderer.maps[0]: missing required parameter 'shape' for inversion"},
        {"ill_typed", replace_once(b, "width: 64", "width: wide"),
         "bad.yaml:3:10: renderer.width: expected an integer, got 'wide'"},
        {"nan",
         replace_once(b, "radius: 0.9}}\n    - {type: inversion, shape: {type: circle, centre: [-0.5, 0.866]",
                      "radius: .nan}}\n    - {type: inversion, shape: {type: circle, centre: [-0.5, 0.866]"),
         "bad.yaml:8:71: renderer.maps[0].shape.radius: must be a finite number, got .nan"},
        {"infinite", replace_once(b, "centre: [1, 0]", "centre: [.inf, 0]"),
         "bad.yaml:8:56: renderer.maps[0].shape.centre: must be a finite number, got .inf"},
        {"out_of_range",
         replace_once(b, "radius: 0.9}}\n    - {type: inversion, shape: {type: circle, centre: [-0.5, 0.866]",
                      "radius: -1}}\n    - {type: inversion, shape: {type: circle, centre: [-0.5, 0.866]"),
         "bad.yaml:8:71: renderer.maps[0].shape.radius: must be > 0, got -1"},
        {"empty_maps", "renderer: {type: chaos-game, maps: []}\n",
         "bad.yaml:1:36: renderer.maps: the list of transforms is empty"},
        {"wrong_kind", replace_once(b, "shape: " + circle0, "shape: {type: picard}"),
         "bad.yaml:8:39: renderer.maps[0].shape.type: 'picard' is an iteration-scheme, but this slot expects "
         "a shape"},
        {"polygon_two_vertices", replace_once(b, circle0, "{type: polygon, vertices: [[0, 0], [1, 0]]}"),
         "bad.yaml:8:58: renderer.maps[0].shape.vertices: expected at least 3 points, got 2"},
        {"polygon_self_intersecting",
         replace_once(b, circle0, "{type: polygon, vertices: [[0, 0], [1, 1], [1, 0], [0, 1]]}"),
         "bad.yaml:8:58: renderer.maps[0].shape.vertices: polygon self-intersects: edges 0 and 2 cross"},
        {"centre_outside_kernel",
         replace_once(b, "shape: " + circle0, "shape: " + circle0 + ", centre: [2, 0]"),
         "bad.yaml:8:85: renderer.maps[0].centre: inversion centre (2, 0) is outside the kernel of the "
         "shape"},
        {"zero_width", replace_once(b, "width: 64", "width: 0"),
         "bad.yaml:3:10: renderer.width: must be in [1, 65536], got 0"},
        // (A chaos-game image of any size renders in strips within the machine's memory: too
        // large is too large for --memory.)
        {"too_large",
         replace_once(replace_once(b, "width: 64", "width: 60000"), "height: 64", "height: 60000"),
         "",
         {"--memory", "2M"}}, // message depends on the threads: checked by prefix below
        {"unknown_format",
         b,
         "'out.bmp': unknown output format '.bmp' (use .png, .exr, .tif, .tiff, .svg or .pdf)",
         {"-o", "out.bmp"}},
        {"unwritable",
         b,
         "cannot write 'no/such/folder/out.png': folder 'no/such/folder' does not exist",
         {"-o", "no/such/folder/out.png"}},
        // Iteration processes (paper 02).
        {"qnumber_syntax", with_iteration("{type: mann, alpha: 0.5+q0.5}"),
         "bad.yaml:7:34: renderer.iteration.alpha: cannot read '0.5+q0.5' as a number or q-system number "
         "(write 0.7, "
         "0.5+0.5q or [0.5, 0.5])"},
        {"qnumber_nan", with_iteration("{type: mann, alpha: .nan}"),
         "bad.yaml:7:34: renderer.iteration.alpha: must be a finite number, got .nan"},
        {"empty_periodic_list", with_iteration("{type: mann, alpha: []}"),
         "bad.yaml:7:34: renderer.iteration.alpha: a periodic list must not be empty"},
        {"empty_switching", with_iteration("{type: switching, schemes: []}"),
         "bad.yaml:7:41: renderer.iteration.schemes: the list of iteration-schemes is empty"},
        {"qnumber_in_real_scheme", with_iteration("{type: mann, alpha: 0.5+0.5q}"),
         "bad.yaml:7:34: renderer.iteration.alpha: 0.5+0.5q is a q-system number, but the scheme computes in "
         "the real "
         "numbers (set numbers: {type: q-system, A: ..., B: ...})"},
        {"nothing_drawn", replace_once(b, "  height: 64\n", "  height: 64\n  view: [10, 11, 10, 11]\n"),
         "bad.yaml:2:3: renderer: nothing was drawn (0 of 20000 points landed in the image); check the view "
         "and the parameters"},
        {"schu_unbounded",
         "renderer:\n  type: chaos-game\n  points: 5000000\n  iteration: {type: schu, alpha: 0.5}\n  maps:\n"
         "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}\n"
         "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}\n",
         "bad.yaml:4:14: renderer.iteration: schu: step n = 1240 needs T composed 1241 times, above "
         "max_compositions = 1000 (the map is not an involution, so a chain of N steps costs N(N+1)/2 "
         "applications "
         "of T); use shorter chains (more chains, fewer points), raise max_compositions, or use mann"},
        {"set_unknown_parameter",
         b,
         "--set renderer.widht=10: renderer: unknown parameter 'widht' for chaos-game (did you mean "
         "'width'?)",
         {"--set", "renderer.widht=10"}},
        {"set_bad_index",
         b,
         "--set renderer.maps[7].weight=2: index 7 out of range ('renderer.maps' has 3 items)",
         {"--set", "renderer.maps[7].weight=2"}},
    };
}

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class BadInput : public testing::TestWithParam<Case> {};

TEST_P(BadInput, OneLineExitTwoNoOutput) {
    const Case& c = GetParam();
    std::vector<std::string> args = {"render", "--quiet", "bad.yaml"};
    bool has_out = false;
    for (const auto& a : c.extra_args) has_out = has_out || a == "-o";
    if (!has_out) args.insert(args.end(), {"-o", "out.png"});
    args.insert(args.end(), c.extra_args.begin(), c.extra_args.end());
    const std::string line = fp::test::run_bad_input(std::string("bad_") + c.name, c.yaml, args);
    if (std::string(c.name) == "too_large") {
        EXPECT_EQ(line.rfind("bad.yaml:2:3: renderer: a 60000x60000 render needs ", 0), 0u) << line;
        EXPECT_NE(line.find(" of memory with "), std::string::npos) << line;
    } else {
        EXPECT_EQ(line, c.expected);
    }
}

INSTANTIATE_TEST_SUITE_P(Cli, BadInput, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

TEST(BadInput, CommandLineErrorsExitTwo) {
    auto r = run_cli({"render"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "fixpoint: config is required (see fixpoint --help)\n");
    r = run_cli({"render", "x.yaml", "--threads", "0"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    r = run_cli({"render", "/no/such/config.yaml"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "/no/such/config.yaml: cannot open file\n");
}

} // namespace
