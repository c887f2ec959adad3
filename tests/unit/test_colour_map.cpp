// The colour-map colourer (paper 04, Algorithm 1, Table 1, and the index rule of Algorithm 3
// lines 16-17): table entries against hand computation, the index rule, the background, bad input.
#include "host.hpp"

#include <fixpoint/fixpoint.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::Colourer;
using fp::Rgb;

// The colour of one caught sample with trap ratio d / r = `ratio`.
Rgb hit(const Colourer& c, float ratio, const Rgb* background = nullptr, std::int32_t trap = 0) {
    std::uint32_t it = 1;
    float rgb[3] = {-1, -1, -1};
    c.colour_hits(&trap, &ratio, &it, 1, background, rgb);
    return {rgb[0], rgb[1], rgb[2]};
}

// The ratio whose index (v / (1 - v), v = ratio^(1/E)) is i + 1/2: entry i, away from rounding.
float ratio_of_entry(int i, double e) { return float(std::pow((i + 0.5) / (i + 1.5), e)); }

void expect_rgb(Rgb got, Rgb want, double tol = 2e-7) {
    EXPECT_NEAR(got.r, want.r, tol);
    EXPECT_NEAR(got.g, want.g, tol);
    EXPECT_NEAR(got.b, want.b, tol);
}

std::string error_of(const std::string& yaml) { return fp::test::error_of(fp::Kind::Colourer, yaml); }

TEST(ColourMap, SmallTableByHand) {
    // Black to white over ratios [0, 1], E = 1, Nc = 5: entry i has q = i / (1 + i) and is the
    // grey q (t = (1 - q) / 1 weights black): 0, 1/2, 2/3, 3/4, 4/5.
    auto c =
        make<Colourer>("{type: colour-map, colours: [0, 0, 0, 255, 255, 255], ratios: [0, 1], E: 1, Nc: 5}");
    const float grey[5] = {0, 0.5f, 2.0f / 3, 0.75f, 0.8f};
    for (int i = 0; i < 5; ++i) expect_rgb(hit(*c, ratio_of_entry(i, 1)), {grey[i], grey[i], grey[i]});
    // The index rule itself: d / r = 0.5 gives v = 0.5, v / (1 - v) = 1: entry 1. d = 0: entry 0.
    expect_rgb(hit(*c, 0.5f), {0.5f, 0.5f, 0.5f});
    expect_rgb(hit(*c, 0.0f), {0, 0, 0});
    // d / r = 0.9: v / (1 - v) = 9, clamped to Nc - 1 = 4; just below 1 likewise.
    expect_rgb(hit(*c, 0.9f), {0.8f, 0.8f, 0.8f});
    expect_rgb(hit(*c, 0.99999994f), {0.8f, 0.8f, 0.8f});
    // E = 2: q = (i / (1 + i))^2 = 0, 1/4, 4/9, 9/16, 16/25; the ratio of entry 2 is (2.5/3.5)^2.
    auto c2 =
        make<Colourer>("{type: colour-map, colours: [0, 0, 0, 255, 255, 255], ratios: [0, 1], E: 2, Nc: 5}");
    expect_rgb(hit(*c2, ratio_of_entry(2, 2)), {4.0f / 9, 4.0f / 9, 4.0f / 9});
    expect_rgb(hit(*c2, ratio_of_entry(3, 2)), {9.0f / 16, 9.0f / 16, 9.0f / 16});
}

TEST(ColourMap, Fig4aEntriesByHand) {
    // Table 1(a), E = 16, Nc = 3000. Entry i is the colour of q = (i / (1 + i))^16:
    auto c = make<Colourer>("{type: colour-map, preset: fig-4a}");
    // i = 0: q = 0 = q_0: b_0, black.
    expect_rgb(hit(*c, ratio_of_entry(0, 16)), {0, 0, 0});
    // i = 44: q = (44/45)^16 = 0.697979 <= q_1 = 0.7: t = (0.7 - q) / 0.7 = 0.0028866, the colour
    // t b_0 + (1 - t) b_1 = (0.9971134, 0, 0).
    expect_rgb(hit(*c, ratio_of_entry(44, 16)), {0.9971134f, 0, 0});
    // i = 45: q = (45/46)^16 = 0.703518 in (0.7, 0.75]: t = (0.75 - q) / 0.05 = 0.929650 between
    // b_1 = (255, 0, 0) and b_2 = (255, 128, 0): (1, (1 - t) 128/255, 0) = (1, 0.0353131, 0).
    expect_rgb(hit(*c, ratio_of_entry(45, 16)), {1, 0.0353131f, 0});
    // i = 60: q = (60/61)^16 = 0.767614 in (0.75, 0.8]: t = (0.8 - q) / 0.05 = 0.647729 between
    // b_2 = (255, 128, 0) and b_3 = black: t (1, 128/255, 0) = (0.647729, 0.325134, 0).
    expect_rgb(hit(*c, ratio_of_entry(60, 16)), {0.6477285f, 0.3251343f, 0});
    // i = 2999 (the last): q = (2999/3000)^16 = 0.994680 in (0.9, 1]: t = (1 - q) / 0.1 = 0.0532002
    // between white and (26, 0, 0): (t + (1 - t) 26/255, t, t) = (0.1497367, 0.0532002, 0.0532002).
    const Rgb last{0.1497367f, 0.0532002f, 0.0532002f};
    expect_rgb(hit(*c, ratio_of_entry(2999, 16)), last);
    // Never trapped: the last entry (Algorithm 3, line 21), or the renderer's background.
    expect_rgb(hit(*c, 0.5f, nullptr, -1), last);
    const Rgb blue{0, 0, 1};
    expect_rgb(hit(*c, 0.5f, &blue, -1), blue);
    // Whatever the ratio of an untrapped sample says.
    expect_rgb(hit(*c, std::nanf(""), &blue, -1), blue);
}

TEST(ColourMap, PresetsAreTable1) {
    // Each preset equals the same map written out (Table 1 rows), entry by entry.
    const char* rows[4][2] = {
        {"fig-4a", "colours: [0,0,0, 255,0,0, 255,128,0, 0,0,0, 255,128,0, 255,255,255, 26,0,0], "
                   "ratios: [0, 0.7, 0.75, 0.8, 0.85, 0.9, 1]"},
        {"fig-4b",
         "colours: [0,0,0, 0,0,150, 161,202,241, 243,195,0, 0,0,0, 243,195,0, 255,255,255, 26,0,0], "
         "ratios: [0, 0.5, 0.7, 0.75, 0.8, 0.85, 0.9, 1]"},
        {"fig-4c", "colours: [0,0,0, 6,204,2, 0,0,0, 19,158,245, 200,200,200, 115,106,55], "
                   "ratios: [0, 0.6, 0.8, 0.85, 0.9, 1]"},
        {"fig-4d", "colours: [0,0,0, 254,0,0, 0,255,0, 255,255,127, 25,0,0, 255,52,0, 0,128,255, 25,0,0], "
                   "ratios: [0, 0.25, 0.3, 0.47, 0.6, 0.7, 0.85, 1]"},
    };
    for (auto& r : rows) {
        auto a = make<Colourer>(std::string("{type: colour-map, preset: ") + r[0] + "}");
        auto b = make<Colourer>(std::string("{type: colour-map, ") + r[1] + "}");
        for (int i = 0; i < 3000; i += 7) {
            const Rgb x = hit(*a, ratio_of_entry(i, 16)), y = hit(*b, ratio_of_entry(i, 16));
            EXPECT_TRUE(x == y) << r[0] << " entry " << i;
        }
    }
}

TEST(ColourMap, ResolveUsesTheTableAndTheBackground) {
    auto c =
        make<Colourer>("{type: colour-map, colours: [0, 0, 0, 255, 255, 255], ratios: [0, 1], E: 1, Nc: 5}");
    fp::Histogram h;
    h.resize(2, 1);
    h.bins[0].hits = 0;
    h.bins[1].hits = 10; // the densest bin: density 1, the last entry (grey 0.8)
    float px[6];
    c->resolve(h, Rgb{0.1f, 0.2f, 0.3f}, px);
    EXPECT_EQ(px[0], 0.1f);
    EXPECT_EQ(px[1], 0.2f);
    EXPECT_EQ(px[2], 0.3f);
    EXPECT_NEAR(px[3], 0.8f, 1e-7);
    EXPECT_TRUE(c->colours_trap_hits());
    EXPECT_FALSE(c->needs_colour());
}

TEST(ColourMap, BadInput) {
    const std::string two = "colours: [0, 0, 0, 255, 255, 255]";
    EXPECT_EQ(error_of("{type: colour-map, " + two + ", ratios: [0, 1], E: 0}"),
              "colourer.E: must be > 0, got 0");
    EXPECT_EQ(error_of("{type: colour-map, " + two + ", ratios: [0, 1], Nc: 1}"),
              "colourer.Nc: must be in [2, 16777216], got 1");
    EXPECT_EQ(
        error_of("{type: colour-map, " + two + ", ratios: [0.5, 0.5]}"),
        "colourer.ratios: the ratios must increase strictly: ratios[1] = 0.5 is not above ratios[0] = 0.5");
    EXPECT_EQ(error_of("{type: colour-map, " + two + ", ratios: [0, 1.5]}"),
              "colourer.ratios[1]: must be in [0, 1], got 1.5");
    EXPECT_EQ(error_of("{type: colour-map, " + two + ", ratios: [0, 0.5, 1]}"),
              "colourer.ratios: expected 2 ratios (one per base colour), got 3");
    EXPECT_EQ(error_of("{type: colour-map, colours: [0, 0, 0], ratios: [0]}"),
              "colourer.colours: a colour map needs at least 2 base colours, got 1");
    EXPECT_EQ(error_of("{type: colour-map, colours: [0, 0, 0, 255], ratios: [0, 1]}"),
              "colourer.colours: expected r, g, b triples (a multiple of 3 numbers), got 4 numbers");
    EXPECT_EQ(error_of("{type: colour-map, colours: [0, 0, 0, 256, 0, 0], ratios: [0, 1]}"),
              "colourer.colours[3]: must be in [0, 255], got 256");
    EXPECT_EQ(error_of("{type: colour-map}"),
              "colourer: no colours: give colours and ratios, or a preset (fig-4a, fig-4b, fig-4c, fig-4d)");
    EXPECT_EQ(error_of("{type: colour-map, preset: fig-4a, " + two + "}"),
              "colourer.colours: give either a preset or colours and ratios, not both");
}

} // namespace
