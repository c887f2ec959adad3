// `fixpoint render --tile`: one period of an orbit-trap pattern, so that copies join without a
// seam; `--dpi` / `--print-size` in the image's metadata; the refusals.
//
// The seam test: the 2 x 2 tiling of a W x H tile is compared pixel by pixel with a render,
// without --tile, of 2W x 2H pixels over two periods in each direction, its area chosen so that
// its pixel centres are the tile's, one period on: with no seam the two images agree.
//   - With double orbits they agree exactly, every byte of all four quadrants (the test asserts
//     it): f(p + t) and f(p) differ by rounding (about 1e-15), too little to change a trap or a
//     colour in 8 bits over these orbits.
//   - With float orbits (the default) they cannot always agree: the rounding of f(p + t) against
//     f(p), grown by chaotic orbits, changes a few samples. The bar is the rounding noise itself:
//     the quadrant where the tile lies untranslated (the same points, rounded by the other
//     formula) sets it, and each translated quadrant (one period right, up, or both) must agree
//     as well (a slack of 0.5% of the pixels off by more than 2 / 255, and below 1% in all).
//     Measured at 200 x 200 pixels, 8 samples: 0.03-0.05% (cmm), 0.007-0.01% (p3m1).
// A hexagonal pattern cut to the square cell (2 pi is no period upwards) fails by far: the last
// seam test checks that the comparison sees such a seam.
#include "cli.hpp"
#include "host.hpp"

#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

constexpr double pi = std::numbers::pi;

// Paper 04's Fig. 6(a) (cmm, square lattice) and Fig. 5(a) (p3m1, hexagonal), small and with
// few samples; double orbits (the float tests set renderer.precision=float).
const std::string cmm = R"(renderer:
  type: orbit-trap
  width: 40
  height: 40
  max_iterations: 100
  samples: 4
  precision: double
  mapping:
    type: wallpaper
    group: cmm
    P04: [0, -0.890893]
    P13: [0, 0.594811]
    P24: [0, 0.166299]
    P31: [2.33836, 0]
    P40: [-1.53665, 0]
    P42: [0.149503, 0]
  traps: {type: circles, preset: fig-3a, metric: {type: lp, p: 1}}
  colourer: {type: colour-map, preset: fig-4c, E: 16, Nc: 3000}
)";

const std::string p3m1 = R"(renderer:
  type: orbit-trap
  width: 32
  height: 32
  max_iterations: 100
  samples: 4
  precision: double
  mapping:
    type: wallpaper
    group: p3m1
    G: [[0.343244, 0.711418], [-0.671499, -0.289951], [-0.959405, -0.868905]]
    H: [[-0.224996, 0.0844803], [-0.0571376, 0.0250126], [0.0250892, 0.553883]]
  traps: {type: circles, preset: fig-1a}
  colourer: {type: colour-map, preset: fig-4b, E: 16, Nc: 3000}
)";

std::string real(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

fp::Image render(const std::string& dir, const std::string& config, std::vector<std::string> extra,
                 const std::string& name) {
    std::vector<std::string> args = {"render", "--quiet", dir + "/" + config, "-o", dir + "/" + name};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.rc, 0) << r.err;
    return fp::host::read_image(dir + "/" + name);
}

// The fraction of pixels of `big`'s quadrant (qx, qy) (each W x H) differing from `tile` by more
// than `by` in some channel.
double mismatch(const fp::Image& big, const fp::Image& tile, int qx, int qy, float by) {
    const int W = tile.width, H = tile.height, c = tile.channels;
    long bad = 0;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const float* a = &tile.pixels[(std::size_t(j) * W + i) * c];
            const float* b =
                &big.pixels[((std::size_t(j) + std::size_t(qy) * H) * big.width + i + qx * W) * c];
            float d = 0;
            for (int k = 0; k < 3; ++k) d = std::max(d, std::fabs(a[k] - b[k]));
            bad += d > by;
        }
    return double(bad) / double(W * H);
}

struct Seam {
    double untranslated;  ///< quadrant (0, 1): the tile's own points
    double translated[3]; ///< quadrants (1, 1), (0, 0), (1, 0): one period right, up, both
};

// Render the 2 x 2 periods the tile of `config` (cell w x h, centred on 0) should tile, and
// measure each quadrant's mismatch (pixels off by more than `by`).
Seam seam(const std::string& dir, const std::string& config, double w, double h, int W, int H,
          const fp::Image& tile, float by, const std::vector<std::string>& extra = {}) {
    const double dx = w / W, dy = h / H;
    // Pixel centres xmin + (i + 1/2) dx, i < 2W, and ymax - (j + 1/2) dy, j < 2H, from the tile's
    // corner (-w / 2, -h / 2): rows 0 .. H - 1 are one period up, columns W .. 2W - 1 one right.
    const std::string area = "renderer.area=[" + real(-w / 2 + dx / 2) + ", " +
                             real(-w / 2 + 2 * w - dx / 2) + ", " + real(-h / 2 + dy / 2) + ", " +
                             real(-h / 2 + 2 * h - dy / 2) + "]";
    std::vector<std::string> args = {"--set", area,
                                     "--set", "renderer.width=" + std::to_string(2 * W),
                                     "--set", "renderer.height=" + std::to_string(2 * H)};
    args.insert(args.end(), extra.begin(), extra.end());
    const fp::Image big = render(dir, config, args, "big.png");
    EXPECT_EQ(big.width, 2 * W);
    EXPECT_EQ(big.height, 2 * H);
    return {mismatch(big, tile, 0, 1, by),
            {mismatch(big, tile, 1, 1, by), mismatch(big, tile, 0, 0, by), mismatch(big, tile, 1, 0, by)}};
}

void expect_exact(const Seam& s) {
    EXPECT_EQ(s.untranslated, 0);
    for (double t : s.translated) EXPECT_EQ(t, 0);
}

void expect_within_noise(const Seam& s) {
    EXPECT_LT(s.untranslated, 0.01);
    for (double t : s.translated) {
        EXPECT_LE(t, s.untranslated + 0.005);
        EXPECT_LT(t, 0.01);
    }
    std::printf("mismatch: untranslated %.4f, translated %.4f %.4f %.4f\n", s.untranslated, s.translated[0],
                s.translated[1], s.translated[2]);
}

// The periods the wallpaper maps declare are periods, for all 17 groups (random coefficients,
// no reduction, double): f(p + t) = f(p) to rounding for t = a, b and the rectangle's sides.
// A map that is not periodic declares none.
TEST(Tile, WallpaperMapsDeclareTheirPeriods) {
    for (const char* g : {"p1", "p2", "pm", "pg", "cm", "pmm", "cmm", "pmg", "pgg", "p4", "p4m", "p4g", "p3",
                          "p3m1", "p31m", "p6", "p6m"}) {
        const auto f = fp::test::host().make<fp::Transform>(std::string("{type: wallpaper, group: ") + g +
                                                            ", seed: 5, reduction: none}");
        ASSERT_TRUE(f);
        const auto cell = f->periods();
        ASSERT_TRUE(cell) << g;
        const bool hex =
            std::string(g).find('3') != std::string::npos || std::string(g).find('6') != std::string::npos;
        EXPECT_DOUBLE_EQ(cell->width, 2 * pi) << g;
        EXPECT_DOUBLE_EQ(cell->height, hex ? 2 * pi * std::numbers::sqrt3 : 2 * pi) << g;
        const fp::Vec2 ts[] = {
            cell->a, cell->b, {cell->width, 0}, {0, cell->height}, {-cell->width, cell->height}};
        double worst = 0;
        for (int k = 0; k < 50; ++k) {
            const double px = 0.37 * k - 9, py = 0.61 * (k % 17) - 5;
            double x0 = px, y0 = py;
            f->apply(fp::Points<double>{&x0, &y0, 1}, nullptr);
            for (const fp::Vec2& t : ts) {
                double x = px + t.x, y = py + t.y;
                f->apply(fp::Points<double>{&x, &y, 1}, nullptr);
                worst = std::max({worst, std::fabs(x - x0), std::fabs(y - y0)});
            }
        }
        EXPECT_LT(worst, 1e-12) << g;
        // Half the rectangle is no period (the groups' centring (pi, pi) of cm and cmm aside).
        double x0 = 0.3, y0 = 0.2, x = 0.3, y = 0.2 + cell->height / 2;
        f->apply(fp::Points<double>{&x0, &y0, 1}, nullptr);
        f->apply(fp::Points<double>{&x, &y, 1}, nullptr);
        EXPECT_GT(std::fabs(x - x0) + std::fabs(y - y0), 1e-6) << g;
        // cm and cmm also forget their centring (pi, pi) (2 pi Z^2 is a sublattice of theirs).
        if (std::string(g) == "cm" || std::string(g) == "cmm") {
            x = 0.3 + pi, y = 0.2 + pi;
            f->apply(fp::Points<double>{&x, &y, 1}, nullptr);
            EXPECT_LT(std::fabs(x - x0) + std::fabs(y - y0), 1e-12) << g;
        }
    }
    EXPECT_FALSE(fp::test::host().make<fp::Transform>("{type: gumowski-mira}")->periods());
}

TEST(Tile, SquareGroupTilesWithoutSeam) {
    const std::string dir = scratch_dir("tile_square");
    write_file(dir + "/cmm.yaml", cmm);
    const fp::Image tile = render(dir, "cmm.yaml", {"--tile"}, "tile.png");
    ASSERT_EQ(tile.width, 40);
    ASSERT_EQ(tile.height, 40); // the 2 pi x 2 pi cell at square pixels
    expect_exact(seam(dir, "cmm.yaml", 2 * pi, 2 * pi, 40, 40, tile, 0));
    const std::vector<std::string> f = {"--set", "renderer.precision=float", "--set", "renderer.width=64"};
    const fp::Image tile_f = render(dir, "cmm.yaml", {"--tile", f[0], f[1], f[2], f[3]}, "tile-f.png");
    expect_within_noise(seam(dir, "cmm.yaml", 2 * pi, 2 * pi, 64, 64, tile_f, 2.0f / 255, {f[0], f[1]}));
}

TEST(Tile, HexagonalGroupTilesWithoutSeam) {
    const std::string dir = scratch_dir("tile_hexagonal");
    write_file(dir + "/p3m1.yaml", p3m1);
    const fp::Image tile = render(dir, "p3m1.yaml", {"--tile"}, "tile.png");
    ASSERT_EQ(tile.width, 32);
    ASSERT_EQ(tile.height, 55); // 2 pi x 2 pi sqrt 3: round(32 sqrt 3) = round(55.43)
    const double h = 2 * pi * std::numbers::sqrt3;
    expect_exact(seam(dir, "p3m1.yaml", 2 * pi, h, 32, 55, tile, 0));
    const std::vector<std::string> f = {"--set", "renderer.precision=float", "--set", "renderer.width=48"};
    const fp::Image tile_f = render(dir, "p3m1.yaml", {"--tile", f[0], f[1], f[2], f[3]}, "tile-f.png");
    ASSERT_EQ(tile_f.height, 83); // round(48 sqrt 3) = round(83.14)
    expect_within_noise(seam(dir, "p3m1.yaml", 2 * pi, h, 48, 83, tile_f, 2.0f / 255, {f[0], f[1]}));
}

// The comparison sees a seam: the hexagonal pattern sampled as a tile of the square cell
// 2 pi x 2 pi (the pixel centres (i + 1/2) 2 pi / W from -pi: the classic mistake), which is a
// period across but not up. The quadrant of its own points agrees, the one a period right too,
// the two a square period up do not.
TEST(Tile, SeamTestSeesAWrongTile) {
    const std::string dir = scratch_dir("tile_wrong");
    write_file(dir + "/p3m1.yaml", p3m1);
    const double d = 2 * pi / 32;
    const fp::Image wrong = render(dir, "p3m1.yaml",
                                   {"--set", "renderer.area=[" + real(-pi + d / 2) + ", " + real(pi - d / 2) +
                                                 ", " + real(-pi + d / 2) + ", " + real(pi - d / 2) + "]"},
                                   "wrong.png");
    const Seam s = seam(dir, "p3m1.yaml", 2 * pi, 2 * pi, 32, 32, wrong, 2.0f / 255);
    std::printf("mismatch of the wrong tile: untranslated %.4f, translated %.4f %.4f %.4f\n", s.untranslated,
                s.translated[0], s.translated[1], s.translated[2]);
    EXPECT_EQ(s.untranslated, 0);
    EXPECT_EQ(s.translated[0], 0); // one period right: 2 pi is a period
    EXPECT_GT(s.translated[1], 0.2);
    EXPECT_GT(s.translated[2], 0.2);
}

// --repeat 2x3: the tile's pixels, 2 across and 3 down; the recipe renders the tile.
TEST(Tile, RepeatWritesCopies) {
    const std::string dir = scratch_dir("tile_repeat");
    write_file(dir + "/p3m1.yaml", p3m1);
    const fp::Image tile = render(dir, "p3m1.yaml", {"--tile"}, "tile.png");
    const fp::Image rep = render(dir, "p3m1.yaml", {"--tile", "--repeat", "2x3"}, "rep.png");
    ASSERT_EQ(rep.width, 2 * tile.width);
    ASSERT_EQ(rep.height, 3 * tile.height);
    for (int j = 0; j < rep.height; ++j)
        for (int i = 0; i < rep.width; ++i)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(rep.pixels[(std::size_t(j) * rep.width + i) * 3 + c],
                          tile.pixels[(std::size_t(j % tile.height) * tile.width + i % tile.width) * 3 + c]);
    const auto r = run_cli({"render", "--quiet", dir + "/rep.png", "-o", dir + "/again.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(read_file(dir + "/again.png"), read_file(dir + "/tile.png"));
}

TEST(Tile, SameBytesOnAnyThreadCount) {
    const std::string dir = scratch_dir("tile_threads");
    write_file(dir + "/p3m1.yaml", p3m1);
    for (const char* t : {"1", "3"}) {
        const auto r = run_cli({"render", "--quiet", dir + "/p3m1.yaml", "--tile", "--threads", t, "-o",
                                dir + "/t" + t + ".png"});
        ASSERT_EQ(r.rc, 0) << r.err;
    }
    EXPECT_EQ(read_file(dir + "/t1.png"), read_file(dir + "/t3.png"));
}

// Big-endian and little-endian readers for the metadata below.
std::uint32_t be32(const std::string& s, std::size_t at) {
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v = v << 8 | std::uint8_t(s[at + k]);
    return v;
}
std::uint32_t le(const std::string& s, std::size_t at, int n) {
    std::uint32_t v = 0;
    for (int k = n - 1; k >= 0; --k) v = v << 8 | std::uint8_t(s[at + k]);
    return v;
}

// A little-endian TIFF's first IFD entry `tag`: its value (SHORT / LONG), or for RATIONAL
// numerator / denominator. -1 when absent.
double tiff_tag(const std::string& f, unsigned tag) {
    EXPECT_EQ(f.substr(0, 4), std::string("II*\0", 4));
    const std::uint32_t ifd = le(f, 4, 4);
    const unsigned n = le(f, ifd, 2);
    for (unsigned e = 0; e < n; ++e) {
        const std::size_t at = ifd + 2 + 12 * e;
        if (le(f, at, 2) != tag) continue;
        const unsigned type = le(f, at + 2, 2);
        if (type == 3 && le(f, at + 4, 4) > 2) return le(f, le(f, at + 8, 4), 2); // the first of several
        if (type == 3) return le(f, at + 8, 2);
        if (type == 4) return le(f, at + 8, 4);
        if (type == 5) {
            const std::uint32_t off = le(f, at + 8, 4);
            return double(le(f, off, 4)) / double(le(f, off + 4, 4));
        }
        ADD_FAILURE() << "tag " << tag << " of type " << type;
    }
    return -1;
}

TEST(Tile, DpiInTiffAndPng) {
    const std::string dir = scratch_dir("tile_dpi");
    write_file(dir + "/cmm.yaml", cmm);
    // A 16-bit TIFF for print at 300 dpi.
    auto r = run_cli({"render", "--quiet", dir + "/cmm.yaml", "--tile", "--dpi", "300", "--set",
                      "output.bit_depth=16", "-o", dir + "/tile.tif"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const std::string tif = read_file(dir + "/tile.tif");
    EXPECT_EQ(tiff_tag(tif, 282), 300); // XResolution
    EXPECT_EQ(tiff_tag(tif, 283), 300); // YResolution
    EXPECT_EQ(tiff_tag(tif, 296), 2);   // ResolutionUnit: inch
    EXPECT_EQ(tiff_tag(tif, 258), 16);  // BitsPerSample
    EXPECT_EQ(tiff_tag(tif, 256), 40);  // ImageWidth

    // PNG: pHYs in pixels per metre; --print-size with --dpi sets the pixels: 2 cm at 50.8 dpi
    // = 40 pixels.
    r = run_cli({"render", "--quiet", dir + "/cmm.yaml", "--tile", "--dpi", "50.8", "--print-size", "2cm",
                 "-o", dir + "/tile.png", "--set", "renderer.width=7"});
    ASSERT_EQ(r.rc, 0) << r.err;
    std::string png = read_file(dir + "/tile.png");
    std::size_t at = png.find("pHYs");
    ASSERT_NE(at, std::string::npos);
    EXPECT_EQ(be32(png, at + 4), 2000u); // 50.8 dpi = 2000 pixels per metre
    EXPECT_EQ(be32(png, at + 8), 2000u);
    EXPECT_EQ(png[at + 12], 1); // unit: metre
    EXPECT_EQ(be32(png, png.find("IHDR") + 4), 40u);

    // --print-size alone: the resolution from the pixels, 40 pixels over 2 in = 20 dpi.
    r = run_cli(
        {"render", "--quiet", dir + "/cmm.yaml", "--tile", "--print-size", "2in", "-o", dir + "/p.tif"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(tiff_tag(read_file(dir + "/p.tif"), 282), 20);
}

TEST(Tile, RefusedWithOneLine) {
    const std::string dir = scratch_dir("tile_refused");
    const auto one_line = [&](std::vector<std::string> args, const std::string& expected) {
        const auto r = run_cli(args);
        EXPECT_EQ(r.rc, 2);
        EXPECT_EQ(r.err, expected + "\n");
    };
    // A renderer without periodic patterns.
    one_line({"render", "--quiet", fp::test::source_dir() + "/configs/inversion/fig4a.yaml", "--tile", "-o",
              dir + "/x.png"},
             "--tile: the chaos-game renderer draws no periodic pattern; only orbit-trap renders one period "
             "(with a wallpaper mapping)");
    // A map without periods.
    write_file(dir + "/gm.yaml", R"(renderer:
  type: orbit-trap
  width: 16
  height: 16
  mapping: {type: gumowski-mira}
  traps: {type: circles, preset: fig-3b}
)");
    one_line({"render", "--quiet", dir + "/gm.yaml", "--tile", "-o", dir + "/x.png"},
             "--tile: the mapping is not periodic, so its pattern has no tile "
             "(the wallpaper maps are)");
    // Not the Picard iteration.
    write_file(dir + "/s.yaml",
               fp::test::replace_once(cmm, "  samples: 4\n",
                                      "  samples: 4\n  iteration: {type: s-iteration, numbers: "
                                      "{type: complex}, alpha: [1.1, 0], beta: [1.1, 0]}\n"));
    one_line({"render", "--quiet", dir + "/s.yaml", "--tile", "-o", dir + "/x.png"},
             "--tile: the pattern is periodic only under the Picard "
             "iteration: a step of this iteration also uses the point itself, so a translation by a period "
             "does not cancel");
    one_line(
        {"render", "--quiet", dir + "/s.yaml", "--print-size", "30", "-o", dir + "/x.png"},
        "--print-size: expected WIDTH or WIDTHxHEIGHT, each a positive number and a unit (mm, cm or in), "
        "as 30cm or 30cmx20cm, got '30'");
    one_line({"render", "--quiet", dir + "/s.yaml", "--repeat", "3x3", "-o", dir + "/x.png"},
             "--repeat: repeats a tile: give --tile too");
    one_line({"render", "--quiet", dir + "/s.yaml", "--tile", "--repeat", "3", "-o", dir + "/x.png"},
             "--repeat: expected NxM, copies across and down (1 to 16 each), as 3x3, got '3'");
    write_file(dir + "/c.yaml", cmm);
    one_line({"render", "--quiet", dir + "/c.yaml", "--tile", "--vary", "renderer.samples=1,4", "-o",
              dir + "/x.png"},
             "--tile, --repeat, --dpi and --print-size make one image: not with --vary");
    one_line({"render", "--quiet", dir + "/c.yaml", "--tile", "--repeat", "16x2", "--set",
              "renderer.width=5000", "-o", dir + "/x.png"},
             "--repeat 16x2: the 5000x5000 tile repeated would be wider or taller than 65536 pixels");
    // A hexagonal tile is sqrt(3) times as tall as wide: too tall, said as such (no --repeat given).
    write_file(dir + "/h.yaml", p3m1);
    one_line({"render", "--quiet", dir + "/h.yaml", "--tile", "--set", "renderer.width=40000", "-o",
              dir + "/x.png"},
             "--tile: the tile would be 40000x69282 pixels, taller than 65536: give a smaller width");
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.png"));
}

// --print-size with a width only, without --tile: the height follows in proportion, so the
// pixels keep their shape (a 40 x 20 render printed 4 cm wide at 50.8 dpi: 80 x 40).
TEST(Tile, PrintWidthKeepsTheAspect) {
    const std::string dir = scratch_dir("tile_print_aspect");
    write_file(dir + "/c.yaml", fp::test::replace_once(cmm, "  height: 40\n", "  height: 20\n"));
    const auto r = run_cli(
        {"render", "--quiet", dir + "/c.yaml", "--dpi", "50.8", "--print-size", "4cm", "-o", dir + "/p.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const std::string png = read_file(dir + "/p.png");
    const std::size_t at = png.find("IHDR");
    EXPECT_EQ(be32(png, at + 4), 80u);
    EXPECT_EQ(be32(png, at + 8), 40u);
}

// `fixpoint symmetry` cannot place a tile by its recipe's area: it says so.
TEST(Tile, SymmetryRefusesATile) {
    const std::string dir = scratch_dir("tile_symmetry");
    write_file(dir + "/c.yaml", cmm);
    ASSERT_EQ(run_cli({"render", "--quiet", dir + "/c.yaml", "--tile", "-o", dir + "/t.png"}).rc, 0);
    const auto r = run_cli({"symmetry", dir + "/t.png"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, dir + "/t.png: a tile (render --tile) shows one period, not its recipe's area; render "
                           "the pattern without --tile to measure it\n");
}

} // namespace
