// `fixpoint animate` with motion blur (animation.temporal_samples, temporal_filter_width;
// framework/src/tools/motion_blur.hpp): a frame that does not move is its plain render, pixel
// for pixel, whatever the colour rule; a moving one holds the shutter and is the same bytes on
// any threads; its recipe names its samples; bad settings are one line.
#include "cli.hpp"
#include "configs.hpp"

#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <cstddef>
#include <string>

using namespace fp::test;

namespace {

// Sierpinski's triangle, 64 x 64 (13 lines).
std::string triangle(const std::string& colourer) {
    return chaos_game({"width: 64", "height: 64", "view: [-0.1, 1.5, -0.1, 1.1]", "points: 60000",
                       "chains: 2048", "seed: 5", "colourer: " + colourer},
                      sierpinski);
}

std::size_t lit(const fp::Image& im) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < im.pixels.size(); i += 3)
        n += im.pixels[i] > 0 || im.pixels[i + 1] > 0 || im.pixels[i + 2] > 0;
    return n;
}

} // namespace

TEST(MotionBlur, AStillFrameIsThePlainRender) {
    // Four samples of a frame whose key holds still: the four shares of the chains at four
    // times that give the same config, summed, are the whole render: the same pixels, under
    // the mean colour and under the last colour (set-colour, the shares' order merged).
    for (const std::string colourer : {"{type: flame}", "{type: flame, mode: set-colour}"}) {
        const std::string dir = scratch_dir("motion_blur_still");
        const std::string still = triangle(colourer) +
                                  "animation:\n  frames: 3\n  temporal_samples: 4\n"
                                  "  keys:\n    renderer.maps[1].coefficients: {0: [0.5, 0, 0, 0.5, 0.5, 0], "
                                  "2: [0.5, 0, 0, 0.5, 0.5, 0]}\n";
        write_file(dir + "/a.yaml", still);
        write_file(dir + "/plain.yaml", triangle(colourer));
        const auto a = run_cli({"animate", "--quiet", dir + "/a.yaml", "-o", dir + "/f/%d.png"});
        ASSERT_EQ(a.rc, 0) << a.err;
        const auto p = run_cli({"render", "--quiet", dir + "/plain.yaml", "-o", dir + "/plain.png"});
        ASSERT_EQ(p.rc, 0) << p.err;
        const fp::Image f = fp::host::read_image(dir + "/f/1.png"),
                        plain = fp::host::read_image(dir + "/plain.png");
        ASSERT_GT(lit(plain), 300u);
        EXPECT_TRUE(f.pixels == plain.pixels) << colourer;
        // Its recipe names the samples.
        EXPECT_NE(
            fp::host::read_recipe(dir + "/f/1.png").find("# motion blur: 4 temporal samples over 1 frame"),
            std::string::npos);
    }
}

TEST(MotionBlur, AMovingFrameHoldsTheShutter) {
    // Map 1's offset moves by 0.2 a frame: frame 1 blurred over 2 frames (8 samples from
    // t = 0.125 to 1.875) spreads its points over more pixels than the frame alone, the same
    // bytes on 1 and 3 threads.
    const std::string dir = scratch_dir("motion_blur_moving");
    const std::string moving = triangle("{type: flame}") + "animation:\n  frames: 3\n";
    const std::string keys = "  keys:\n    renderer.maps[1].coefficients: {0: [0.5, 0, 0, 0.5, 0.3, 0], 2: "
                             "[0.5, 0, 0, 0.5, 0.7, 0]}\n";
    write_file(dir + "/sharp.yaml", moving + keys);
    write_file(dir + "/blur.yaml", moving + "  temporal_samples: 8\n  temporal_filter_width: 2\n" + keys);
    const auto s =
        run_cli({"animate", "--quiet", dir + "/sharp.yaml", "-o", dir + "/s/%d.png", "--frames", "1..1"});
    ASSERT_EQ(s.rc, 0) << s.err;
    for (const char* threads : {"1", "3"}) {
        const auto b = run_cli({"animate", "--quiet", "--threads", threads, dir + "/blur.yaml", "-o",
                                dir + "/b" + threads + "/%d.png", "--frames", "1..1"});
        ASSERT_EQ(b.rc, 0) << b.err;
    }
    EXPECT_EQ(read_file(dir + "/b1/1.png"), read_file(dir + "/b3/1.png"));
    const fp::Image sharp = fp::host::read_image(dir + "/s/1.png"),
                    blur = fp::host::read_image(dir + "/b1/1.png");
    EXPECT_GT(lit(blur), lit(sharp) + lit(sharp) / 10) << lit(blur) << " " << lit(sharp);
    // A rerun skips the frame (its recipe); another shutter is another recipe, refused.
    const auto again = run_cli({"animate", dir + "/blur.yaml", "-o", dir + "/b1/%d.png", "--frames", "1..1"});
    ASSERT_EQ(again.rc, 0) << again.err;
    EXPECT_NE(again.err.find("skipped"), std::string::npos) << again.err;
    const auto other = run_cli({"animate", dir + "/blur.yaml", "-o", dir + "/b1/%d.png", "--frames", "1..1",
                                "--set", "animation.temporal_samples=4"});
    EXPECT_EQ(other.rc, 2) << other.err;
    EXPECT_NE(other.err.find("is not frame 1 of this animation (another recipe)"), std::string::npos)
        << other.err;
}

TEST(MotionBlur, BadSettingsAreOneLine) {
    const std::string dir = scratch_dir("motion_blur_bad");
    const std::string keys = "  keys: {renderer.width: {0: 64}}\n";
    auto line = [&](const std::string& config) {
        write_file(dir + "/bad.yaml", config);
        const auto r = run_cli({"animate", dir + "/bad.yaml", "-o", dir + "/f/%d.png"});
        EXPECT_EQ(r.rc, 2) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir + "/f"));
        return r.err.substr(r.err.find("bad.yaml:") == std::string::npos ? 0 : r.err.find("bad.yaml:"));
    };
    const std::string c = triangle("{type: flame}"); // (13 lines: animation: is line 14)
    EXPECT_EQ(
        line(c + "animation:\n  frames: 2\n  temporal_samples: 0\n" + keys),
        "bad.yaml:16:21: animation.temporal_samples: expected a whole number from 1 to 1024, got '0'\n");
    EXPECT_EQ(line(c + "animation:\n  frames: 2\n  temporal_filter_width: -1\n" + keys),
              "bad.yaml:16:26: animation.temporal_filter_width: expected a number in (0, 16] (the frames a "
              "frame's samples span), got '-1'\n");
    const std::string trap = read_file(source_dir() + "/configs/orbit-trap/fig5a.yaml");
    // Too few chains for the samples (chaos-game's blocks: 64 chains are one), said after the
    // first sample.
    write_file(dir + "/few.yaml",
               triangle("{type: flame}") + "animation:\n  frames: 2\n  temporal_samples: 4\n" + keys);
    const auto few =
        run_cli({"animate", dir + "/few.yaml", "-o", dir + "/few/%d.png", "--set", "renderer.chains=64"});
    EXPECT_EQ(few.rc, 2);
    EXPECT_EQ(few.err,
              "animation.temporal_samples: frame 0's sample 1 has no chains of its own: the render's "
              "chains are too few for 4 samples (raise renderer.chains)\n");
    EXPECT_FALSE(std::filesystem::exists(dir + "/few/0.png"));
    const std::string r = line(trap + "animation:\n  frames: 2\n  temporal_samples: 2\n" + keys);
    EXPECT_NE(r.find("animation.temporal_samples: motion blur sums the histograms of its samples: orbit-trap "
                     "keeps none (chaos-game renders keep one)"),
              std::string::npos)
        << r;
}
