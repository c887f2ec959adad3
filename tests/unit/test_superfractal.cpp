// The superfractal renderer (paper 03, Sec. III): Barnsley's V-variable algorithm with buffers.
#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include "cli.hpp"
#include "picture.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <string>
#include <vector>

namespace {

fp::host::Host& host() {
    static fp::host::Host h;
    return h;
}

// The IFSs F and G of paper 03, eq. (2), as affine coefficients [a, b, c, d, e, f].
const std::string f1 = "{type: affine, coefficients: [0.5, 0.375, 0.5, -0.375, -0.0625, 0.5625]}";
const std::string f2 = "{type: affine, coefficients: [0.5, -0.375, -0.5, -0.375, 0.5625, 1.0625]}";
const std::string g1 = "{type: affine, coefficients: [0.5, 0.375, -0.5, 0.375, -0.0625, 0.4375], ifs: 1}";
const std::string g2 = "{type: affine, coefficients: [0.5, -0.375, 0.5, 0.375, 0.5625, -0.0625], ifs: 1}";
const std::string g1_alone = "{type: affine, coefficients: [0.5, 0.375, -0.5, 0.375, -0.0625, 0.4375]}";
const std::string g2_alone = "{type: affine, coefficients: [0.5, -0.375, 0.5, 0.375, 0.5625, -0.0625]}";
const std::string fg = "maps: [" + f1 + ", " + f2 + ", " + g1 + ", " + g2 + "]";

struct Render {
    fp::Image img;
    fp::RenderStats stats;
    std::uint64_t progress = 0, work_units = 0;
};

Render render(const std::string& yaml, unsigned threads = 2) {
    auto r = host().make<fp::Renderer>(yaml);
    fp::host::Runtime rt(threads, nullptr);
    Render out;
    out.img = r->render(rt, out.stats);
    out.progress = rt.done();
    out.work_units = r->work_units();
    return out;
}

// The error message without its "<string>:line:col: " prefix (the column depends on the YAML).
std::string error_of(const std::string& yaml) {
    try {
        host().make<fp::Renderer>(yaml);
    } catch (const fp::InputError& e) {
        const std::string m = e.what();
        const auto at = m.find(": ");
        return m.rfind("<string>:1:", 0) == 0 && at != std::string::npos ? m.substr(at + 2) : m;
    }
    return "(no error)";
}

// Lit pixels (any channel above 0; the background is black).
std::vector<char> lit(const fp::Image& img) {
    std::vector<char> out(std::size_t(img.width) * std::size_t(img.height), 0);
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = img.pixels[3 * i] > 0 || img.pixels[3 * i + 1] > 0 || img.pixels[3 * i + 2] > 0;
    return out;
}

std::size_t count(const std::vector<char>& v) {
    std::size_t n = 0;
    for (char c : v) n += c != 0;
    return n;
}

// Pixels lit in `a` with no lit pixel of `b` among themselves and their 8 neighbours.
std::size_t unmatched(const std::vector<char>& a, const std::vector<char>& b, int w, int h) {
    std::size_t n = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (!a[std::size_t(y) * std::size_t(w) + std::size_t(x)]) continue;
            bool near = false;
            for (int dy = -1; dy <= 1 && !near; ++dy)
                for (int dx = -1; dx <= 1 && !near; ++dx) {
                    const int u = x + dx, v = y + dy;
                    near = u >= 0 && v >= 0 && u < w && v < h &&
                           b[std::size_t(v) * std::size_t(w) + std::size_t(u)];
                }
            n += !near;
        }
    return n;
}

fp::Vec2 apply(const std::string& map, fp::Vec2 p) {
    auto t = host().make<fp::Transform>(map);
    double x = p.x, y = p.y;
    t->apply(fp::Points<double>{&x, &y, 1}, nullptr);
    return {x, y};
}

TEST(Superfractal, EquationTwoJoinsItsCurves) {
    // The checks behind configs/gumowski-mira/fig2-F.yaml's reading of eq. (2): f1, g1 fix
    // A = (1/4, 1/2), f2, g2 fix B = (3/4, 1/2), and the two halves of each attractor meet,
    // F's at (1/2, 3/4) above, G's at (1/2, 1/4) below (exact in binary fractions).
    const fp::Vec2 A{0.25, 0.5}, B{0.75, 0.5};
    EXPECT_EQ(apply(f1, A), A);
    EXPECT_EQ(apply(f2, B), B);
    EXPECT_EQ(apply(g1_alone, A), A);
    EXPECT_EQ(apply(g2_alone, B), B);
    EXPECT_EQ(apply(f1, B), (fp::Vec2{0.5, 0.75}));
    EXPECT_EQ(apply(f2, A), (fp::Vec2{0.5, 0.75}));
    EXPECT_EQ(apply(g1_alone, B), (fp::Vec2{0.5, 0.25}));
    EXPECT_EQ(apply(g2_alone, A), (fp::Vec2{0.5, 0.25}));
}

const std::string sf_head = "{type: superfractal, width: 256, height: 256, view: [0, 1, 0, 1], ";

// Several chunks per buffer (16384 points each), three buffers, an IFS of three maps (shares of
// unequal size), bad values to repair (the 1e200 map), coloured by `colourer`.
std::string three_buffers(const std::string& colourer) {
    const std::string maps = "maps: [" + f1 + ", " + f2 + ", " + g1 + ", " + g2 +
                             ", {type: affine, coefficients: [0.3, 0, 0, 0.3, 0.1, 0.1], ifs: 1}, "
                             "{type: affine, coefficients: [1e200, 0, 0, 1e200, 0, 0], ifs: 2}, " +
                             "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0.5], ifs: 2}]";
    return sf_head +
           "points_per_buffer: 40001, buffers: 3, child: 2, steps: 25, colourer: {type: " + colourer + "}, " +
           maps + "}";
}

TEST(Superfractal, OneIfsOneBufferReachesTheAttractor) {
    // With one IFS and one buffer the buffer algorithm is the deterministic IFS algorithm: its
    // points lie on the attractor that the chaos game draws, within a pixel, and fill it.
    for (const std::string& maps : {"[" + f1 + ", " + f2 + "]", "[" + g1_alone + ", " + g2_alone + "]"}) {
        const auto sf = render(sf_head + "buffers: 1, points_per_buffer: 200000, maps: " + maps + "}");
        const auto cg =
            render("{type: chaos-game, width: 256, height: 256, view: [0, 1, 0, 1], points: 4000000, "
                   "skip: 60, colourer: {type: map-colour}, maps: " +
                   maps + "}");
        const auto a = lit(sf.img), b = lit(cg.img);
        ASSERT_GT(count(a), 1000u) << maps;
        EXPECT_EQ(unmatched(a, b, 256, 256), 0u) << maps;             // on the attractor
        EXPECT_LT(unmatched(b, a, 256, 256), count(b) / 100) << maps; // and all of it
        EXPECT_EQ(sf.stats.samples, 200000u);
        EXPECT_EQ(sf.stats.drawn, 200000u);
        EXPECT_EQ(sf.stats.bad_values, 0u);
    }
}

TEST(Superfractal, ForgetsItsInitialSets) {
    // The same choices from start sets far apart give the same child, within a pixel: one IFS
    // (the attractor) and the two-buffer superfractal of F and G alike.
    for (const std::string& body : {"buffers: 1, maps: [" + f1 + ", " + f2 + "]", "buffers: 2, " + fg}) {
        const auto near = render(sf_head + "points_per_buffer: 50000, " + body + "}");
        const auto far =
            render(sf_head + "points_per_buffer: 50000, start_box: [-30, -20, 40, 41], " + body + "}");
        const auto a = lit(near.img), b = lit(far.img);
        ASSERT_GT(count(a), 1000u);
        EXPECT_EQ(unmatched(a, b, 256, 256), 0u) << body;
        EXPECT_EQ(unmatched(b, a, 256, 256), 0u) << body;
        // Nearly the same pixels, not only nearby ones.
        std::size_t differ = 0;
        for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
        EXPECT_LT(differ, count(a) / 50) << body;
    }
}

TEST(Superfractal, SameImageOnOneAndManyThreads) {
    // Several chunks per buffer (16384 points each), three buffers, an IFS of three maps (shares
    // of unequal size), flame colours, and bad values repaired.
    const std::string yaml = three_buffers("flame");
    const auto one = render(yaml, 1), two = render(yaml, 2), three = render(yaml, 3);
    ASSERT_GT(count(lit(one.img)), 100u);
    EXPECT_TRUE(one.img.pixels == two.img.pixels);
    EXPECT_TRUE(one.img.pixels == three.img.pixels);
    EXPECT_GT(one.stats.bad_values, 0u);
    EXPECT_EQ(one.stats.bad_values, three.stats.bad_values);
    EXPECT_EQ(one.stats.drawn, three.stats.drawn);
    EXPECT_EQ(one.progress, one.work_units);
    EXPECT_EQ(three.progress, three.work_units);
}

TEST(Superfractal, AHitCountColourerGetsHitCountsAlone) {
    // density reads hit counts alone (Colourer::reads_hits_only): the child is plotted into a
    // histogram of hit counts, 8 bytes a bin where flame's colour sums take 32. The same points
    // land in the same bins: both light the same pixels.
    const std::string body = "points_per_buffer: 30000, steps: 20, " + fg + ", colourer: ";
    auto r_density = host().make<fp::Renderer>(sf_head + body + "{type: density}}");
    auto r_flame = host().make<fp::Renderer>(sf_head + body + "{type: flame}}");
    // The difference: 24 bytes a bin, and flame's colour of each point (3 floats) in two
    // generations of 2 buffers of 30000 points.
    EXPECT_EQ(r_flame->memory_bytes(1) - r_density->memory_bytes(1),
              256u * 256u * (sizeof(fp::HistBin) - sizeof(std::uint64_t)) + 2u * 2u * 30000u * 12u);
    const auto density = render(sf_head + body + "{type: density}}");
    const auto flame = render(sf_head + body + "{type: flame}}");
    ASSERT_GT(count(lit(density.img)), 1000u);
    EXPECT_TRUE(lit(density.img) == lit(flame.img));
    EXPECT_EQ(density.stats.drawn, flame.stats.drawn);
}

TEST(Superfractal, BadValuesAreCountedAndReplaced) {
    // A map that sends every point to infinity in two steps: half of each new buffer goes bad
    // and is replaced by copies of finite points; an IFS of that map alone empties its buffer,
    // which is redrawn from the start box. Never a crash, never an empty image.
    const std::string blow = "{type: affine, coefficients: [1e200, 0, 0, 1e200, 0, 0]}";
    const auto half =
        render(sf_head + "buffers: 1, points_per_buffer: 10000, maps: [" + blow + ", " + f1 + "]}");
    EXPECT_GT(half.stats.bad_values, 0u);
    EXPECT_EQ(half.stats.restarts, 0u);
    EXPECT_GT(half.stats.drawn, 0u);
    const auto all =
        render(sf_head + "buffers: 1, points_per_buffer: 10000, steps: 5, maps: [" + blow + "]}");
    EXPECT_GT(all.stats.bad_values, 0u);
    EXPECT_GT(all.stats.restarts, 0u);
    EXPECT_EQ(all.stats.samples, 10000u);
}

TEST(Superfractal, CollectionsAreDeterministicPerSeed) {
    const std::string base = sf_head + "points_per_buffer: 30000, " + fg;
    const auto a = render(base + ", seed: 7}");
    const auto b = render(base + ", seed: 7}", 3);
    const auto c = render(base + ", seed: 8}");
    const auto d = render(base + ", seed: 7, child: 1}");
    EXPECT_TRUE(a.img.pixels == b.img.pixels);
    EXPECT_FALSE(a.img.pixels == c.img.pixels);
    EXPECT_FALSE(a.img.pixels == d.img.pixels);
    // Different seeds give different children, not a few different pixels.
    const auto la = lit(a.img), lc = lit(c.img);
    EXPECT_GT(unmatched(la, lc, 256, 256), count(la) / 10);
}

TEST(Superfractal, AnIfsOfProbabilityZeroIsNeverChosen) {
    // The draws are the same whatever the probabilities, so F with G at probability 0 gives the
    // same bytes as F alone.
    const auto with_g = render(sf_head + "points_per_buffer: 20000, ifs_probabilities: [1, 0], " + fg + "}");
    const auto alone = render(sf_head + "points_per_buffer: 20000, maps: [" + f1 + ", " + f2 + "]}");
    EXPECT_TRUE(with_g.img.pixels == alone.img.pixels);
}

TEST(Superfractal, ProbabilitiesAndCountsAreValidated) {
    const std::string h = "{type: superfractal, " + fg;
    EXPECT_EQ(error_of(h + ", ifs_probabilities: [0.5, 0.4]}"),
              "renderer.ifs_probabilities: the probabilities sum to 0.9, not 1: give probabilities "
              "that sum to 1 (they are not normalised)");
    EXPECT_EQ(error_of(h + ", ifs_probabilities: [0.5, 0.25, 0.25]}"),
              "renderer.ifs_probabilities: expected 2 probabilities (one per IFS), got 3");
    EXPECT_EQ(error_of(h + ", ifs_probabilities: [1.5, -0.5]}"),
              "renderer.ifs_probabilities[1]: must be >= 0, got -0.5");
    EXPECT_EQ(error_of(h + ", buffers: 3, buffer_probabilities: [0.5, 0.5]}"),
              "renderer.buffer_probabilities: expected 3 probabilities (one per buffer), got 2");
    EXPECT_EQ(error_of(h + ", buffer_probabilities: [0.6, 0.6]}"),
              "renderer.buffer_probabilities: the probabilities sum to 1.2, not 1: give "
              "probabilities that sum to 1 (they are not normalised)");
    EXPECT_EQ(error_of(h + ", buffers: 0}"), "renderer.buffers: must be in [1, 65536], got 0");
    // flame's last and set-colour modes need the last colour of a pixel, which has no meaning here.
    for (const char* mode : {"last", "set-colour"})
        EXPECT_EQ(
            error_of(h + ", colourer: {type: flame, mode: " + mode + "}}"),
            "renderer.colourer: the superfractal renderer keeps the mean colour of a pixel's points: this "
            "colourer's mode needs the last one (chaos-game keeps it)");
    EXPECT_EQ(error_of(h + ", child: 2}"),
              "renderer.child: child 2 does not exist: there are 2 buffers, numbered from 0");
    EXPECT_EQ(error_of("{type: superfractal, maps: []}"), "renderer.maps: the list of transforms is empty");
    EXPECT_EQ(error_of("{type: superfractal, maps: [" + f1 + ", " + g1 + ", " + f2 +
                       ", {type: affine, coefficients: [1, 0, 0, 1, 0, 0], ifs: 3}]}"),
              "renderer.maps: IFS 2 has no maps: the maps' ifs indices must cover 0 to 3 (each IFS "
              "needs at least one map)");
    // Sums within 1e-6 of 1 are accepted (decimal thirds).
    EXPECT_EQ(error_of("{type: superfractal, maps: [" + f1 + ", " + g1 + ", " + f2 +
                       ", {type: affine, coefficients: [1, 0, 0, 1, 0, 0], ifs: 2}], "
                       "ifs_probabilities: [0.3333333, 0.3333333, 0.3333334]}"),
              "(no error)");
}

TEST(Superfractal, BadProbabilitiesStopTheCliWithOneLine) {
    const std::string dir = fp::test::scratch_dir("superfractal-bad");
    fp::test::write_file(dir + "/bad.yaml",
                         "renderer:\n  type: superfractal\n  " + fg + "\n  ifs_probabilities: [0.5, 0.6]\n");
    const auto r = fp::test::run_cli({"render", dir + "/bad.yaml", "-o", dir + "/bad.png"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, dir + "/bad.yaml:4:22: renderer.ifs_probabilities: the probabilities sum to 1.1, not 1: "
                           "give probabilities that sum to 1 (they are not normalised)\n");
}

// ---------------------------------------------------------------- colour stealing

TEST(Superfractal, StolenColoursFollowTheAddresses) {
    // One IFS, one buffer of 4 points, 2 steps, every point starting at (1/2, 1/2) in the
    // plane and in the picture square. f0 = (x/2, y), f1 = (x/2 + 1/2, y); the colour IFS
    // g0 = (u/2, v/2 + 1/2), g1 = (u/2 + 1/2, v/2). The shares (share j takes source points
    // j, j + 2 of map j) give point 0 the address f0 f0, point 1 f0 f1, point 2 f1 f0, point 3
    // f1 f1: x = 1/8, 3/8, 5/8, 7/8, pixels 0 to 3 of a 4 x 1 image; and in the picture the
    // same addresses: g0 g0 (1/2, 1/2) = (1/8, 7/8), g0 g1 = g0 (3/4, 1/4) = (3/8, 5/8),
    // g1 g0 = (5/8, 3/8), g1 g1 = (7/8, 1/8): cells (col, row from the top) (0, 0), (1, 1), (2,
    // 2), (3, 3) of a 4 x 4 picture, its diagonal. Point 1 was made by f0 from a parent made
    // by f1: it shows the colour g0 g1, inherited from its parent's g1.
    const std::string dir = fp::test::scratch_dir("superfractal-steal-addresses");
    const std::string pic = fp::test::write_picture(dir, 4, 4);
    const std::string yaml =
        "{type: superfractal, width: 4, height: 1, view: [0, 1, 0, 1], buffers: 1, points_per_buffer: 4, "
        "steps: 2, start_box: [0.5, 0.5, 0.5, 0.5], picture: \"" +
        pic +
        "\", colourer: {type: map-colour, density: flat}, maps: ["
        "{type: affine, coefficients: [0.5, 0, 0, 1, 0, 0], colour_map: [0.5, 0, 0, 0.5, 0, 0.5]}, "
        "{type: affine, coefficients: [0.5, 0, 0, 1, 0.5, 0], colour_map: [0.5, 0, 0, 0.5, 0.5, 0]}]}";
    const auto r = render(yaml, 1);
    ASSERT_EQ(r.stats.drawn, 4u);
    EXPECT_EQ(fp::test::pixel8(r.img, 0), (std::vector<int>{10, 10, 255}));
    EXPECT_EQ(fp::test::pixel8(r.img, 1), (std::vector<int>{30, 30, 255}));
    EXPECT_EQ(fp::test::pixel8(r.img, 2), (std::vector<int>{50, 50, 255}));
    EXPECT_EQ(fp::test::pixel8(r.img, 3), (std::vector<int>{70, 70, 255}));
    // One step: points 0, 1 by f0 (x = 1/4: pixel 1), points 2, 3 by f1 (x = 3/4: pixel 3);
    // g0 (1/2, 1/2) = (1/4, 3/4): cell (1, 1); g1: (3/4, 1/4): cell (3, 3). Pixels 0 and 2 empty.
    const auto one = render(fp::test::replace_once(yaml, "steps: 2", "steps: 1"), 1);
    EXPECT_EQ(fp::test::pixel8(one.img, 0), (std::vector<int>{0, 0, 0}));
    EXPECT_EQ(fp::test::pixel8(one.img, 1), (std::vector<int>{30, 30, 255}));
    EXPECT_EQ(fp::test::pixel8(one.img, 3), (std::vector<int>{70, 70, 255}));
    // The built-in picture `hues` by the default colour maps ((u + t) / m, v): after one step
    // map 0's points are at (1/4, 1/2), column 128 and row 256 of its 512 x 512: v = 1 -
    // 256.5/512, value 0.45 + 0.55 v = 0.72446, saturation 1 - 0.45 v = 0.77544, hue sector 1
    // (6 * 128.5/512 = 1.50586, f = 0.50586): (value (1 - saturation f), value, value (1 -
    // saturation)) = (112.27, 184.74, 41.48) / 255.
    const auto hues = render(
        "{type: superfractal, width: 4, height: 1, view: [0, 1, 0, 1], buffers: 1, points_per_buffer: 4, "
        "steps: 1, start_box: [0.5, 0.5, 0.5, 0.5], picture: hues, colourer: {type: map-colour, density: "
        "flat}, maps: [{type: affine, coefficients: [0.5, 0, 0, 1, 0, 0]}, "
        "{type: affine, coefficients: [0.5, 0, 0, 1, 0.5, 0]}]}",
        1);
    EXPECT_EQ(fp::test::pixel8(hues.img, 1), (std::vector<int>{112, 185, 41}));
}

TEST(Superfractal, StealingKeepsTheGeometryAndTheBytesOnAnyThreads) {
    // The same child with and without colour stealing (the colour IFS draws nothing from the
    // RNG), and the same bytes on 1, 2 and 3 threads: several chunks per buffer, three buffers,
    // an IFS of three maps, bad values repaired (their colour points copied with them).
    const std::string plain = three_buffers("map-colour");
    const std::string yaml = fp::test::replace_once(
        fp::test::replace_once(plain, "colourer:", "picture: hues, colourer:"), "0.1, 0.1], ifs: 1}",
        "0.1, 0.1], ifs: 1, colour_map: [0, 0.5, 0.5, 0, 0.25, 0.25]}");
    const auto one = render(yaml, 1), two = render(yaml, 2), three = render(yaml, 3);
    ASSERT_GT(count(lit(one.img)), 100u);
    EXPECT_TRUE(one.img.pixels == two.img.pixels);
    EXPECT_TRUE(one.img.pixels == three.img.pixels);
    EXPECT_GT(one.stats.bad_values, 0u);
    const auto without = render(plain, 2);
    EXPECT_TRUE(lit(without.img) == lit(one.img));
    EXPECT_FALSE(without.img.pixels == one.img.pixels);
    EXPECT_EQ(one.progress, one.work_units);
}

TEST(Superfractal, ColourStealingIsValidated) {
    const std::string dir = fp::test::scratch_dir("superfractal-steal-errors");
    fp::test::write_file(dir + "/not.png", "not a picture\n");
    const std::string h = "{type: superfractal, " + fg;
    EXPECT_EQ(error_of(h + ", picture: " + dir + "/none.png}"),
              "renderer.picture: cannot read the picture \"" + dir +
                  "/none.png\": no such file (give a PNG file, relative to the config, or hues)");
    EXPECT_EQ(error_of(h + ", picture: " + dir + "/not.png}"),
              "renderer.picture: cannot read the picture \"" + dir +
                  "/not.png\": it is not a PNG file (give a PNG file, relative to the config, or hues)");
    EXPECT_EQ(error_of(h + ", picture: hues, colourer: {type: density}}"),
              "renderer.picture: colour stealing needs a colourer that shows the points' colours (map-colour "
              "or flame); this one shows only where they fall");
    EXPECT_EQ(
        error_of("{type: superfractal, maps: [" + f1 +
                 ", {type: affine, coefficients: [1, 0, 0, 1, 0, 0], colour_map: [1, 0, 0, 1, 0, 0]}]}"),
        "renderer.maps: maps[1]: a colour_map is used only by colour stealing: give the renderer a "
        "picture (hues, or a PNG file)");
    EXPECT_EQ(
        error_of("{type: superfractal, picture: hues, maps: [{type: affine, coefficients: [1, 0, 0, 1, 0, "
                 "0], colour_map: [1, 0, 0, 1, 0]}]}"),
        "renderer.maps[0].colour_map: expected 6 numbers, got 5");
}

TEST(Superfractal, BadPictureStopsTheCliWithOneLine) {
    const std::string line =
        fp::test::run_bad_input("superfractal-bad-picture",
                                "renderer:\n  type: superfractal\n  " + fg + "\n  picture: missing.png\n");
    EXPECT_EQ(line, "bad.yaml:4:12: renderer.picture: cannot read the picture \"missing.png\": no such file "
                    "(give a PNG file, relative to the config, or hues)");
}

TEST(Superfractal, Cancels) {
    auto r = host().make<fp::Renderer>(sf_head + fg + "}");
    std::atomic<bool> stop{true};
    fp::host::Runtime rt(2, &stop);
    fp::RenderStats st;
    EXPECT_THROW(r->render(rt, st), fp::Cancelled);
}

} // namespace
