// Colour stealing in the chaos game (`picture` and the maps' `colour_map`; picture.hpp): each
// chain's colour point moves by its map's colour map, in lockstep with the chain's choices, and
// the point takes the picture's colour there. Checked by hand on an IFS whose colour IFS is the
// same maps, so that every pixel's colour is known; the geometry is that of the render without
// a picture; the bytes are the same on any threads and strip plan, and after a checkpoint; and
// the one-line refusals.
#include "cli.hpp"
#include "host.hpp"
#include "picture.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

fp::Image image_of(const std::string& yaml, unsigned threads) { return fp::test::render(yaml, threads).img; }

std::string error_of(const std::string& yaml) { return fp::test::error_of(fp::Kind::Renderer, yaml); }

std::vector<char> lit(const fp::Image& img) {
    std::vector<char> out(std::size_t(img.width) * std::size_t(img.height), 0);
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = img.pixels[3 * i] > 0 || img.pixels[3 * i + 1] > 0 || img.pixels[3 * i + 2] > 0;
    return out;
}

// The Sierpinski triangle, its maps' colours stolen from `hues` by the default colour maps.
const std::string triangle =
    "{type: chaos-game, width: 256, height: 256, view: [-0.05, 1.05, -0.05, 1.05], points: 300000, "
    "chains: 300, picture: hues, colourer: {type: map-colour, density: log}, maps: ["
    "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}, "
    "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}, "
    "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, 0.5]}]}";

} // namespace

TEST(ChaosGameSteal, StolenColoursFollowTheAddresses) {
    // f0 = (x/2, y), f1 = (x/2 + 1/2, y) from (1/2, 1/2), and the colour IFS g0 = (u/2, v/2 +
    // 1/2), g1 = (u/2 + 1/2, v/2) from the colour point (1/2, 1/2): u runs as x does, and
    // u + v = 1 at every step. A point of pixel p of a 4 x 1 image (x in [p/4, (p + 1)/4), its
    // last two maps the binary digits of p) has its colour point in column p and row p from the
    // top of the 4 x 4 picture: its diagonal, whatever the chain and the step.
    const std::string dir = scratch_dir("chaos-steal-addresses");
    const std::string yaml =
        "{type: chaos-game, width: 4, height: 1, view: [0, 1, 0, 1], points: 20000, chains: 16, skip: 0, "
        "start: [0.5, 0.5], picture: \"" +
        write_picture(dir, 4, 4) +
        "\", colourer: {type: map-colour, density: flat}, maps: ["
        "{type: affine, coefficients: [0.5, 0, 0, 1, 0, 0], colour_map: [0.5, 0, 0, 0.5, 0, 0.5]}, "
        "{type: affine, coefficients: [0.5, 0, 0, 1, 0.5, 0], colour_map: [0.5, 0, 0, 0.5, 0.5, 0]}]}";
    const fp::Image img = image_of(yaml, 2);
    ASSERT_EQ(img.width, 4);
    for (std::size_t p = 0; p < 4; ++p)
        EXPECT_EQ(pixel8(img, p), (std::vector<int>{int(10 + 20 * p), int(10 + 20 * p), 255})) << p;
    // The default colour maps ((u + j) / k, v) read the picture's row v = 1/2 (row 2 from the
    // top of 4) at u, the address as a binary fraction: column p again.
    std::string plain = yaml;
    for (const char* cm :
         {", colour_map: [0.5, 0, 0, 0.5, 0, 0.5]", ", colour_map: [0.5, 0, 0, 0.5, 0.5, 0]"})
        plain.erase(plain.find(cm), std::string(cm).size());
    const fp::Image d = image_of(plain, 2);
    for (std::size_t p = 0; p < 4; ++p)
        EXPECT_EQ(pixel8(d, p), (std::vector<int>{int(10 + 20 * p), 50, p == 2 ? 255 : 200})) << p;
}

TEST(ChaosGameSteal, TheGeometryIsTheRenderWithoutAndTheBytesAnyThreads) {
    const fp::Image one = image_of(triangle, 1), two = image_of(triangle, 2), three = image_of(triangle, 3);
    EXPECT_TRUE(one.pixels == two.pixels);
    EXPECT_TRUE(one.pixels == three.pixels);
    std::string plain = triangle;
    plain.erase(plain.find("picture: hues, "), 15);
    const fp::Image without = image_of(plain, 2);
    EXPECT_TRUE(lit(without) == lit(one));
    EXPECT_FALSE(without.pixels == one.pixels);
    // The corners' colours: address 000... (bottom left) u = 0, red; 111... (bottom right)
    // u = 1/2, cyan; 222... (the top) u = 1, red again (hues' last column).
    auto at = [&](double x, double y) {
        const std::size_t col = std::size_t((x + 0.05) / 1.1 * 256),
                          row = std::size_t((1.05 - y) / 1.1 * 256);
        return pixel8(one, row * 256 + col);
    };
    const std::vector<int> bl = at(0.01, 0.005), br = at(0.985, 0.005), top = at(0.5, 0.99);
    EXPECT_GT(bl[0], 2 * bl[2]) << "bottom left, red: " << bl[0] << " " << bl[1] << " " << bl[2];
    EXPECT_GT(br[2], 2 * br[0]) << "bottom right, cyan: " << br[0] << " " << br[1] << " " << br[2];
    EXPECT_GT(br[1], 2 * br[0]);
    EXPECT_GT(top[0], 2 * top[2]) << "top, red: " << top[0] << " " << top[1] << " " << top[2];
}

TEST(ChaosGameSteal, StripsAndCheckpointsGiveTheSameBytes) {
    const std::string dir = scratch_dir("chaos-steal-strips");
    std::string yaml = "renderer: " + triangle + "\n";
    write_file(dir + "/t.yaml", yaml);
    const auto whole = run_cli({"render", "--quiet", dir + "/t.yaml", "-o", dir + "/whole.png"});
    ASSERT_EQ(whole.rc, 0) << whole.err;
    const auto strips =
        run_cli({"render", "--threads", "3", "--memory", "7M", dir + "/t.yaml", "-o", dir + "/strips.png"});
    ASSERT_EQ(strips.rc, 0) << strips.err;
    EXPECT_NE(strips.err.find(" strips of "), std::string::npos) << strips.err;
    EXPECT_EQ(read_file(dir + "/whole.png"), read_file(dir + "/strips.png"));
    // A finished render's checkpoint continued to three times the points: the render of those
    // points (the chains' colour points are in the checkpoint).
    const auto first = run_cli(
        {"render", "--quiet", dir + "/t.yaml", "-o", dir + "/first.png", "--checkpoint", dir + "/ck.bin"});
    ASSERT_EQ(first.rc, 0) << first.err;
    const auto more = run_cli({"render", "--quiet", dir + "/t.yaml", "--set", "renderer.points=900000", "-o",
                               dir + "/more.png", "--resume", dir + "/ck.bin"});
    ASSERT_EQ(more.rc, 0) << more.err;
    const auto fresh = run_cli(
        {"render", "--quiet", dir + "/t.yaml", "--set", "renderer.points=900000", "-o", dir + "/fresh.png"});
    ASSERT_EQ(fresh.rc, 0) << fresh.err;
    EXPECT_EQ(read_file(dir + "/more.png"), read_file(dir + "/fresh.png"));
    EXPECT_NE(read_file(dir + "/more.png"), read_file(dir + "/whole.png"));
}

TEST(ChaosGameSteal, ColourStealingIsValidated) {
    const std::string maps = "maps: [{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}]";
    EXPECT_EQ(error_of("{type: chaos-game, picture: hues, colourer: {type: density}, " + maps + "}"),
              "renderer.picture: colour stealing needs a colourer that shows the points' colours (map-colour "
              "or flame); this one shows only where they fall");
    EXPECT_EQ(
        error_of("{type: chaos-game, picture: hues, colourer: {type: flame, palette: sunset}, " + maps + "}"),
        "renderer.picture: colour stealing takes the points' colours from the picture: not with a "
        "colourer's palette (leave out the picture, or the palette)");
    EXPECT_EQ(error_of("{type: chaos-game, maps: [{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0], "
                       "colour_map: [1, 0, 0, 1, 0, 0]}]}"),
              "renderer.maps: maps[0]: a colour_map is used only by colour stealing: give the renderer a "
              "picture (hues, or a PNG file)");
    EXPECT_EQ(error_of("{type: chaos-game, picture: hues, maps: [{type: affine, coefficients: [0.5, 0, 0, "
                       "0.5, 0, 0], colour_map: [1, 0, 0, 1, 0]}]}"),
              "renderer.maps[0].colour_map: expected 6 numbers, got 5");
    const std::string line = run_bad_input(
        "chaos-steal-bad-picture", "renderer:\n  type: chaos-game\n  " + maps + "\n  picture: missing.png\n");
    EXPECT_EQ(line, "bad.yaml:4:12: renderer.picture: cannot read the picture \"missing.png\": no such file "
                    "(give a PNG file, relative to the config, or hues)");
}
