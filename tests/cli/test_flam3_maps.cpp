// flam3's maps in the chaos game (docs/flam3.md): xforms with random variations (julia,
// gaussian_blur) draw from the chains' own keys, so a render is the same bytes on 1 and 3
// threads; a final map moves the plotted points only (an identity final gives
// the render without it; a linear final of weight 2 over the doubled view gives it too, the
// chains unmoved); flam3's camera, y_axis: down, is the mirror image, and
// rotate: 180 is the point reflection in the view's centre.
#include "cli.hpp"

#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

std::string flame(const std::string& extra, const std::string& view = "[-1.6, 1.6, -1.2, 1.2]") {
    return "renderer:\n  type: chaos-game\n  width: 80\n  height: 60\n  points: 300000\n  chains: 512\n"
           "  view: " +
           view +
           "\n  inversion_rules: off\n"
           "  colourer: {type: flame, palette: sunset}\n"
           "  maps:\n"
           "    - {type: xform, coefs: [0.9, -0.5, 0.5, 0.9, 0.3, 0.1], julia: 0.8, linear: 0.2, color: 0}\n"
           "    - {type: xform, coefs: [-0.4, 0.2, -0.2, -0.4, -0.4, 0.3], swirl: 0.5, gaussian_blur: 0.1, "
           "color: 1}\n" +
           extra;
}

fp::Image render(const std::string& dir, const std::string& name, const std::string& yaml,
                 const std::vector<std::string>& args = {}) {
    write_file(dir + "/" + name + ".yaml", yaml);
    std::vector<std::string> cmd = {"render", "--quiet", dir + "/" + name + ".yaml", "-o",
                                    dir + "/" + name + ".png"};
    cmd.insert(cmd.end(), args.begin(), args.end());
    const auto r = run_cli(cmd);
    EXPECT_EQ(r.rc, 0) << r.err;
    return fp::host::read_image(dir + "/" + name + ".png");
}

/// Pixel (x, y) of an RGB(A) image, channel c.
float px(const fp::Image& im, int x, int y, int c) {
    return im.pixels[(std::size_t(y) * std::size_t(im.width) + std::size_t(x)) * std::size_t(im.channels) +
                     std::size_t(c)];
}

TEST(Flam3Maps, RandomVariationsAreTheSameBytesOnAnyThreads) {
    const std::string dir = scratch_dir("flam3_maps_threads");
    const fp::Image one = render(dir, "one", flame(""), {"--threads", "1"});
    const fp::Image three = render(dir, "three", flame(""), {"--threads", "3"});
    ASSERT_FALSE(one.pixels.empty());
    EXPECT_EQ(one.pixels, three.pixels);
    // Not a black picture: most of the view is lit.
    std::size_t lit = 0;
    for (int y = 0; y < one.height; ++y)
        for (int x = 0; x < one.width; ++x)
            lit += px(one, x, y, 0) + px(one, x, y, 1) + px(one, x, y, 2) > 0.05f;
    EXPECT_GT(lit, std::size_t(one.width * one.height / 8));
    // Another seed: other random numbers, another image.
    const fp::Image other = render(dir, "other", flame("  seed: 2\n"));
    EXPECT_NE(one.pixels, other.pixels);
}

TEST(Flam3Maps, AFinalMapMovesThePlottedPointsOnly) {
    const std::string dir = scratch_dir("flam3_maps_final");
    const fp::Image plain = render(dir, "plain", flame(""));
    // An identity final (linear, weight 1, color_speed 0): the same picture.
    const fp::Image same = render(dir, "same", flame("  final:\n    - {type: linear, color_speed: 0}\n"));
    EXPECT_EQ(plain.pixels, same.pixels);
    // The plotted points doubled: the picture of the doubled view, the chains as they were.
    const fp::Image doubled = render(
        dir, "doubled",
        flame("  final:\n    - {type: linear, linear: 2, color_speed: 0}\n", "[-3.2, 3.2, -2.4, 2.4]"));
    EXPECT_EQ(doubled.pixels, plain.pixels);
    // A final that changes colour changes the picture, not the lit pixels' set.
    const fp::Image tinted =
        render(dir, "tinted", flame("  final:\n    - {type: linear, color: 0.5, color_speed: 1}\n"));
    EXPECT_NE(plain.pixels, tinted.pixels);
    for (int y = 0; y < plain.height; ++y)
        for (int x = 0; x < plain.width; ++x) {
            const bool a = px(plain, x, y, 0) + px(plain, x, y, 1) + px(plain, x, y, 2) > 0;
            const bool b = px(tinted, x, y, 0) + px(tinted, x, y, 1) + px(tinted, x, y, 2) > 0;
            ASSERT_EQ(a, b) << "pixel " << x << ", " << y;
        }
}

// flam3's opacity of a final xform (flam3_iterate: applied when opacity is 1 or a random number
// is below it; else the point is plotted as the maps left it). Sierpinski's triangle in [0, 1]^2
// with a final that moves it by 2 to the right: at opacity 1/4 a quarter of the hits land on the
// moved copy (300 000 points: within 0.01 by a wide margin, the standard deviation is 0.001);
// opacity 0 is the render without the final, 1 the final without an opacity, and a final of
// opacity 0.5 over random variations and a palette is the same bytes on 1 and 3 threads.
TEST(Flam3Maps, AFinalsOpacityIsTheChanceThatItApplies) {
    const std::string dir = scratch_dir("flam3_maps_final_opacity");
    const auto triangle = [](const std::string& final) {
        return "renderer:\n  type: chaos-game\n  width: 80\n  height: 40\n  points: 300000\n  chains: 256\n"
               "  view: [-0.5, 3.5, -0.5, 1.5]\n  colourer: {type: density}\n  maps:\n"
               "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}\n"
               "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}\n"
               "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, 0.5]}\n" +
               final;
    };
    const std::string moved = "  final:\n    - {type: affine, coefficients: [1, 0, 0, 1, 2, 0]";
    const auto hits = [&](const std::string& name, const std::string& yaml) {
        write_file(dir + "/" + name + ".yaml", yaml);
        const auto r = run_cli({"render", "--quiet", dir + "/" + name + ".yaml", "-o",
                                dir + "/" + name + ".png", "--histogram", dir + "/" + name + ".fph"});
        EXPECT_EQ(r.rc, 0) << r.err;
        const fp::host::HistogramFile h = fp::host::read_histogram_file(dir + "/" + name + ".fph", 1u << 26);
        double left = 0, right = 0;
        for (int y = 0; y < h.histogram.height; ++y)
            for (int x = 0; x < h.histogram.width; ++x)
                (x < h.histogram.width / 2 ? left : right) += double(
                    h.histogram.hits_at(std::size_t(y) * std::size_t(h.histogram.width) + std::size_t(x)));
        return right / (left + right);
    };
    EXPECT_NEAR(hits("quarter", triangle(moved + ", opacity: 0.25}\n")), 0.25, 0.01);
    EXPECT_EQ(hits("none", triangle(moved + ", opacity: 0}\n")), 0.0);
    EXPECT_EQ(hits("all", triangle(moved + ", opacity: 1}\n")), 1.0);
    hits("plain", triangle(""));
    hits("always", triangle(moved + "}\n"));
    // (The same pixels; the recipes differ by the final.)
    const auto pixels = [&](const std::string& name) {
        return fp::host::read_image(dir + "/" + name).pixels;
    };
    EXPECT_EQ(pixels("none.png"), pixels("plain.png"));
    EXPECT_EQ(pixels("all.png"), pixels("always.png"));
    const std::string half =
        "  final:\n    - {type: linear, linear: 0.5, color: 0.5, color_speed: 1, opacity: 0.5}\n";
    const fp::Image one = render(dir, "one", flame(half), {"--threads", "1"});
    const fp::Image three = render(dir, "three", flame(half), {"--threads", "3"});
    EXPECT_EQ(one.pixels, three.pixels);
    EXPECT_NE(one.pixels, render(dir, "whole", flame(replace_once(half, ", opacity: 0.5", ""))).pixels);
}

TEST(Flam3Maps, TheCameraMirrorsAndTurnsThePicture) {
    const std::string dir = scratch_dir("flam3_maps_camera");
    // A view symmetric about 0, so that the mirror and the half turn keep the bins' edges.
    const fp::Image up = render(dir, "up", flame(""));
    const fp::Image down = render(dir, "down", flame("  y_axis: down\n"));
    const fp::Image turned = render(dir, "turned", flame("  rotate: 180\n"));
    ASSERT_EQ(up.pixels.size(), down.pixels.size());
    std::size_t mirror_bad = 0, turn_bad = 0, lit = 0;
    for (int y = 0; y < up.height; ++y)
        for (int x = 0; x < up.width; ++x)
            for (int c = 0; c < 3; ++c) {
                lit += px(up, x, y, c) > 0;
                // (A point on a bin's edge may fall on the other side of it in the mirrored or
                // turned arithmetic, sin 180 degrees is not exactly 0: a few such pixels are allowed.)
                mirror_bad += std::abs(px(up, x, y, c) - px(down, x, up.height - 1 - y, c)) > 0.2f;
                turn_bad +=
                    std::abs(px(up, x, y, c) - px(turned, up.width - 1 - x, up.height - 1 - y, c)) > 0.2f;
            }
    EXPECT_GT(lit, std::size_t(up.width * up.height / 4));
    EXPECT_LT(mirror_bad, lit / 50);
    EXPECT_LT(turn_bad, lit / 50);
}

TEST(Flam3Maps, EscapeAndRestartSkipAreFlam3sBadValues) {
    // x -> x + 1 never leaves the finite numbers; with escape 100 (flam3's bad value is beyond
    // 1e10) a chain restarts every hundred steps or so, and with restart_skip 0 it plots from its
    // first point after a restart: points near the start box, which skip 20 would have hidden.
    const std::string dir = scratch_dir("flam3_maps_escape");
    const std::string base =
        "renderer:\n  type: chaos-game\n  width: 40\n  height: 40\n  view: [0, 200, -1, 1]\n"
        "  points: 100000\n  chains: 64\n  start_box: [0, 1, -0.5, 0.5]\n"
        "  colourer: {type: density}\n"
        "  maps:\n    - {type: affine, coefficients: [1, 0, 0, 1, 1, 0]}\n";
    auto run = [&](const std::string& name, const std::string& extra) {
        write_file(dir + "/" + name + ".yaml", base + extra);
        const auto r = run_cli({"render", dir + "/" + name + ".yaml", "-o", dir + "/" + name + ".png"});
        EXPECT_EQ(r.rc, 0) << r.err;
        return r.err;
    };
    EXPECT_NE(run("plain", "").find(" 0 bad values"), std::string::npos);
    const std::string esc = run("escape", "  escape: 100\n");
    EXPECT_EQ(esc.find(" 0 bad values"), std::string::npos) << esc;
    // Beyond x = 100 nothing is plotted once chains restart there.
    const fp::Image e = fp::host::read_image(dir + "/escape.png");
    for (int x = 21; x < 40; ++x) EXPECT_EQ(e.pixels[std::size_t(20 * 40 + x) * 3], 0.0f) << x;
    // The first columns (x < 20: the steps after a start) lit only with restart_skip 0.
    run("skip0", "  escape: 100\n  restart_skip: 0\n  skip: 30\n");
    run("skip30", "  escape: 100\n  skip: 30\n");
    const fp::Image a = fp::host::read_image(dir + "/skip0.png"),
                    b = fp::host::read_image(dir + "/skip30.png");
    EXPECT_GT(a.pixels[std::size_t(20 * 40 + 2) * 3], 0.0f);
    EXPECT_EQ(b.pixels[std::size_t(20 * 40 + 2) * 3], 0.0f);
}

} // namespace
