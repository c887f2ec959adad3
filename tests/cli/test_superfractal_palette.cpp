// flam3's palettes in the superfractal (docs/palettes.md), as in the chaos game: each point of a
// buffer carries a palette index, from a random start drawn from its own stream, that moves
// toward the map's `color` by its `color_speed` at each step, and is coloured through the
// `flame` colourer's palette. Checked: at color_speed 1 each point is its map's palette entry,
// the picture of map-colour with those entries; the same bytes on 1 and 3 threads; and colour
// stealing with a palette, or a `color` without one, gets one positioned line.
#include "cli.hpp"

#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace fp::test;

namespace {

// Sierpinski's triangle as a superfractal of one IFS and one buffer (the paper's algorithm with
// V = 1: the IFS's attractor), with `extra` on each map.
std::string triangle(const std::string& colourer, const std::vector<std::string>& extra,
                     const std::string& more = "") {
    const char* affine[] = {"[0.5, 0, 0, 0.5, 0, 0]", "[0.5, 0, 0, 0.5, 0.5, 0]",
                            "[0.5, 0, 0, 0.5, 0.25, 0.5]"};
    std::string s = "renderer:\n  type: superfractal\n  width: 96\n  height: 80\n  steps: 12\n"
                    "  points_per_buffer: 30000\n  buffers: 1\n  seed: 3\n" +
                    more + "  colourer: " + colourer + "\n  maps:\n";
    for (int j = 0; j < 3; ++j)
        s += std::string("    - {type: affine, coefficients: ") + affine[j] + ", " + extra[std::size_t(j)] +
             "}\n";
    return s;
}

fp::Image render(const std::string& dir, const std::string& name, const std::string& yaml,
                 const std::string& threads = "2") {
    write_file(dir + "/" + name + ".yaml", yaml);
    const auto r = run_cli({"render", "--quiet", "--threads", threads, dir + "/" + name + ".yaml", "-o",
                            dir + "/" + name + ".png"});
    EXPECT_EQ(r.rc, 0) << r.err;
    return fp::host::read_image(dir + "/" + name + ".png");
}

} // namespace

TEST(SuperfractalPalette, SpeedOneIsEachMapsEntryAsMapColourDrawsIt) {
    const std::string dir = scratch_dir("superfractal_palette_speed_one");
    // Grey's entries 0, 128 and 255 are (e + 1/2) / 256: exact in float and in the YAML below.
    const fp::Image a = render(
        dir, "palette",
        triangle("{type: flame, palette_stops: [0, 0, 0, 0, 1, 1, 1, 1]}",
                 {"color: 0, color_speed: 1", "color: 0.5, color_speed: 1", "color: 1, color_speed: 1"}));
    const fp::Image b =
        render(dir, "map",
               triangle("{type: map-colour}", {"colour: [0.001953125, 0.001953125, 0.001953125]",
                                               "colour: [0.501953125, 0.501953125, 0.501953125]",
                                               "colour: [0.998046875, 0.998046875, 0.998046875]"}));
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    EXPECT_EQ(a.pixels, b.pixels);
    // At speed 1/2 the index runs through the palette: grey levels between the entries.
    const fp::Image half = render(dir, "half",
                                  triangle("{type: flame, palette_stops: [0, 0, 0, 0, 1, 1, 1, 1]}",
                                           {"color: 0", "color: 0.5", "color: 1"}));
    EXPECT_NE(half.pixels, a.pixels);
}

TEST(SuperfractalPalette, SameBytesOnAnyThreads) {
    const std::string dir = scratch_dir("superfractal_palette_threads");
    const std::string yaml = triangle("{type: flame, palette: sunset, palette_mode: linear}",
                                      {"color: 0.1", "color: 0.6, color_speed: 0.3", ""}, "  buffers: 2\n");
    const std::string two_buffers = replace_once(yaml, "  buffers: 1\n", "");
    const fp::Image one = render(dir, "one", two_buffers, "1");
    const fp::Image three = render(dir, "three", two_buffers, "3");
    EXPECT_EQ(read_file(dir + "/one.png"), read_file(dir + "/three.png"));
    // Lit, and in more than one colour.
    int lit = 0;
    bool two_colours = false;
    for (std::size_t i = 0; i + 2 < one.pixels.size(); i += 3) {
        if (one.pixels[i] + one.pixels[i + 1] + one.pixels[i + 2] <= 0) continue;
        ++lit;
        two_colours = two_colours || std::abs(one.pixels[i] - one.pixels[i + 1]) > 0.05f;
    }
    EXPECT_GT(lit, 500);
    EXPECT_TRUE(two_colours);
}

TEST(SuperfractalPalette, BadInputGetsOneLine) {
    EXPECT_EQ(
        run_bad_input("superfractal_palette_picture",
                      triangle("{type: flame, palette: fire}", {"", "", ""}, "  picture: hues\n"),
                      {"render", "--quiet", "bad.yaml", "-o", "out.png"}),
        "bad.yaml:9:12: renderer.picture: colour stealing takes the points' colours from the picture: not "
        "with a colourer's palette (leave out the picture, or the palette)");
    EXPECT_EQ(
        run_bad_input("superfractal_palette_color", triangle("{type: flame}", {"", "color: 0.5", ""}),
                      {"render", "--quiet", "bad.yaml", "-o", "out.png"}),
        "bad.yaml:11:5: renderer.maps: maps[1].color: a palette index (flam3's), but the colourer takes no "
        "palette (flame with palette: ...)");
}
