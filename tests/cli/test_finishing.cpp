// The finishing stage from the command line (docs/finishing.md): supersampled, filtered and
// density-estimated renders give the same bytes in strips as in one pass and on any number of
// threads, for the chaos game's colour paths and the superfractal; a checkpointed one resumes to
// the uninterrupted bytes; and its bad settings get one positioned line, exit 2, nothing
// written.
#include "cli.hpp"
#include "configs.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

using namespace fp::test;
namespace fs = std::filesystem;

namespace {

// The stage at its fullest: supersample 2, a gaussian wider than flam3's default, the estimate.
const std::vector<std::string> stage = {"--set", "renderer.supersample=2",
                                        "--set", "renderer.filter={type: gaussian, radius: 0.75}",
                                        "--set", "renderer.estimator_radius=2"};

struct Case {
    const char* name;
    const char* config; ///< under the source tree
    const char* points;
    const char* memory; ///< small enough for several strips at this size
};

class FinishedStrips : public ::testing::TestWithParam<Case> {};

TEST_P(FinishedStrips, SameBytesAsOnePassOnAnyThreads) {
    const Case& c = GetParam();
    const std::string dir = scratch_dir(std::string("finished_") + c.name);
    const std::string config = source_dir() + "/" + c.config;
    const std::vector<std::string> base =
        with({config, "--set", std::string("renderer.points=") + c.points, "--set", "renderer.width=300",
              "--set", "renderer.height=200"},
             stage);
    const auto whole = run_cli(with({"render", "--quiet", "--threads", "2", "-o", dir + "/whole.png"}, base));
    ASSERT_EQ(whole.rc, 0) << whole.err;
    const auto plain = run_cli({"render", "--quiet", "--threads", "2", "-o", dir + "/plain.png", config,
                                "--set", std::string("renderer.points=") + c.points, "--set",
                                "renderer.width=300", "--set", "renderer.height=200"});
    ASSERT_EQ(plain.rc, 0) << plain.err;
    EXPECT_NE(read_file(dir + "/whole.png"), read_file(dir + "/plain.png")) << "the stage changed nothing";
    for (const char* threads : {"1", "3"}) {
        const std::string out = dir + "/strips-" + threads + ".png";
        const auto r = run_cli(with({"render", "--threads", threads, "--memory", c.memory, "-o", out}, base));
        ASSERT_EQ(r.rc, 0) << r.err;
        EXPECT_NE(r.err.find(" strips of "), std::string::npos) << r.err;
        EXPECT_EQ(read_file(out), read_file(dir + "/whole.png"))
            << c.name << " on " << threads << " thread(s)";
    }
}

INSTANTIATE_TEST_SUITE_P(
    ChaosGame, FinishedStrips,
    ::testing::Values(Case{"density", "bench/circles.yaml", "300000", "14M"},
                      Case{"flame_affine", "bench/sierpinski.yaml", "300000", "20M"},
                      Case{"set_colour_last", "configs/inversion/fig6a.yaml", "300000", "24M"},
                      Case{"centroid_double", "configs/gumowski-mira/fig6b.yaml", "30000", "14M"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(Finishing, SuperfractalSameBytesOnAnyThreads) {
    const std::string dir = scratch_dir("finished_superfractal");
    const std::string config = source_dir() + "/configs/gumowski-mira/fig2-F.yaml";
    // A quarter of the figure's pixels and points: still many buffers' worth per thread.
    const std::vector<std::string> size = {"--set", "renderer.width=512",
                                           "--set", "renderer.height=512",
                                           "--set", "renderer.points_per_buffer=500000"};
    const std::vector<std::string> small = with(stage, size);
    const auto a =
        run_cli(with({"render", "--quiet", "--threads", "1", config, "-o", dir + "/a.png"}, small));
    ASSERT_EQ(a.rc, 0) << a.err;
    const auto b =
        run_cli(with({"render", "--quiet", "--threads", "3", config, "-o", dir + "/b.png"}, small));
    ASSERT_EQ(b.rc, 0) << b.err;
    EXPECT_TRUE(read_file(dir + "/a.png") == read_file(dir + "/b.png"));
    const auto raw = run_cli(with({"render", "--quiet", config, "-o", dir + "/raw.png"}, size));
    ASSERT_EQ(raw.rc, 0) << raw.err;
    EXPECT_FALSE(read_file(dir + "/a.png") == read_file(dir + "/raw.png"));
}

// The checkpoint holds the supersampled histogram: continued to more points, it finishes to the
// bytes of a render of those points.
TEST(Finishing, CheckpointContinuesToTheSameBytes) {
    const std::string dir = scratch_dir("finished_checkpoint");
    write_file(dir + "/s.yaml", chaos_game({"width: 96", "height: 96", "points: 400000"}, sierpinski));
    const auto first = run_cli(with(
        {"render", "--quiet", dir + "/s.yaml", "-o", dir + "/first.png", "--checkpoint", dir + "/ck.bin"},
        stage));
    ASSERT_EQ(first.rc, 0) << first.err;
    const auto more = run_cli(with({"render", "--quiet", dir + "/s.yaml", "--set", "renderer.points=800000",
                                    "-o", dir + "/more.png", "--resume", dir + "/ck.bin"},
                                   stage));
    ASSERT_EQ(more.rc, 0) << more.err;
    const auto fresh = run_cli(with(
        {"render", "--quiet", dir + "/s.yaml", "--set", "renderer.points=800000", "-o", dir + "/fresh.png"},
        stage));
    ASSERT_EQ(fresh.rc, 0) << fresh.err;
    EXPECT_EQ(read_file(dir + "/more.png"), read_file(dir + "/fresh.png"));
}

struct Bad {
    const char* name;
    std::vector<std::string> sets;
    std::string expected; ///< the whole line
};

void PrintTo(const Bad& c, std::ostream* os) { *os << c.name; }

class FinishingBadInput : public ::testing::TestWithParam<Bad> {};

TEST_P(FinishingBadInput, OneLineExitTwoNothingWritten) {
    const Bad& c = GetParam();
    std::vector<std::string> args = {"render", "--quiet", "bad.yaml", "-o", "out.png"};
    for (const auto& s : c.sets) args.insert(args.end(), {"--set", s});
    const std::string yaml =
        chaos_game({"width: 64", "height: 64", "points: 20000", "chains: 64"}, three_circles("0.9"));
    EXPECT_EQ(run_bad_input(std::string("finishing_") + c.name, yaml, args), c.expected);
}

INSTANTIATE_TEST_SUITE_P(
    Finishing, FinishingBadInput,
    ::testing::Values(Bad{"radius_zero",
                          {"renderer.filter={type: gaussian, radius: 0}"},
                          "--set renderer.filter={type: gaussian, radius: 0}: renderer.filter.radius: must "
                          "be in (0, 16], got 0"},
                      Bad{"radius_huge",
                          {"renderer.filter={type: gaussian, radius: 1e9}"},
                          "--set renderer.filter={type: gaussian, radius: 1e9}: renderer.filter.radius: must "
                          "be in (0, 16], got 1e9"},
                      Bad{"unknown_filter",
                          {"renderer.filter={type: gausian}"},
                          "--set renderer.filter={type: gausian}: renderer.filter.type: unknown filter "
                          "'gausian' (did you mean "
                          "'gaussian'?)"},
                      Bad{"no_weight",
                          {"renderer.supersample=2", "renderer.filter={type: box, radius: 0.01}"},
                          "--set renderer.filter={type: box, radius: 0.01}: renderer.filter: the filter has "
                          "no weight at radius "
                          "0.010000: make the radius larger"},
                      Bad{"minimum_above_radius",
                          {"renderer.estimator_radius=2", "renderer.estimator_minimum=3"},
                          "--set renderer.estimator_minimum=3: renderer.estimator_minimum: the estimator's "
                          "minimum must not exceed "
                          "estimator_radius"},
                      Bad{"supersample_17",
                          {"renderer.supersample=17"},
                          "--set renderer.supersample=17: renderer.supersample: must be in [1, 16], got 17"}),
    [](const auto& info) { return std::string(info.param.name); });

// A config's finishing can be taken back from the command line: an optional parameter set to
// null is unset, and the render is the raw one, byte for byte.
TEST(Finishing, NullUnsetsTheConfigsFilter) {
    const std::string dir = scratch_dir("finishing_null");
    const std::vector<std::string> keys = {"width: 64", "height: 64", "points: 20000", "chains: 64"};
    std::vector<std::string> finished = keys;
    finished.insert(finished.end(), {"supersample: 2", "filter: {type: gaussian, radius: 0.5}"});
    write_file(dir + "/raw.yaml", chaos_game(keys, three_circles("0.9")));
    write_file(dir + "/fin.yaml", chaos_game(finished, three_circles("0.9")));
    ASSERT_EQ(run_cli({"render", "--quiet", dir + "/raw.yaml", "-o", dir + "/raw.png"}).rc, 0);
    const auto r = run_cli({"render", "--quiet", dir + "/fin.yaml", "--set", "renderer.filter=null", "--set",
                            "renderer.supersample=1", "-o", dir + "/unset.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(read_file(dir + "/unset.png"), read_file(dir + "/raw.png"));
}

// In the file, the line names its place there.
TEST(Finishing, ABadFilterInTheFileIsPlaced) {
    const std::string yaml = chaos_game({"width: 64", "height: 64", "points: 20000", "chains: 64",
                                         "supersample: 2", "filter: {type: lanczos, radius: 0}"},
                                        three_circles("0.9"));
    EXPECT_EQ(run_bad_input("finishing_in_file", yaml, {"render", "--quiet", "bad.yaml", "-o", "out.png"}),
              "bad.yaml:8:35: renderer.filter.radius: must be in (0, 16], got 0");
}

} // namespace
