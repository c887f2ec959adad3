// Palettes (fixpoint/palette.hpp): gradients of stops sampled at the entries' centres by hand,
// flam3's lookup (rect.c: step and linear), a palette read from a tiny fixture file of flam3's
// format equal to its entries, the real file where Debian's flam3-palette installs it, and the
// refusals with their "did you mean".
#include <fixpoint/errors.hpp>
#include <fixpoint/palette.hpp>

#include <gtest/gtest.h>

#include "cli.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>

namespace {

const std::string fixture = fp::test::source_dir() + "/tests/fixtures/flam3-palettes-tiny.xml";

std::string refusal(const std::function<void()>& f) {
    try {
        f();
    } catch (const fp::ParamError& e) {
        return e.param() + ": " + e.what();
    }
    return "(no refusal)";
}

TEST(Palette, StopsAreSampledAtTheEntriesCentres) {
    // Black to white: entry e is (e + 1/2) / 256.
    const fp::Palette grey = fp::palette_of_stops({0, 0, 0, 0, 1, 1, 1, 1}, "palette_stops");
    EXPECT_FLOAT_EQ(grey.colours[0].r, 0.5f / 256);
    EXPECT_FLOAT_EQ(grey.colours[255].g, 255.5f / 256);
    // Red, green, blue at 0, 1/2, 1: entry 64 lies at t = 64.5/256, a fraction 0.50390625 of the
    // way from red to green.
    const fp::Palette rgb = fp::palette_of_stops({0, 1, 0, 0, 0.5, 0, 1, 0, 1, 0, 0, 1}, "palette_stops");
    EXPECT_FLOAT_EQ(rgb.colours[64].r, 1 - 0.50390625f);
    EXPECT_FLOAT_EQ(rgb.colours[64].g, 0.50390625f);
    EXPECT_FLOAT_EQ(rgb.colours[64].b, 0);
    // Flat beyond the first and last stops.
    const fp::Palette mid = fp::palette_of_stops({0.25, 1, 0, 0, 0.75, 0, 0, 1}, "palette_stops");
    EXPECT_FLOAT_EQ(mid.colours[10].r, 1);
    EXPECT_FLOAT_EQ(mid.colours[250].b, 1);
    EXPECT_FLOAT_EQ(mid.colours[128].r, 1 - float((128.5 / 256 - 0.25) / 0.5));
}

TEST(Palette, Flam3sLookupStepAndLinear) {
    fp::Palette p = fp::palette_of_stops({0, 0, 0, 0, 1, 1, 1, 1}, "palette_stops");
    // Step: entry floor(256 t), clamped to [0, 255].
    EXPECT_EQ(p.at(0).r, p.colours[0].r);
    EXPECT_EQ(p.at(0.5f).r, p.colours[128].r);
    EXPECT_EQ(p.at(0.999f).r, p.colours[255].r);
    EXPECT_EQ(p.at(1).r, p.colours[255].r);
    EXPECT_EQ(p.at(-0.5f).r, p.colours[0].r);
    EXPECT_EQ(p.at(std::numeric_limits<float>::quiet_NaN()).r, p.colours[0].r);
    // Linear: between entry floor(256 t) and the next; the last pair at the top.
    p.linear = true;
    EXPECT_FLOAT_EQ(p.at(0.5f).r, p.colours[128].r);
    EXPECT_FLOAT_EQ(p.at(128.5f / 256).r, 0.5f * (p.colours[128].r + p.colours[129].r));
    EXPECT_FLOAT_EQ(p.at(1).r, p.colours[255].r);
    EXPECT_FLOAT_EQ(p.at(-1).r, p.colours[0].r);
}

TEST(Palette, Flam3FileEqualsItsEntries) {
    // The fixture's palette 0 ramps red by one step an entry; palette 1 is blue then red.
    const fp::Palette ramp = fp::read_flam3_palette(fixture, "0", "palette");
    for (int i = 0; i < 256; ++i) {
        EXPECT_FLOAT_EQ(ramp.colours[std::size_t(i)].r, float(i) / 255.0f) << i;
        EXPECT_EQ(ramp.colours[std::size_t(i)].g, 0.0f);
    }
    const fp::Palette two = fp::read_flam3_palette(fixture, "two-tone", "palette");
    EXPECT_EQ(two.colours[127].b, 1.0f);
    EXPECT_EQ(two.colours[127].r, 0.0f);
    EXPECT_EQ(two.colours[128].r, 1.0f);
    EXPECT_EQ(two.colours[128].b, 0.0f);
    EXPECT_EQ(fp::read_flam3_palette(fixture, "1", "palette").colours[200].r, 1.0f);
}

TEST(Palette, Flam3FileRefusals) {
    EXPECT_EQ(refusal([] { (void)fp::read_flam3_palette(fixture, "ramp-rde", "palette"); }),
              "palette: '" + fixture + "' holds no palette named 'ramp-rde' (did you mean 'ramp-red'?)");
    EXPECT_EQ(refusal([] { (void)fp::read_flam3_palette(fixture, "7", "palette"); }),
              "palette: '" + fixture + "' holds no palette number '7'");
    EXPECT_EQ(refusal([] { (void)fp::read_flam3_palette(fixture, "short", "palette"); }),
              "palette: palette 'short' of '" + fixture + "': its data is not 256 colours of 8 hex digits");
    EXPECT_EQ(refusal([] { (void)fp::read_flam3_palette("/nonexistent/p.xml", "0", "palette"); }),
              "palette: flam3's palettes are read from '/nonexistent/p.xml', which is not there: install "
              "Debian's flam3-palette (or set FIXPOINT_FLAM3_PALETTES to the file)");
    const std::string yaml = fp::test::source_dir() + "/bench/circles.yaml";
    EXPECT_EQ(refusal([&] { (void)fp::read_flam3_palette(yaml, "0", "palette"); }),
              "palette: '" + yaml + "' is not a flam3 palette file (no <palettes>)");
}

TEST(Palette, NamesAndTheirRefusals) {
    const fp::Palette fire = fp::palette_named("fire", "palette");
    EXPECT_FLOAT_EQ(fire.colours[0].r, 0.6f * float(0.5 / 256 / 0.35));
    EXPECT_EQ(refusal([] { (void)fp::palette_named("fier", "palette"); }),
              "palette: unknown palette 'fier' (did you mean 'fire'?); the built-ins are "
              "grey|fire|ice|sea|sunset|spectrum, and flam3's are flam3:N or flam3:NAME");
    EXPECT_EQ(refusal([] {
                  (void)fp::palette_of_stops({0, 0, 0, 0, 0, 1, 1, 1}, "palette_stops");
              }),
              "palette_stops: stop 1: the positions must increase");
    EXPECT_EQ(refusal([] {
                  (void)fp::palette_of_stops({0, 0, 0, 0, 1, 1, 1}, "palette_stops");
              }),
              "palette_stops: expected stops of four numbers each (t, r, g, b), got 7 numbers");
}

// Debian's flam3-palette (setup.sh installs it for the tests): its palette 0, read by number and
// by name, begins with the colour its first entry "00b9eaeb" gives.
TEST(Palette, Flam3sOwnFile) {
    const std::string path = "/usr/share/flam3/flam3-palettes.xml";
    ASSERT_TRUE(std::filesystem::exists(path)) << "install Debian's flam3-palette (./setup.sh test does)";
    for (const char* which : {"0", "south-sea-bather"}) {
        const fp::Palette p = fp::read_flam3_palette(path, which, "palette");
        EXPECT_FLOAT_EQ(p.colours[0].r, 0xb9 / 255.0f) << which;
        EXPECT_FLOAT_EQ(p.colours[0].g, 0xea / 255.0f) << which;
        EXPECT_FLOAT_EQ(p.colours[0].b, 0xeb / 255.0f) << which;
    }
}

} // namespace
