// `fixpoint animate` with `loop: true` and `interpolation: catmull-rom`: the values by hand
// (dyadic keys, so every figure is exact), the loop's seam (the would-be frame N renders the
// bytes of frame 0), and the keys round the loop.
#include "cli.hpp"
#include "configs.hpp"

#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/tools/animate.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

using namespace fp::test;

namespace {

const std::string base = chaos_game(
    {"width: 64", "height: 64", "view: [-1.6, 1.6, -1.6, 1.6]", "points: 20000", "chains: 16", "seed: 5"},
    three_circles("0.9", true));

// `animate --list` of `section` (after the base config), one line per frame.
std::string listed(const std::string& name, const std::string& section) {
    const std::string dir = scratch_dir("animate_loop_" + name);
    write_file(dir + "/cfg.yaml", base + section);
    const auto r = run_cli({"animate", dir + "/cfg.yaml", "--list"});
    EXPECT_EQ(r.rc, 0) << r.err;
    return r.out;
}

const char* const radius = "renderer.maps[0].shape.radius=";

std::string frames(std::initializer_list<const char*> values) {
    std::string out;
    int k = 0;
    for (const char* v : values) out += std::to_string(k++) + " " + radius + v + "\n";
    return out;
}

} // namespace

TEST(AnimateLoop, LinearRunsTheLastKeyOnIntoTheFirst) {
    const std::string keys = "  keys:\n    renderer.maps[0].shape.radius: {0: 0.5, 4: 0.75}\n";
    // Without the loop the value holds after the last key; with it, it runs back to frame 8's
    // 0.5 (frame 0 again): 0.75 + (0.5 - 0.75) t, t = 1/4, 2/4, 3/4.
    EXPECT_EQ(listed("hold", "animation:\n  frames: 8\n" + keys),
              frames({"0.5", "0.5625", "0.625", "0.6875", "0.75", "0.75", "0.75", "0.75"}));
    EXPECT_EQ(listed("loop", "animation:\n  frames: 8\n  loop: true\n" + keys),
              frames({"0.5", "0.5625", "0.625", "0.6875", "0.75", "0.6875", "0.625", "0.5625"}));
    // Keys not at frame 0: before the first key the value comes from the last one's, a period
    // back (key 6 stands at -2 too): frame 0 is halfway from 0.75 to 0.5.
    EXPECT_EQ(listed("offset", "animation:\n  frames: 8\n  loop: true\n  keys:\n"
                               "    renderer.maps[0].shape.radius: {2: 0.5, 6: 0.75}\n"),
              frames({"0.625", "0.5625", "0.5", "0.5625", "0.625", "0.6875", "0.75", "0.6875"}));
}

TEST(AnimateLoop, CatmullRomByHand) {
    const std::string keys = "  keys:\n    renderer.maps[0].shape.radius: {0: 0.5, 2: 1, 4: 0.5}\n";
    // Slopes (per frame): at 0 the one-sided secant (1 - 0.5) / 2 = 0.25, at 2 (0.5 - 0.5) / 4 =
    // 0, at 4 -0.25. Frame 1 (t = 1/2, d = 2; h00 = h01 = 1/2, h10 = 1/8, h11 = -1/8):
    // 0.25 + 2 * 0.25 / 8 + 0.5 - 0 = 0.8125; frame 3 likewise by symmetry; frame 5 holds.
    EXPECT_EQ(listed("cr", "animation:\n  frames: 6\n  interpolation: catmull-rom\n" + keys),
              frames({"0.5", "0.8125", "1", "0.8125", "0.5", "0.5"}));
    // Round a loop of 6 (key 0 again at 6, key 4 at -2): the slope at 0 is (1 - 0.5) / 4 =
    // 0.125, at 4 -0.125. Frame 1: 0.25 + 2 * 0.125 / 8 + 0.5 = 0.78125; frame 5, from 0.5 at 4
    // to 0.5 at 6 with slopes -0.125 and 0.125: 0.25 - 0.03125 + 0.25 - 0.03125 = 0.4375.
    EXPECT_EQ(
        listed("cr_loop", "animation:\n  frames: 6\n  interpolation: catmull-rom\n  loop: true\n" + keys),
        frames({"0.5", "0.78125", "1", "0.78125", "0.5", "0.4375"}));
    // Catmull-Rom may overshoot between keys: a radius that goes below 0 there (frame 2: slopes
    // (0.01 - 2) / 3 and 0, so 0.01 - 2 * 0.663 / 8 = -0.156) is refused before anything renders,
    // at the frame.
    const std::string dir = scratch_dir("animate_loop_overshoot");
    write_file(dir + "/cfg.yaml", base + "animation:\n  frames: 4\n  interpolation: catmull-rom\n  keys:\n"
                                         "    renderer.maps[0].shape.radius: {0: 2, 1: 0.01, 3: 0.01}\n");
    const auto r = run_cli({"animate", dir + "/cfg.yaml", "-o", dir + "/f%d.png"});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("frame 2"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/f0.png"));
}

// The seam: frame N (one past the last) of a loop is frame 0, whatever the interpolation, and
// renders frame 0's bytes; frame N - 1 is one step short of it.
TEST(AnimateLoop, TheWouldBeFrameNRendersFrameZero) {
    const std::string dir = scratch_dir("animate_loop_seam");
    const std::string cfg = base + R"(animation:
  frames: 5
  loop: true
  interpolation: catmull-rom
  keys:
    renderer.maps[0].shape.radius: {1: 0.7, 3: 0.875}
    renderer.maps[1].colour: {0: "#ff0000", 2: [0, 0, 1]}
    renderer.view: {2: [-1.5, 1.5, -1.5, 1.5]}
)";
    write_file(dir + "/cfg.yaml", cfg);
    auto r = run_cli({"animate", "--quiet", dir + "/cfg.yaml", "-o", dir + "/f%d.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const fp::host::CNode root = fp::host::parse_config(cfg, dir + "/cfg.yaml");
    const fp::host::Animation a = fp::host::parse_animation(root);
    ASSERT_TRUE(a.loop);
    for (long k : {5L, 10L, -5L}) {
        write_file(dir + "/n.yaml", fp::host::emit_yaml(fp::host::frame_config(root, a, k)));
        r = run_cli({"render", "--quiet", dir + "/n.yaml", "-o", dir + "/n" + std::to_string(k) + ".png"});
        ASSERT_EQ(r.rc, 0) << r.err;
        EXPECT_EQ(read_file(dir + "/n" + std::to_string(k) + ".png"), read_file(dir + "/f0.png"))
            << "frame " << k;
    }
    // (Frame 4 is not frame 0: the loop does not close by repeating a frame.)
    EXPECT_NE(read_file(dir + "/f4.png"), read_file(dir + "/f0.png"));
}
