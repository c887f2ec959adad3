// `fixpoint explore`: the measures on made-up images with known values, and the search as a
// user runs it (deterministic for a seed on any thread count, the best beating the rest,
// exact error lines).
#include "cli.hpp"
#include "configs.hpp"

#include <fixpoint/host/tools/measures.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>

using namespace fp::test;
namespace fs = std::filesystem;
using namespace fp::host;

namespace {

fp::Image blank(int w, int h) {
    fp::Image img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    img.pixels.assign(std::size_t(w) * std::size_t(h) * 3, 0.0f);
    return img;
}

void set_grey(fp::Image& img, int x, int y, float v) {
    for (int c = 0; c < 3; ++c)
        img.pixels[(std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 3 + c] = v;
}

const fp::Rgb black{0, 0, 0};

TEST(ExploreMeasures, FilledSquareHasDimensionTwo) {
    fp::Image img = blank(256, 256);
    for (int y = 64; y < 192; ++y)
        for (int x = 64; x < 192; ++x) set_grey(img, x, y, 1);
    EXPECT_NEAR(box_dimension(img, black), 2.0, 1e-9); // aligned to every box size: exact
    // Not aligned to the grid (squares of 100 and 150 pixels at (37, 41)): within 0.1, the
    // boxes on the edge ((L/s + 1)^2 of them) pulling it down.
    for (int side : {100, 150}) {
        fp::Image off = blank(256, 256);
        for (int y = 41; y < 41 + side; ++y)
            for (int x = 37; x < 37 + side; ++x) set_grey(off, x, y, 1);
        EXPECT_NEAR(box_dimension(off, black), 2.0, 0.1) << side;
    }
    EXPECT_NEAR(coverage(img, black), 0.25, 1e-12);
}

TEST(ExploreMeasures, LineHasDimensionOne) {
    fp::Image img = blank(256, 256);
    for (int x = 0; x < 256; ++x) set_grey(img, x, 100, 0.5f);
    EXPECT_NEAR(box_dimension(img, black), 1.0, 1e-9);
    // Not aligned to the grid (200 pixels from (37, 37)): within 0.1, across and along the
    // diagonal.
    fp::Image across = blank(256, 256), diag = blank(256, 256);
    for (int x = 0; x < 200; ++x) set_grey(across, x + 37, 100, 1), set_grey(diag, x + 37, x + 37, 1);
    EXPECT_NEAR(box_dimension(across, black), 1.0, 0.1);
    EXPECT_NEAR(box_dimension(diag, black), 1.0, 0.1);
    // A few scattered points (dust): dimension near 0.
    fp::Image dust = blank(256, 256);
    set_grey(dust, 3, 5, 1), set_grey(dust, 200, 17, 1), set_grey(dust, 90, 240, 1);
    EXPECT_NEAR(box_dimension(dust, black), 0.0, 1e-9);
    EXPECT_EQ(box_dimension(blank(64, 64), black), 0.0);
}

TEST(ExploreMeasures, CoverageAndEntropyByHand) {
    // 4 x 2 pixels: grey levels 0, 0, 0, 0, 1, 1, 0.5, 0.5 (255 and 128 of 255).
    fp::Image img = blank(4, 2);
    set_grey(img, 0, 1, 1), set_grey(img, 1, 1, 1), set_grey(img, 2, 1, 0.5f), set_grey(img, 3, 1, 0.5f);
    EXPECT_DOUBLE_EQ(coverage(img, black), 0.5);
    // p = 1/2, 1/4, 1/4: H = 0.5 + 0.5 + 0.5 = 1.5 bits.
    EXPECT_NEAR(grey_entropy(img), 1.5, 1e-12);
    // Against a white background every black pixel is lit.
    EXPECT_DOUBLE_EQ(coverage(img, fp::Rgb{1, 1, 1}), 0.75);
    // A pixel below half an 8-bit step is not lit; one above is.
    fp::Image faint = blank(2, 1);
    set_grey(faint, 0, 0, 0.4f / 255), set_grey(faint, 1, 0, 0.6f / 255);
    EXPECT_DOUBLE_EQ(coverage(faint, black), 0.5);
    EXPECT_DOUBLE_EQ(grey_entropy(blank(8, 8)), 0.0);
    // 256 pixels, one of each level: 8 bits.
    fp::Image ramp = blank(256, 1);
    for (int x = 0; x < 256; ++x) set_grey(ramp, x, 0, float(x) / 255);
    EXPECT_NEAR(grey_entropy(ramp), 8.0, 1e-12);
}

TEST(ExploreMeasures, ScoreMappings) {
    EXPECT_EQ(coverage_score(0.001), 0);
    EXPECT_NEAR(coverage_score(0.0063245553), 0.5, 1e-6); // half way in log between 0.2% and 2%
    EXPECT_EQ(coverage_score(0.3), 1);
    EXPECT_NEAR(coverage_score(0.8), 0.5, 1e-12);
    EXPECT_EQ(coverage_score(1), 0);
    EXPECT_NEAR(entropy_score(3), 0.5, 1e-12);
    EXPECT_EQ(entropy_score(7.5), 1);
    EXPECT_EQ(dimension_score(1.5), 1);
    EXPECT_NEAR(dimension_score(0.9), 0.5, 1e-12);
    EXPECT_NEAR(dimension_score(1.9), 0.5, 1e-12);
    EXPECT_EQ(dimension_score(2), 0);
    EXPECT_NEAR(lyapunov_score(0), 0.5, 1e-12);
    EXPECT_GT(lyapunov_score(0.3), 0.99);
    EXPECT_LT(lyapunov_score(-0.3), 0.01);
}

// Three circles and a star, inverted: radii drawn from 0.2 to 1.2 give anything from a few
// scattered points to a full gasket.
const std::string circles = chaos_game(
    {"width: 64", "height: 64", "view: [-1.6, 1.6, -1.6, 1.6]", "points: 40000", "chains: 16", "seed: 7"},
    three_circles("0.9"));

std::vector<std::string> explore_args(const std::string& dir, const std::string& out,
                                      std::vector<std::string> extra = {}, const std::string& seed = "5") {
    std::vector<std::string> a = {"explore",
                                  "--quiet",
                                  dir + "/cfg.yaml",
                                  "-o",
                                  dir + "/" + out,
                                  "--seed",
                                  seed,
                                  "--candidates",
                                  "10",
                                  "--keep",
                                  "3",
                                  "--draft-size",
                                  "48",
                                  "--draft-points",
                                  "20000",
                                  "--param",
                                  "renderer.maps[0].shape.radius=0.2..1.2",
                                  "--param",
                                  "renderer.maps[1].shape.radius=0.2..1.2"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

std::vector<std::map<std::string, std::string>> table(const std::string& path) { return read_tsv(path); }

TEST(Explore, SameSeedSameFilesOnAnyThreadCount) {
    const std::string dir = scratch_dir("explore_same");
    write_file(dir + "/cfg.yaml", circles);
    auto a = run_cli(explore_args(dir, "a", {"--threads", "1", "--generations", "1"}));
    ASSERT_EQ(a.rc, 0) << a.err;
    EXPECT_EQ(a.err, "");
    auto b = run_cli(explore_args(dir, "b", {"--threads", "2", "--generations", "1"}));
    ASSERT_EQ(b.rc, 0) << b.err;
    for (const std::string f :
         {"candidates.tsv", "sheet.png", "best-1.yaml", "best-1.png", "best-2.yaml", "best-3.png"})
        EXPECT_EQ(read_file(dir + "/a/" + f), read_file(dir + "/b/" + f)) << f;
    // The evolutionary phase ran: children of generation 1 are listed.
    bool child = false;
    for (const auto& r : table(dir + "/a/candidates.tsv")) child = child || r.at("generation") == "1";
    EXPECT_TRUE(child);
    // Another seed, another search.
    auto c = run_cli(explore_args(dir, "c", {}, "6"));
    ASSERT_EQ(c.rc, 0) << c.err;
    EXPECT_NE(read_file(dir + "/a/candidates.tsv"), read_file(dir + "/c/candidates.tsv"));
    // best-1.yaml is a config: rendering it gives best-1.png.
    auto r = run_cli({"render", "--quiet", dir + "/a/best-1.yaml", "-o", dir + "/again.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(read_file(dir + "/again.png"), read_file(dir + "/a/best-1.png"));
}

TEST(Explore, TheBestBeatsTheWorst) {
    const std::string dir = scratch_dir("explore_best");
    write_file(dir + "/cfg.yaml", circles);
    auto a = run_cli(explore_args(dir, "a"));
    ASSERT_EQ(a.rc, 0) << a.err;
    const auto rows = table(dir + "/a/candidates.tsv");
    ASSERT_EQ(rows.size(), 10u);
    const auto& top = rows.front();
    EXPECT_EQ(top.at("rank"), "1");
    // The top candidate beats, on every measure, the first random draw (id 0) and the last
    // ranked (on this config radii below 0.5 give dust, above 1 overlapping circles).
    for (const auto& other : rows) {
        if (other.at("id") != "0" && &other != &rows.back()) continue;
        EXPECT_NE(other.at("id"), top.at("id"));
        EXPECT_GT(std::stod(top.at("score")), std::stod(other.at("score")));
        for (const char* m : {"coverage_score", "entropy_score", "dimension_score", "lyapunov_score"})
            EXPECT_GT(std::stod(top.at(m)), std::stod(other.at(m))) << m << " against id " << other.at("id");
    }
    // Ranked by score.
    for (std::size_t i = 1; i < rows.size(); ++i)
        EXPECT_GE(std::stod(rows[i - 1].at("score")), std::stod(rows[i].at("score")));
    // The configs carry their scores and values.
    const std::string best = read_file(dir + "/a/best-1.yaml");
    EXPECT_NE(best.find("# rank 1 of 10 valid candidates"), std::string::npos) << best;
    EXPECT_NE(best.find("# renderer.maps[0].shape.radius=" + top.at("renderer.maps[0].shape.radius")),
              std::string::npos)
        << best;
    // The folder is not written over without --force.
    auto again = run_cli(explore_args(dir, "a"));
    EXPECT_EQ(again.rc, 2);
    EXPECT_EQ(again.err, "'" + dir + "/a/sheet.png' exists: add --force to replace it\n");
    auto forced = run_cli(explore_args(dir, "a", {"--force"}));
    EXPECT_EQ(forced.rc, 0) << forced.err;
}

TEST(Explore, RandomSearchesAPluginsParameters) {
    const std::string dir = scratch_dir("explore_random");
    write_file(dir + "/cfg.yaml", std::string(circles) + "output: {path: original.png}\n");
    const auto r = run_cli({"explore", "--quiet", dir + "/cfg.yaml", "-o", dir + "/out", "--random",
                            "renderer.maps[2].shape", "--random", "renderer", "--candidates", "6", "--keep",
                            "2", "--draft-size", "32", "--draft-points", "5000"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto rows = table(dir + "/out/candidates.tsv");
    ASSERT_EQ(rows.size(), 6u);
    for (const auto& row : rows) {
        // The circle's radius 0.9 over 0.45..1.35 (no upper end declared); the renderer's
        // set_line and set_fill over their declared ranges; its width, points, ... kept.
        const double radius = std::stod(row.at("renderer.maps[2].shape.radius"));
        EXPECT_GE(radius, 0.45);
        EXPECT_LE(radius, 1.35);
        const double fill = std::stod(row.at("renderer.set_fill"));
        EXPECT_GE(fill, 0);
        EXPECT_LE(fill, 1);
        EXPECT_EQ(row.count("renderer.width"), 0u);
        EXPECT_EQ(row.count("renderer.maps[2].shape.centre"), 0u); // a point: not searched
    }
    // The configs written do not name the original's output: rendered without -o, they do not
    // write over it.
    EXPECT_EQ(read_file(dir + "/out/best-1.yaml").find("original.png"), std::string::npos);
}

TEST(Explore, RandomSearchesVectorParametersComponentwise) {
    // Paper 04's S-iteration with vector alpha = [1.1, 0.5] and beta = [0.5, 0] (fig9a): each
    // component over v +- |v| / 2 (+- 0.5 around 0), written back as a vector, and each
    // candidate's config renders.
    const std::string dir = scratch_dir("explore_random_vectors");
    const auto r =
        run_cli({"explore", "--quiet", source_dir() + "/configs/orbit-trap/fig9a.yaml", "-o", dir + "/out",
                 "--random", "renderer.iteration", "--candidates", "4", "--keep", "1", "--draft-size", "16"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto rows = table(dir + "/out/candidates.tsv");
    ASSERT_EQ(rows.size(), 4u);
    auto pair = [](const std::string& t) {
        double a = 0, b = 0;
        EXPECT_EQ(std::sscanf(t.c_str(), "[%lf, %lf]", &a, &b), 2) << t;
        return std::pair{a, b};
    };
    std::set<std::string> alphas;
    for (const auto& row : rows) {
        const auto [a0, a1] = pair(row.at("renderer.iteration.alpha"));
        const auto [b0, b1] = pair(row.at("renderer.iteration.beta"));
        EXPECT_TRUE(a0 >= 0.55 && a0 <= 1.65) << a0;
        EXPECT_TRUE(a1 >= 0.25 && a1 <= 0.75) << a1;
        EXPECT_TRUE(b0 >= 0.25 && b0 <= 0.75) << b0;
        EXPECT_TRUE(b1 >= -0.5 && b1 <= 0.5) << b1;
        alphas.insert(row.at("renderer.iteration.alpha"));
    }
    EXPECT_EQ(alphas.size(), 4u);
    const auto v = run_cli({"validate", dir + "/out/best-1.yaml"});
    EXPECT_EQ(v.rc, 0) << v.err;
}

TEST(Explore, SymmetryOfSymmetry) {
    // The three circles keep the rotation by 120 degrees and a mirror only with equal radii:
    // weighted alone, `fixpoint symmetry`'s measure puts the second radius nearest 0.9 first.
    const std::string dir = scratch_dir("explore_symmetry");
    write_file(dir + "/cfg.yaml", circles);
    const auto r = run_cli({"explore", "--quiet", dir + "/cfg.yaml", "-o", dir + "/out", "--param",
                            "renderer.maps[1].shape.radius=0.5..1.3", "--weights",
                            "coverage=0,entropy=0,dimension=0,lyapunov=0,symmetry=1", "--candidates", "10",
                            "--keep", "1", "--draft-size", "64", "--draft-points", "40000"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto rows = table(dir + "/out/candidates.tsv");
    ASSERT_EQ(rows.size(), 10u);
    double nearest = 1;
    for (const auto& row : rows)
        nearest = std::min(nearest, std::fabs(std::stod(row.at("renderer.maps[1].shape.radius")) - 0.9));
    EXPECT_EQ(std::fabs(std::stod(rows[0].at("renderer.maps[1].shape.radius")) - 0.9), nearest);
    EXPECT_LT(nearest, 0.01);
    // Not weighted (the default), it is not computed.
    const std::string d2 = scratch_dir("explore_symmetry_off");
    write_file(d2 + "/cfg.yaml", circles);
    const auto r2 = run_cli({"explore", "--quiet", d2 + "/cfg.yaml", "-o", d2 + "/out", "--param",
                             "renderer.maps[1].shape.radius=0.5..1.3", "--candidates", "2", "--keep", "1",
                             "--draft-size", "32", "--draft-points", "5000"});
    ASSERT_EQ(r2.rc, 0) << r2.err;
    EXPECT_EQ(table(d2 + "/out/candidates.tsv")[0].at("symmetry"), "");
}

TEST(Explore, ErrorLines) {
    const std::string dir = scratch_dir("explore_errors");
    write_file(dir + "/cfg.yaml", circles);
    const std::string cfg = dir + "/cfg.yaml";
    auto err = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = {"explore", "--quiet", cfg, "-o", dir + "/out"};
        a.insert(a.end(), extra.begin(), extra.end());
        const auto r = run_cli(a);
        EXPECT_EQ(r.rc, 2) << r.err;
        EXPECT_FALSE(fs::exists(dir + "/out"));
        return r.err;
    };
    EXPECT_EQ(err({"--param", "renderer.maps[0].shape.radus=0.3..0.9"}),
              "--param renderer.maps[0].shape.radus=0.3..0.9: '" + cfg +
                  "' has no parameter 'renderer.maps[0].shape.radus' (did you mean "
                  "'renderer.maps[0].shape.radius'?)\n");
    EXPECT_EQ(err({"--param", "renderer.maps[0].shape.radius=0.9..0.3"}),
              "--param renderer.maps[0].shape.radius=0.9..0.3: expected finite numbers A..B with A < B\n");
    EXPECT_EQ(
        err({"--param", "renderer.maps[0].shape.radius=-1..0.3"}),
        "--param renderer.maps[0].shape.radius=-1..0.3: the range leaves the parameter's declared range "
        "(0, inf)\n");
    EXPECT_EQ(
        err({"--param", "renderer.chains=1.5..4"}),
        "--param renderer.chains=1.5..4: 'renderer.chains' is an integer parameter: expected whole numbers "
        "A..B with A < B\n");
    EXPECT_EQ(
        err({"--param", "renderer.background=0..1"}),
        "--param renderer.background=0..1: 'renderer.background' is a colour parameter: a range A..B takes "
        "a real, integer or sequence parameter (give choices a|b|c instead)\n");
    EXPECT_EQ(
        err({"--param", "renderer.precision=float|quad"}),
        "--param renderer.precision=float|quad: the choice 'quad' is refused: --param "
        "renderer.precision=quad:1:1: renderer.precision: must be one of 'float' or 'double', got 'quad'\n");
    EXPECT_EQ(err({"--random", "renderer.iteration.alpha"}),
              "--random renderer.iteration.alpha: '" + cfg +
                  "' has no plugin at 'renderer.iteration.alpha' (did you mean 'renderer.iteration'?)\n");
    EXPECT_EQ(err({"--random", "renderer.iteration"}),
              "--random renderer.iteration: picard has no real, integer or constant sequence parameter to "
              "search\n");
    EXPECT_EQ(err({"--param", "renderer.maps[0].shape.radius=0.3..0.9", "--weights", "coverage=1,beauty=2"}),
              "--weights coverage=1,beauty=2: unknown measure 'beauty' (the measures: coverage, entropy, "
              "dimension, lyapunov, symmetry, colour_entropy, edge_entropy, spectrum, group, contrast)\n");
    EXPECT_EQ(err({}),
              "explore: name the parameters to search with --param PATH=RANGE or --random PLUGIN-PATH\n");
}

} // namespace
