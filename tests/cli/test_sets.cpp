// chaos-game's `sets`: the sets of the maps and their centres of inversion, beside the fractal
// (papers 01 and 02's two-panel figures), over it, or alone (raster, SVG, PDF). Checked on the
// pixels: the fractal's half is the plain render's, bit for bit; a set's inside is its colour
// at the fill's opacity; a centre is its map's colour; outside every set, the background.
#include "cli.hpp"
#include "configs.hpp"

#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

// 96 x 80 pixels over [-1.6, 1.6] x [-1.4, 1.4]: 30 pixels per unit.
const std::string config = chaos_game({"width: 96", "height: 80", "view: [-1.6, 1.6, -1.4, 1.4]",
                                       "points: 200000", "chains: 200", "seed: 5", "sets: none"},
                                      three_circles("0.9", true));

struct Rendered {
    fp::Image img;
    std::string dir;
};

Rendered render(const std::string& name, const std::string& sets, const std::string& out = "out.png") {
    Rendered r{{}, scratch_dir("sets_" + name)};
    write_file(r.dir + "/c.yaml", replace_once(config, "sets: none", sets));
    const auto res = run_cli({"render", "--quiet", r.dir + "/c.yaml", "-o", r.dir + "/" + out});
    EXPECT_EQ(res.rc, 0) << res.err;
    if (out.ends_with(".png")) r.img = fp::host::read_image(r.dir + "/" + out);
    return r;
}

/// Pixel (column c, row r) of an image, channel k.
float at(const fp::Image& img, int c, int r, int k) {
    return img.pixels[(std::size_t(r) * std::size_t(img.width) + std::size_t(c)) * std::size_t(img.channels) +
                      std::size_t(k)];
}

/// The pixel whose centre is nearest the point (x, y) of the plane.
std::pair<int, int> pixel_of(double x, double y) {
    return {int(std::floor((x + 1.6) * 30)), int(std::floor((1.4 - y) * 30))};
}

} // namespace

TEST(Sets, BesideKeepsTheFractalBitForBitAndDrawsTheSetsLeft) {
    const fp::Image plain = render("plain", "sets: none").img;
    // (In the fractal's view, so that pixel_of finds the sets' pixels on the left too.)
    const fp::Image both = render("beside", "sets: beside\n  set_view: [-1.6, 1.6, -1.4, 1.4]").img;
    ASSERT_EQ(both.width, 2 * plain.width);
    ASSERT_EQ(both.height, plain.height);
    bool lit = false;
    for (int r = 0; r < plain.height; ++r)
        for (int c = 0; c < plain.width; ++c)
            for (int k = 0; k < 3; ++k) {
                ASSERT_EQ(at(both, plain.width + c, r, k), at(plain, c, r, k)) << c << "," << r;
                lit = lit || at(plain, c, r, k) > 0;
            }
    ASSERT_TRUE(lit);
    // The centre of the first circle: its colour (the centre's dot).
    auto [cc, cr] = pixel_of(1, 0);
    EXPECT_NEAR(at(both, cc, cr, 0), 1.0, 1.0 / 255);
    EXPECT_NEAR(at(both, cc, cr, 1), 0.4, 1.0 / 255);
    EXPECT_NEAR(at(both, cc, cr, 2), 0.2, 1.0 / 255);
    // Inside it, away from its edge and its centre: 0.3 of its colour over black.
    auto [ic, ir] = pixel_of(1.35, 0.35);
    EXPECT_NEAR(at(both, ic, ir, 0), 0.3, 1.5 / 255);
    EXPECT_NEAR(at(both, ic, ir, 1), 0.12, 1.5 / 255);
    EXPECT_NEAR(at(both, ic, ir, 2), 0.06, 1.5 / 255);
    // Outside every set: the background.
    auto [oc, orow] = pixel_of(-1.5, 1.3);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(at(both, oc, orow, k), 0.0f);
}

// Without set_view the panel shows the sets whole. By hand: the circles of radius 0.9 at (1, 0)
// and (-0.5, +-0.866) span [-1.4, 1.9] x [-1.766, 1.766]; with 5% margins, 3.63 x 3.885, widened
// to the panel's 96:80, the view is [-2.0811, 2.5811] x [-1.9426, 1.9426], 20.59 pixels a unit.
TEST(Sets, ThePanelShowsTheSetsWholeByDefault) {
    const fp::Image only = render("whole", "sets: only").img;
    ASSERT_EQ(only.width, 96);
    ASSERT_EQ(only.height, 80);
    // The first circle's centre, (1, 0): pixel (63.4, 40.0), inside its dot of radius 4.
    EXPECT_NEAR(at(only, 63, 40, 0), 1.0, 1.0 / 255);
    EXPECT_NEAR(at(only, 63, 40, 1), 0.4, 1.0 / 255);
    // The second circle's top, y = 1.766, at row 3.6: the rows above it are the background,
    // and the margin is no wider than 5% (its outline lights row 4 or 5).
    auto row_lit = [&](int r) {
        for (int c = 0; c < 96; ++c)
            if (at(only, c, r, 0) + at(only, c, r, 1) + at(only, c, r, 2) > 0.05f) return true;
        return false;
    };
    EXPECT_FALSE(row_lit(0));
    EXPECT_FALSE(row_lit(1));
    EXPECT_FALSE(row_lit(79));
    EXPECT_TRUE(row_lit(5));
    EXPECT_TRUE(row_lit(74));
    // The first circle's right edge, x = 1.9, at column 81.96: lit; the columns beyond its
    // stroke are not.
    EXPECT_GT(at(only, 81, 40, 0), 0.2f);
    for (int c = 84; c < 96; ++c) EXPECT_EQ(at(only, c, 40, 0), 0.0f) << c;
}

TEST(Sets, OverBlendsTheSetsOnTheFractal) {
    const fp::Image plain = render("plain2", "sets: none").img;
    const fp::Image over = render("over", "sets: over").img;
    ASSERT_EQ(over.width, plain.width);
    // Outside every set the fractal's pixels are untouched; inside one, 0.3 of the set's
    // colour over 0.7 of the fractal.
    auto [oc, orow] = pixel_of(-1.5, 1.3);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(at(over, oc, orow, k), at(plain, oc, orow, k));
    const float colour[3] = {1, 0.4f, 0.2f};
    for (double y : {0.3, 0.35, 0.4}) {
        auto [ic, ir] = pixel_of(1.35, y);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(at(over, ic, ir, k), 0.3 * colour[k] + 0.7 * at(plain, ic, ir, k), 2.0 / 255);
    }
}

TEST(Sets, OnlyDrawsTheLeftPanelAloneAndAsVectors) {
    const fp::Image both = render("beside2", "sets: beside").img;
    const fp::Image only = render("only", "sets: only").img;
    ASSERT_EQ(only.width, 96);
    for (int r = 0; r < only.height; ++r)
        for (int c = 0; c < only.width; ++c)
            for (int k = 0; k < 3; ++k) ASSERT_EQ(at(only, c, r, k), at(both, c, r, k));
    // SVG: one path per set and one per centre, and the recipe inside.
    const Rendered svg = render("svg", "sets: only", "sets.svg");
    const std::string doc = read_file(svg.dir + "/sets.svg");
    std::size_t paths = 0;
    for (auto p = doc.find("<path"); p != std::string::npos; p = doc.find("<path", p + 1)) ++paths;
    EXPECT_GE(paths, 3u);
    const auto rec = run_cli({"recipe", svg.dir + "/sets.svg"});
    EXPECT_EQ(rec.rc, 0);
    EXPECT_NE(rec.out.find("sets: \"only\""), std::string::npos) << rec.out;
    const Rendered pdf = render("pdf", "sets: only", "sets.pdf");
    EXPECT_EQ(read_file(pdf.dir + "/sets.pdf").rfind("%PDF", 0), 0u);
}

TEST(Sets, TheSetsViewIsTheLeftPanelsOwn) {
    // Twice the view: the first circle's centre moves to where (0.5, 0) was.
    const fp::Image wide = render("wide", "sets: only\n  set_view: [-3.2, 3.2, -2.8, 2.8]").img;
    auto [cc, cr] = pixel_of(0.5, 0);
    EXPECT_NEAR(at(wide, cc, cr, 0), 1.0, 1.0 / 255);
    EXPECT_NEAR(at(wide, cc, cr, 1), 0.4, 1.0 / 255);
}

TEST(Sets, RefusedWhereTheyCannotBeDrawn) {
    const std::string affine = R"(renderer:
  type: chaos-game
  sets: beside
  maps:
    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}
    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}
)";
    EXPECT_EQ(fp::test::run_bad_input("sets_affine", affine),
              "bad.yaml:3:9: renderer.sets: none of the maps has a set to draw (inversions have one)");
    const std::string over_view =
        replace_once(config, "sets: none", "sets: over\n  set_view: [-2, 2, -2, 2]");
    EXPECT_EQ(
        fp::test::run_bad_input("sets_over_view", over_view),
        "bad.yaml:10:13: renderer.set_view: the sets' own view needs sets: beside or sets: only (over the "
        "fractal, the sets are drawn in its view)");
    const std::string fractal = replace_once(config, "sets: none", "sets: over");
    EXPECT_EQ(
        fp::test::run_bad_input("sets_over_svg", fractal, {"render", "--quiet", "bad.yaml", "-o", "out.svg"}),
        "bad.yaml:2:3: renderer: this renderer has no vector output: write 'out.svg' as .png, .exr or .tif "
        "instead");
}

// Every figure of papers 01 (Figs. 4-6) and 02 (Figs. 3, 6(a), 7(a), 8, 11) whose left half shows
// the sets: its config with `sets: beside` draws them left of the fractal it renders alone,
// whole.
TEST(Sets, EveryTwoPanelFigureOfThePapers) {
    const std::string configs[] = {
        "inversion/fig4a", "inversion/fig4b", "inversion/fig4c", "inversion/fig4d",  "inversion/fig5a",
        "inversion/fig5b", "inversion/fig5c", "inversion/fig5d", "inversion/fig6a",  "inversion/fig6b",
        "inversion/fig6c", "inversion/fig6d", "iterations/fig3", "iterations/fig6a", "iterations/fig7a",
        "iterations/fig8", "iterations/fig11"};
    for (const auto& c : configs) {
        const std::string dir = scratch_dir("sets_fig_" + c.substr(c.find('/') + 1) + "_" + c.substr(0, 3));
        const std::string cfg = fp::test::source_dir() + "/configs/" + c + ".yaml";
        const std::vector<std::string> small = {
            "--set", "renderer.width=64", "--set", "renderer.height=64", "--set", "renderer.points=20000"};
        auto run = [&](const std::string& sets, const std::string& out) {
            std::vector<std::string> args = {
                "render", "--quiet", cfg, "-o", dir + "/" + out, "--set", "renderer.sets=" + sets};
            args.insert(args.end(), small.begin(), small.end());
            const auto res = run_cli(args);
            EXPECT_EQ(res.rc, 0) << c << ": " << res.err;
            return fp::host::read_image(dir + "/" + out);
        };
        const fp::Image plain = run("none", "plain.png"), both = run("beside", "both.png");
        ASSERT_EQ(both.width, 128) << c;
        std::size_t set_pixels = 0;
        for (int r = 0; r < 64; ++r)
            for (int x = 0; x < 64; ++x) {
                for (int k = 0; k < 3; ++k) ASSERT_EQ(at(both, 64 + x, r, k), at(plain, x, r, k)) << c;
                set_pixels += at(both, x, r, 0) + at(both, x, r, 1) + at(both, x, r, 2) > 0.1f;
            }
        EXPECT_GT(set_pixels, 64u * 64u / 10) << c << ": the sets cover a tenth of their panel at least";
        // Whole: nothing of them on the panel's border (the margin is 5%, 3 pixels here).
        for (int i = 0; i < 64; ++i)
            for (const auto& [x, r] : {std::pair{i, 0}, std::pair{i, 63}, std::pair{0, i}, std::pair{63, i}})
                EXPECT_LT(at(both, x, r, 0) + at(both, x, r, 1) + at(both, x, r, 2), 0.1f)
                    << c << ": a set at the border, pixel " << x << "," << r;
    }
}
