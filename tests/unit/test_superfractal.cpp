// The superfractal renderer (paper 03, Sec. III): Barnsley's V-variable algorithm with buffers.
#include <fixpoint/host/host.hpp>
#include <fixpoint/host/runtime.hpp>

#include "cli.hpp"

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
    const std::string maps = "maps: [" + f1 + ", " + f2 + ", " + g1 + ", " + g2 +
                             ", {type: affine, coefficients: [0.3, 0, 0, 0.3, 0.1, 0.1], ifs: 1}, "
                             "{type: affine, coefficients: [1e200, 0, 0, 1e200, 0, 0], ifs: 2}, " +
                             "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0.5], ifs: 2}]";
    const std::string yaml = sf_head +
                             "points_per_buffer: 40001, buffers: 3, child: 2, steps: 25, "
                             "colourer: {type: flame}, " +
                             maps + "}";
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

TEST(Superfractal, Cancels) {
    auto r = host().make<fp::Renderer>(sf_head + fg + "}");
    std::atomic<bool> stop{true};
    fp::host::Runtime rt(2, &stop);
    fp::RenderStats st;
    EXPECT_THROW(r->render(rt, st), fp::Cancelled);
}

} // namespace
