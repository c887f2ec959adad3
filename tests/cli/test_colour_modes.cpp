// flame's `mode`: paper 02's eq. (28) as written (`last`) and paper 01's colouring by set
// (`set-colour`), beside the mean of today. Checked by hand on constant maps, where every point
// of a chain lands in one pixel and its colours follow c' = (c + c_j) / 2 from a random start:
//   - last: the pixel holds the colour after the chain's plotted points only (Algorithm 2
//     updates c under "if i > 20"), from the start colour the renderer documents (the stream
//     fp::chain_stream(seed + "colour", chain));
//   - among chains, the last write is the largest (step, chain);
//   - set-colour: a pixel shows one set's colour, never a mix;
//   - the same bytes on 1, 2 and 3 threads.
#include "cli.hpp"

#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/rng.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

/// chaos-game's start colour of chain `chain` (flame, mode last): Algorithm 2's "c = random
/// colour" from the chain's colour stream.
std::array<float, 3> start_colour(std::uint64_t seed, std::uint64_t chain) {
    fp::Rng r = fp::chain_stream(seed + 0x636f6c6f7572ull, chain);
    std::array<float, 3> c{};
    for (float& x : c) x = fp::uniform_float(r);
    return c;
}

/// c after `updates` steps of c = (c + m) / 2 in float, then as the histogram keeps it (16 bits).
std::array<double, 3> after(std::array<float, 3> c, std::array<float, 3> m, int updates) {
    for (int u = 0; u < updates; ++u)
        for (int k = 0; k < 3; ++k) c[k] = (c[k] + m[k]) * 0.5f;
    std::array<double, 3> q{};
    for (int k = 0; k < 3; ++k) q[k] = std::trunc(double(c[k]) * 65535.0 + 0.5) / 65535.0;
    return q;
}

/// A 2 x 2 render over [0, 1]^2 (EXR: the floats themselves), gamma 1: the fullest bin is
/// shaded by 1, so its pixel is its colour.
fp::Image render(const std::string& name, const std::string& renderer_lines, int threads = 1) {
    const std::string dir = scratch_dir("colour_modes_" + name);
    write_file(dir + "/c.yaml",
               "renderer:\n  type: chaos-game\n  width: 2\n  height: 2\n  view: [0, 1, 0, 1]\n"
               "  seed: 7\n" +
                   renderer_lines);
    const auto r = run_cli(
        {"render", "--quiet", "--threads", std::to_string(threads), dir + "/c.yaml", "-o", dir + "/out.exr"});
    EXPECT_EQ(r.rc, 0) << r.err;
    return fp::host::read_image(dir + "/out.exr");
}

/// Pixel (column c, row r), channel k.
float at(const fp::Image& img, int c, int r, int k) {
    return img.pixels[(std::size_t(r) * std::size_t(img.width) + std::size_t(c)) * std::size_t(img.channels) +
                      std::size_t(k)];
}

// One map sending every point to (0.6, 0.6): column 1, row 0.
const std::string red_map =
    "  maps:\n    - {type: affine, coefficients: [0, 0, 0, 0, 0.6, 0.6], colour: [1, 0, 0]}\n";

} // namespace

TEST(FlameModes, LastIsTheColourAfterThePlottedPointsFromARandomStart) {
    const std::string lines = "  chains: 1\n  points: 3\n  skip: 2\n  start: [0.1, 0.1]\n"
                              "  colourer: {type: flame, gamma: 1, mode: last}\n" +
                              red_map;
    const fp::Image img = render("last_one_chain", lines);
    // Three plotted points: three updates (not five: the two skipped steps leave c alone).
    const auto want = after(start_colour(7, 0), {1, 0, 0}, 3);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(at(img, 1, 0, k), want[k], 1e-6) << k;
    // The start colour is not red: the test tells last from mean.
    EXPECT_GT(std::abs(want[1]) + std::abs(want[2]), 0.01);
    // The other pixels: the background.
    for (int k = 0; k < 3; ++k) EXPECT_EQ(at(img, 0, 0, k), 0.0f);

    // mean: one map, its colour carried from the mean map colour: pure red.
    const fp::Image mean =
        render("mean_one_chain", fp::test::replace_once(lines, "mode: last", "mode: mean"));
    EXPECT_NEAR(at(mean, 1, 0, 0), 1.0, 1e-6);
    EXPECT_NEAR(at(mean, 1, 0, 1), 0.0, 1e-6);
    EXPECT_NEAR(at(mean, 1, 0, 2), 0.0, 1e-6);
}

TEST(FlameModes, LastAmongChainsIsTheLargestStepThenChain) {
    // 5 points over 3 chains: chains 0 and 1 plot 2 points (steps 0 and 1), chain 2 one (step
    // 0). The last write is (step 1, chain 1): chain 1's colour after two updates.
    const std::string lines = "  chains: 3\n  points: 5\n  skip: 0\n  start: [0.1, 0.1]\n"
                              "  colourer: {type: flame, gamma: 1, mode: last}\n" +
                              red_map;
    const auto want = after(start_colour(7, 1), {1, 0, 0}, 2);
    for (int threads : {1, 2, 3}) {
        const fp::Image img = render("last_chains_" + std::to_string(threads), lines, threads);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(at(img, 1, 0, k), want[k], 1e-6) << threads << " " << k;
    }
    // Not chain 0's colour, nor chain 2's.
    const auto c0 = after(start_colour(7, 0), {1, 0, 0}, 2), c2 = after(start_colour(7, 2), {1, 0, 0}, 1);
    EXPECT_GT(std::abs(c0[1] - want[1]) + std::abs(c0[2] - want[2]), 1e-3);
    EXPECT_GT(std::abs(c2[1] - want[1]) + std::abs(c2[2] - want[2]), 1e-3);
}

TEST(FlameModes, LastIsMergedAcrossWorkersByStepThenChain) {
    // 3000 chains (six blocks and more, so 2 and 3 threads split them over their workers) and
    // 5999 points: chains 0-2998 plot 2 points, chain 2999 one. Every worker's bin holds its own
    // last (step, chain); the merge must pick (step 1, chain 2998) whichever worker had it.
    const std::string lines = "  chains: 3000\n  points: 5999\n  skip: 0\n  start: [0.1, 0.1]\n"
                              "  colourer: {type: flame, gamma: 1, mode: last}\n" +
                              red_map;
    const auto want = after(start_colour(7, 2998), {1, 0, 0}, 2);
    for (int threads : {1, 2, 3}) {
        const fp::Image img = render("last_merge_" + std::to_string(threads), lines, threads);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(at(img, 1, 0, k), want[k], 1e-6) << threads << " " << k;
    }
    const auto c2999 = after(start_colour(7, 2999), {1, 0, 0}, 1);
    EXPECT_GT(std::abs(c2999[1] - want[1]) + std::abs(c2999[2] - want[2]), 1e-3);
}

TEST(FlameModes, SetColourShowsOneSetsColourNeverAMix) {
    // Two maps onto the same point, red and blue: the mean mixes them, set-colour shows the
    // colour of the set that produced the last point, exactly.
    const std::string maps =
        "  maps:\n"
        "    - {type: affine, coefficients: [0, 0, 0, 0, 0.6, 0.6], colour: [1, 0, 0]}\n"
        "    - {type: affine, coefficients: [0, 0, 0, 0, 0.6, 0.6], colour: [0, 0, 1]}\n";
    const std::string base = "  chains: 16\n  points: 4000\n  inversion_rules: off\n";
    const fp::Image set =
        render("set_colour", base + "  colourer: {type: flame, gamma: 1, mode: set-colour}\n" + maps);
    const float r = at(set, 1, 0, 0), b = at(set, 1, 0, 2);
    EXPECT_EQ(at(set, 1, 0, 1), 0.0f);
    EXPECT_TRUE((r == 1.0f && b == 0.0f) || (r == 0.0f && b == 1.0f)) << r << " " << b;
    const fp::Image mean = render("set_mean", base + "  colourer: {type: map-colour, gamma: 1}\n" + maps);
    EXPECT_GT(at(mean, 1, 0, 0), 0.2f);
    EXPECT_GT(at(mean, 1, 0, 2), 0.2f);
}

TEST(FlameModes, LastAndSetColourGiveTheSameBytesOnAnyThreadCount) {
    for (const std::string mode : {"last", "set-colour"}) {
        std::vector<std::string> bytes;
        for (int threads : {1, 2, 3}) {
            const std::string dir = scratch_dir("colour_modes_threads_" + mode + std::to_string(threads));
            const auto r = run_cli({"render", "--quiet", "--threads", std::to_string(threads),
                                    fp::test::source_dir() + "/configs/inversion/fig6a.yaml", "--set",
                                    "renderer.points=300000", "--set", "renderer.width=200", "--set",
                                    "renderer.height=200", "--set", "renderer.colourer.mode=" + mode, "-o",
                                    dir + "/out.png"});
            ASSERT_EQ(r.rc, 0) << r.err;
            bytes.push_back(read_file(dir + "/out.png"));
        }
        EXPECT_EQ(bytes[0], bytes[1]) << mode;
        EXPECT_EQ(bytes[0], bytes[2]) << mode;
    }
}

TEST(FlameModes, AnUnknownModeIsRefusedWithTheChoices) {
    const std::string dir = scratch_dir("colour_modes_bad");
    write_file(dir + "/c.yaml",
               "renderer:\n  type: chaos-game\n  colourer: {type: flame, mode: latest}\n" + red_map);
    const auto r = run_cli({"render", "--quiet", dir + "/c.yaml", "-o", dir + "/out.png"});
    EXPECT_NE(r.rc, 0);
    EXPECT_NE(
        r.err.find("c.yaml:3:33: renderer.colourer.mode: must be one of 'mean', 'last' or 'set-colour', "
                   "got 'latest'\n"),
        std::string::npos)
        << r.err;
}
