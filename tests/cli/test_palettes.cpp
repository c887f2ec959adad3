// flam3's palettes in the chaos game (docs/palettes.md): each chain carries a palette index that
// moves toward the chosen map's `color` by its `color_speed` (i' = s c_j + (1 - s) i) and colours
// its point through the `flame` colourer's palette. Checked: at color_speed 1 each point is its
// map's palette entry, the picture of map-colour with those entries; a palette render is the
// same bytes on any thread count, in strips, and resumed from a checkpoint; and its bad input
// gets one positioned line.
#include "cli.hpp"
#include "configs.hpp"

#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace fp::test;

namespace {

std::string triangle(const std::string& colourer, const std::string& maps) {
    return "renderer:\n  type: chaos-game\n  width: 96\n  height: 80\n  points: 200000\n  chains: 256\n"
           "  colourer: " +
           colourer + "\n  maps:\n" + maps;
}

const char* affine[] = {"[0.5, 0, 0, 0.5, 0, 0]", "[0.5, 0, 0, 0.5, 0.5, 0]", "[0.5, 0, 0, 0.5, 0.25, 0.5]"};

std::string maps_with(const std::vector<std::string>& extra) {
    std::string s;
    for (int j = 0; j < 3; ++j)
        s += std::string("    - {type: affine, coefficients: ") + affine[j] + ", " + extra[std::size_t(j)] +
             "}\n";
    return s;
}

TEST(Palettes, SpeedOneIsEachMapsEntryAsMapColourDrawsIt) {
    const std::string dir = scratch_dir("palettes_speed_one");
    // Grey's entries 0, 128 and 255 are (e + 1/2) / 256: exact in float and in the YAML below.
    write_file(dir + "/palette.yaml",
               triangle("{type: flame, palette_stops: [0, 0, 0, 0, 1, 1, 1, 1]}",
                        maps_with({"color: 0, color_speed: 1", "color: 0.5, color_speed: 1",
                                   "color: 1, color_speed: 1"})));
    write_file(dir + "/map.yaml", triangle("{type: map-colour}",
                                           maps_with({"colour: [0.001953125, 0.001953125, 0.001953125]",
                                                      "colour: [0.501953125, 0.501953125, 0.501953125]",
                                                      "colour: [0.998046875, 0.998046875, 0.998046875]"})));
    for (const char* name : {"palette", "map"}) {
        const auto r =
            run_cli({"render", "--quiet", dir + "/" + name + ".yaml", "-o", dir + "/" + name + ".png"});
        ASSERT_EQ(r.rc, 0) << r.err;
    }
    const fp::Image a = fp::host::read_image(dir + "/palette.png"),
                    b = fp::host::read_image(dir + "/map.png");
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    EXPECT_EQ(a.pixels, b.pixels);
    // At speed 1/2 the index runs through the palette: other colours.
    write_file(dir + "/half.yaml", triangle("{type: flame, palette_stops: [0, 0, 0, 0, 1, 1, 1, 1]}",
                                            maps_with({"color: 0", "color: 0.5", "color: 1"})));
    const auto r = run_cli({"render", "--quiet", dir + "/half.yaml", "-o", dir + "/half.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(fp::host::read_image(dir + "/half.png").pixels, a.pixels);
}

TEST(Palettes, SameBytesOnAnyThreadsInStripsAndResumed) {
    const std::string dir = scratch_dir("palettes_bytes");
    // (400 x 300: large enough for strips within a few MiB.)
    write_file(dir + "/p.yaml",
               replace_once(triangle("{type: flame, palette: sunset, palette_mode: linear}",
                                     maps_with({"color: 0.1", "color: 0.6, color_speed: 0.3", "color: 0.9"})),
                            "width: 96\n  height: 80", "width: 400\n  height: 300"));
    const auto one =
        run_cli({"render", "--quiet", "--threads", "1", dir + "/p.yaml", "-o", dir + "/one.png"});
    ASSERT_EQ(one.rc, 0) << one.err;
    const auto three =
        run_cli({"render", "--quiet", "--threads", "3", dir + "/p.yaml", "-o", dir + "/three.png"});
    ASSERT_EQ(three.rc, 0) << three.err;
    EXPECT_EQ(read_file(dir + "/one.png"), read_file(dir + "/three.png"));
    const auto strips = run_cli({"render", "--memory", "6M", dir + "/p.yaml", "-o", dir + "/strips.png"});
    ASSERT_EQ(strips.rc, 0) << strips.err;
    EXPECT_NE(strips.err.find(" strips of "), std::string::npos) << strips.err;
    EXPECT_EQ(read_file(dir + "/strips.png"), read_file(dir + "/one.png"));
    // Half the points with a checkpoint, continued to all: the chains' palette indices are kept.
    const auto half = run_cli({"render", "--quiet", dir + "/p.yaml", "--set", "renderer.points=100000", "-o",
                               dir + "/half.png", "--checkpoint", dir + "/ck.bin"});
    ASSERT_EQ(half.rc, 0) << half.err;
    const auto more =
        run_cli({"render", "--quiet", dir + "/p.yaml", "-o", dir + "/more.png", "--resume", dir + "/ck.bin"});
    ASSERT_EQ(more.rc, 0) << more.err;
    EXPECT_EQ(read_file(dir + "/more.png"), read_file(dir + "/one.png"));
}

TEST(Palettes, Flam3PaletteByNumberAndByName) {
    const std::string dir = scratch_dir("palettes_flam3");
    for (const char* p : {"flam3:0", "flam3:south-sea-bather"}) {
        write_file(dir + "/p.yaml",
                   triangle(std::string("{type: flame, palette: ") + p + "}", maps_with({"", "", ""})));
        const auto r = run_cli(
            {"render", "--quiet", dir + "/p.yaml", "-o", dir + "/" + (p[6] == '0' ? "n" : "s") + ".png"});
        ASSERT_EQ(r.rc, 0) << r.err;
    }
    EXPECT_EQ(fp::host::read_image(dir + "/n.png").pixels, fp::host::read_image(dir + "/s.png").pixels);
}

struct Bad {
    const char* name;
    std::string colourer, maps, expected;
};

void PrintTo(const Bad& c, std::ostream* os) { *os << c.name; }

class PaletteBadInput : public ::testing::TestWithParam<Bad> {};

TEST_P(PaletteBadInput, OneLineExitTwoNothingWritten) {
    const Bad& c = GetParam();
    EXPECT_EQ(run_bad_input(std::string("palette_") + c.name, triangle(c.colourer, c.maps),
                            {"render", "--quiet", "bad.yaml", "-o", "out.png"}),
              c.expected);
}

INSTANTIATE_TEST_SUITE_P(
    Palettes, PaletteBadInput,
    ::testing::Values(
        Bad{"unknown_name", "{type: flame, palette: fier}", maps_with({"", "", ""}),
            "bad.yaml:7:36: renderer.colourer.palette: unknown palette 'fier' (did you mean 'fire'?); the "
            "built-ins are grey|fire|ice|sea|sunset|spectrum, and flam3's are flam3:N or flam3:NAME"},
        Bad{"flam3_unknown", "{type: flame, palette: flam3:south-sea-bathr}", maps_with({"", "", ""}),
            "bad.yaml:7:36: renderer.colourer.palette: '/usr/share/flam3/flam3-palettes.xml' holds no "
            "palette "
            "named 'south-sea-bathr' (did you mean 'south-sea-bather'?)"},
        Bad{"not_mean", "{type: flame, palette: fire, mode: set-colour}", maps_with({"", "", ""}),
            "bad.yaml:7:48: renderer.colourer.mode: a palette colours each point by flam3's index, whose "
            "pixels "
            "show the mean: mode mean, not set-colour"},
        Bad{"stops_order", "{type: flame, palette_stops: [0.5, 0, 0, 0, 0.2, 1, 1, 1]}",
            maps_with({"", "", ""}),
            "bad.yaml:7:42: renderer.colourer.palette_stops: stop 1: the positions must increase"},
        Bad{"color_without_palette", "{type: flame}", maps_with({"", "color: 0.5", ""}),
            "bad.yaml:9:5: renderer.maps: maps[1].color: a palette index (flam3's), but the colourer takes "
            "no "
            "palette (flame with palette: ...)"},
        Bad{"color_range", "{type: flame, palette: fire}", maps_with({"color: 1.5", "", ""}),
            "bad.yaml:9:67: renderer.maps[0].color: must be in [0, 1], got 1.5"}),
    [](const auto& info) { return std::string(info.param.name); });

} // namespace
