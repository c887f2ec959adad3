// flam3's tone (`flame` colourer, `density: flam3`; docs/flam3.md): a bin's density is
// k1 ln(1 + k2 h) with k2 from the points drawn per unit of the view's area, not from the
// brightest bin. Checked on the uniform measure of the unit square (four maps of ratio 1/2 onto
// its quarters), whose density is 1 everywhere: each pixel is flam3's hand-computed value
// (256/255) (268/256) contrast brightness ln(1 + 1/contrast), whatever the pixel's size and the
// points drawn; its 8 bits truncate as flam3's do; an xform's opacity weighs its points by
// flam3's opacity^log2(10); in strips and re-toned from a kept histogram it is the same bytes;
// and `contrast` without density flam3 is refused.
#include "cli.hpp"

#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

using namespace fp::test;

namespace {

/// The unit square's uniform measure, in white, at gamma 1 (pixel = the tone's value itself).
std::string square(const std::string& view, int size, long points, const std::string& tone,
                   const std::string& item = "") {
    std::string maps;
    for (const char* t : {"0, 0", "0.5, 0", "0, 0.5", "0.5, 0.5"})
        maps += std::string("    - {type: affine, coefficients: [0.5, 0, 0, 0.5, ") + t + "]" + item + "}\n";
    return "renderer:\n  type: chaos-game\n  width: " + std::to_string(size) +
           "\n  height: " + std::to_string(size) + "\n  view: " + view +
           "\n  points: " + std::to_string(points) +
           "\n  chains: 256\n  colourer: {type: flame, density: flam3, gamma: 1, palette_stops: [0, 1, 1, 1, "
           "1, 1, 1, 1]" +
           tone + "}\n  maps:\n" + maps;
}

/// flam3's value of a pixel of density 1 (rect.c: k1 ln(1 + k2 h) / PREFILTER_WHITE, scaled by
/// 256 where white is 255), 8-bit.
double expected(double brightness, double contrast) {
    return 255.0 * (256.0 / 255.0) * (268.0 / 256.0) * contrast * brightness * std::log1p(1.0 / contrast);
}

/// Pixel (x, y)'s red, 0..255.
double red(const fp::Image& im, int x, int y) {
    return 255.0 *
           im.pixels[(std::size_t(y) * std::size_t(im.width) + std::size_t(x)) * std::size_t(im.channels)];
}

/// The value pixel (x, y)'s red stands for: flam3 truncates to its 8 bits, so a value v is
/// written floor(v), on average v - 1/2.
double shown(const fp::Image& im, int x, int y) { return red(im, x, y) + 0.5; }

fp::Image render(const std::string& dir, const std::string& name, const std::string& config) {
    write_file(dir + "/" + name + ".yaml", config);
    const auto r =
        run_cli({"render", "--quiet", dir + "/" + name + ".yaml", "-o", dir + "/" + name + ".png"});
    EXPECT_EQ(r.rc, 0) << r.err;
    return fp::host::read_image(dir + "/" + name + ".png");
}

TEST(Flam3Tone, TheSquaresDensityIsFlam3sValue) {
    const std::string dir = scratch_dir("flam3_tone_value");
    // 4 x 4 pixels of 1/4 x 1/4: 100 000 hits each (+-0.3%, +-0.4 of an 8-bit step).
    const fp::Image a = render(dir, "a", square("[0, 1, 0, 1]", 4, 1600000, ""));
    ASSERT_EQ(a.width, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_NEAR(shown(a, x, y), expected(1, 1), 1.5) << x << ", " << y;
    // Brightness and contrast as flam3 has them.
    const fp::Image b =
        render(dir, "b", square("[0, 1, 0, 1]", 4, 1600000, ", brightness: 0.5, contrast: 2"));
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_NEAR(shown(b, x, y), expected(0.5, 2), 1.5) << x << ", " << y;
    // Pixels of 1/2 x 1/2 (four times the hits each) over a view of 3 x 3 (the square in its
    // middle 2 x 2 pixels): the same density, the same value; outside, the background.
    const fp::Image c = render(dir, "c", square("[-1, 2, -1, 2]", 6, 1600000, ""));
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 6; ++x) {
            const bool in = x >= 2 && x < 4 && y >= 2 && y < 4;
            EXPECT_NEAR(shown(c, x, y), in ? expected(1, 1) : 0.0, 1.5) << x << ", " << y;
        }
    // A quarter of the points: the same picture (flam3's quality changes the noise, not the tone).
    const fp::Image d = render(dir, "d", square("[0, 1, 0, 1]", 4, 400000, ""));
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_NEAR(shown(d, x, y), expected(1, 1), 2.0) << x << ", " << y;
}

TEST(Flam3Tone, EightBitsTruncateAsFlam3Does) {
    // flam3 writes (unsigned char) of its 0..255 value. The square's pixels are worth
    // 268 ln 2 = 185.76 of 255: flam3 writes 185 where rounding would give 186. 4e6 hits a
    // pixel (2 x 2 pixels) keep the value within +-0.07 (1 sigma) of it, so every pixel is 185.
    const std::string dir = scratch_dir("flam3_tone_truncate");
    ASSERT_NEAR(expected(1, 1), 185.763, 1e-3);
    const fp::Image a = render(dir, "a", square("[0, 1, 0, 1]", 2, 16000000, ""));
    ASSERT_EQ(a.width, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) EXPECT_EQ(std::lround(red(a, x, y)), 185) << x << ", " << y;
}

TEST(Flam3Tone, OpacityWeighsEachPointAsFlam3Does) {
    const std::string dir = scratch_dir("flam3_tone_opacity");
    // flam3 weighs a point of an xform of opacity o by o^log2(10) (adjust_percentage): at
    // o = 0.25^(1 / log2 10) = 0.65881 a quarter, the density of the square 1/4, the pixel
    // (256/255) (268/256) ln(1 + 1/4) (25 000 hits a pixel: +-0.6%, +-0.3 of a step).
    const fp::Image a = render(dir, "a", square("[0, 1, 0, 1]", 4, 1600000, "", ", opacity: 0.65881"));
    const double want = 255.0 * (256.0 / 255.0) * (268.0 / 256.0) * std::log1p(0.25);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_NEAR(shown(a, x, y), want, 1.5) << x << ", " << y;
    // Opacity 0 on three of the maps: only the fourth's images are plotted (its quarter: the
    // bottom-left, rows down).
    std::string c = square("[0, 1, 0, 1]", 4, 400000, "");
    for (const char* t : {"0.5, 0]", "0, 0.5]", "0.5, 0.5]"}) {
        const std::string m = std::string(t);
        c.replace(c.find(m), m.size(), m + ", opacity: 0");
    }
    const fp::Image b = render(dir, "b", c);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_EQ(red(b, x, y) > 0, x < 2 && y >= 2) << x << ", " << y;
    // The same bytes on 1 and 3 threads.
    for (const char* t : {"1", "3"}) {
        const auto r =
            run_cli({"render", "--quiet", "--threads", t, dir + "/a.yaml", "-o", dir + "/a" + t + ".png"});
        ASSERT_EQ(r.rc, 0) << r.err;
    }
    EXPECT_EQ(read_file(dir + "/a1.png"), read_file(dir + "/a3.png"));
}

TEST(Flam3Tone, StripsAndReTonedAreTheSameBytes) {
    const std::string dir = scratch_dir("flam3_tone_bytes");
    // A finished picture (supersampled, filtered, estimated): the density is per bin of the
    // supersampled histogram.
    write_file(dir + "/s.yaml",
               square("[-0.25, 1.25, -0.25, 1.25]", 300, 2000000, ", brightness: 3") +
                   "  supersample: 2\n  filter: {type: gaussian, radius: 0.75}\n  estimator_radius: 4\n");
    const auto whole = run_cli(
        {"render", "--quiet", dir + "/s.yaml", "-o", dir + "/whole.png", "--histogram", dir + "/s.fph"});
    ASSERT_EQ(whole.rc, 0) << whole.err;
    const auto strips =
        run_cli({"render", "--quiet", "--memory", "8M", dir + "/s.yaml", "-o", dir + "/strips.png"});
    ASSERT_EQ(strips.rc, 0) << strips.err;
    EXPECT_EQ(read_file(dir + "/whole.png"), read_file(dir + "/strips.png"));
    // brightness 1 on the kept histogram is a full render at brightness 1, and another picture.
    const auto toned = run_cli({"tone", "--quiet", dir + "/s.fph", "--set", "renderer.colourer.brightness=1",
                                "-o", dir + "/toned.png"});
    ASSERT_EQ(toned.rc, 0) << toned.err;
    write_file(dir + "/one.yaml", square("[-0.25, 1.25, -0.25, 1.25]", 300, 2000000, ", brightness: 1") +
                                      "  supersample: 2\n  filter: {type: gaussian, radius: 0.75}\n"
                                      "  estimator_radius: 4\n");
    const auto one = run_cli({"render", "--quiet", dir + "/one.yaml", "-o", dir + "/one.png"});
    ASSERT_EQ(one.rc, 0) << one.err;
    EXPECT_EQ(read_file(dir + "/toned.png"), read_file(dir + "/one.png"));
    EXPECT_NE(read_file(dir + "/toned.png"), read_file(dir + "/whole.png"));
}

TEST(Flam3Tone, ContrastNeedsDensityFlam3) {
    const std::string dir = scratch_dir("flam3_tone_bad");
    std::string c = square("[0, 1, 0, 1]", 4, 1000, ", contrast: 2");
    c.replace(c.find("density: flam3"), 14, "density: log");
    write_file(dir + "/bad.yaml", c);
    const auto r = run_cli({"render", dir + "/bad.yaml", "-o", dir + "/bad.png"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("bad.yaml:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("contrast is flam3's: it needs density flam3"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/bad.png"));
}

} // namespace
