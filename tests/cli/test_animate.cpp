// `fixpoint animate`: frames equal renders with the interpolated values, the interpolation by
// hand, skipping on a rerun, exact error lines for bad animation sections, and the video.
#include "cli.hpp"
#include "configs.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sys/stat.h>
#include <unistd.h>

using namespace fp::test;
namespace fs = std::filesystem;

namespace {

// Three circles, 64 x 64, few points: the smallest pipeline that draws.
const std::string base = chaos_game(
    {"width: 64", "height: 64", "view: [-1.6, 1.6, -1.6, 1.6]", "points: 20000", "chains: 16", "seed: 5"},
    three_circles("0.9", true));

// Three frames: a radius, a colour from "#rrggbb" to a list, and a point.
const std::string animated = base + R"(animation:
  frames: 3
  keys:
    renderer.maps[0].shape.radius: {0: 0.75, 2: 0.875}
    renderer.maps[1].colour: {0: "#ff0000", 2: [0, 0, 1]}
    renderer.maps[2].shape.centre: {0: [-0.5, -0.866], 2: [-0.5, -0.5]}
)";

// Whether `name` runs from PATH.
bool have(const std::string& name) {
    return std::system(("command -v " + name + " >/dev/null 2>&1").c_str()) == 0;
}

// The output of a shell command.
std::string shell(const std::string& cmd) {
    std::string out;
    if (FILE* p = ::popen(cmd.c_str(), "r")) {
        char buf[256];
        for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
        ::pclose(p);
    }
    return out;
}

// The frames ffprobe counts in the video `path`, as it prints them ("3\n").
std::string frames_in(const std::string& path) {
    return shell("ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of "
                 "csv=p=0 '" +
                 path + "'");
}

// PATH replaced for the CLI runs of one scope.
struct PathFor {
    std::string saved;
    explicit PathFor(const std::string& path) : saved(std::getenv("PATH") ? std::getenv("PATH") : "") {
        ::setenv("PATH", path.c_str(), 1);
    }
    ~PathFor() { ::setenv("PATH", saved.c_str(), 1); }
};

TEST(Animate, FramesAreRendersWithTheInterpolatedValues) {
    const std::string dir = scratch_dir("animate_frames");
    write_file(dir + "/cfg.yaml", animated);
    auto r = run_cli({"animate", "--quiet", dir + "/cfg.yaml", "-o", dir + "/f/%02d.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(r.err, "");
    // Frame 1 by hand: halfway, linear.
    const std::vector<std::vector<std::string>> sets = {
        {"renderer.maps[0].shape.radius=0.75", "renderer.maps[1].colour=\"#ff0000\"",
         "renderer.maps[2].shape.centre=[-0.5, -0.866]"},
        {"renderer.maps[0].shape.radius=0.8125", "renderer.maps[1].colour=[0.5, 0, 0.5]",
         "renderer.maps[2].shape.centre=[-0.5, -0.683]"},
        {"renderer.maps[0].shape.radius=0.875", "renderer.maps[1].colour=[0, 0, 1]",
         "renderer.maps[2].shape.centre=[-0.5, -0.5]"},
    };
    for (int k = 0; k < 3; ++k) {
        std::vector<std::string> args = {"render", "--quiet", dir + "/cfg.yaml", "-o",
                                         dir + "/r" + std::to_string(k) + ".png"};
        for (const auto& s : sets[std::size_t(k)]) args.insert(args.end(), {"--set", s});
        r = run_cli(args);
        ASSERT_EQ(r.rc, 0) << r.err;
        EXPECT_EQ(read_file(dir + "/f/0" + std::to_string(k) + ".png"),
                  read_file(dir + "/r" + std::to_string(k) + ".png"))
            << "frame " << k;
    }
    EXPECT_NE(read_file(dir + "/f/00.png"), read_file(dir + "/f/01.png"));
    // A frame's recipe renders it again, byte for byte.
    r = run_cli({"render", "--quiet", dir + "/f/01.png", "-o", dir + "/again.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(read_file(dir + "/f/01.png"), read_file(dir + "/again.png"));
    // The recipe holds the values, not the animation.
    r = run_cli({"recipe", dir + "/f/01.png"});
    EXPECT_NE(r.out.find("radius: 0.8125"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("animation"), std::string::npos) << r.out;
}

TEST(Animate, LinearSmoothAndIntegerValuesByHand) {
    const std::string dir = scratch_dir("animate_values");
    const std::string keys = base + R"(animation:
  frames: 6
  interpolation: INTERP
  keys:
    renderer.view: {0: [-2, 2, -2, 2], 4: [-1, 1, -1, 1]}
    renderer.seed: {0: 10, 4: 13}
    renderer.maps[0].colour: {1: "#000000", 3: "#ff0080"}
)";
    write_file(dir + "/linear.yaml", fp::test::replace_once(keys, "INTERP", "linear"));
    write_file(dir + "/smooth.yaml", fp::test::replace_once(keys, "INTERP", "smooth"));
    auto r = run_cli({"animate", dir + "/linear.yaml", "--list"});
    ASSERT_EQ(r.rc, 0) << r.err;
    // t = 1/4, 1/2, 3/4. The view is real though written in whole numbers; the seed is an
    // integer parameter: 10.75 -> 11, 11.5 -> 12 (halves away from zero), 12.25 -> 12. The
    // colour keyed at 1 and 3: as written there and outside, [0.5, 0, 128/255 / 2] at 2.
    EXPECT_EQ(r.out, "0 renderer.view=[-2, 2, -2, 2] renderer.seed=10 renderer.maps[0].colour=\"#000000\"\n"
                     "1 renderer.view=[-1.75, 1.75, -1.75, 1.75] renderer.seed=11 "
                     "renderer.maps[0].colour=\"#000000\"\n"
                     "2 renderer.view=[-1.5, 1.5, -1.5, 1.5] renderer.seed=12 "
                     "renderer.maps[0].colour=[0.5, 0, 0.25098039215686274]\n"
                     "3 renderer.view=[-1.25, 1.25, -1.25, 1.25] renderer.seed=12 "
                     "renderer.maps[0].colour=\"#ff0080\"\n"
                     "4 renderer.view=[-1, 1, -1, 1] renderer.seed=13 renderer.maps[0].colour=\"#ff0080\"\n"
                     "5 renderer.view=[-1, 1, -1, 1] renderer.seed=13 renderer.maps[0].colour=\"#ff0080\"\n");
    // smooth: s = t^2 (3 - 2t) = 0.15625, 0.5, 0.84375; the seed 10.46875 -> 10, 11.5 -> 12,
    // 12.53125 -> 13.
    r = run_cli({"animate", dir + "/smooth.yaml", "--list", "--frames", "1..3"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(r.out, "1 renderer.view=[-1.84375, 1.84375, -1.84375, 1.84375] renderer.seed=10 "
                     "renderer.maps[0].colour=\"#000000\"\n"
                     "2 renderer.view=[-1.5, 1.5, -1.5, 1.5] renderer.seed=12 "
                     "renderer.maps[0].colour=[0.5, 0, 0.25098039215686274]\n"
                     "3 renderer.view=[-1.15625, 1.15625, -1.15625, 1.15625] renderer.seed=13 "
                     "renderer.maps[0].colour=\"#ff0080\"\n");
    // --set applies before the animation: a shorter one for a preview.
    r = run_cli({"animate", dir + "/linear.yaml", "--list", "--set", "animation.frames=2"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, dir + "/linear.yaml:17:40: animation.keys.renderer.view: keyframe '4': expected a frame "
                           "number from 0 to 1 (frames: 2)\n");
}

TEST(Animate, RerunSkipsFramesWithTheirRecipeAndRefusesOthers) {
    const std::string dir = scratch_dir("animate_rerun");
    write_file(dir + "/cfg.yaml", animated);
    const std::vector<std::string> args = {"animate", dir + "/cfg.yaml", "-o", dir + "/f/%d.png"};
    auto r = run_cli(args);
    ASSERT_EQ(r.rc, 0) << r.err;
    const std::string frame1 = read_file(dir + "/f/1.png");
    struct stat before {};
    ::stat((dir + "/f/1.png").c_str(), &before);
    r = run_cli(args);
    ASSERT_EQ(r.rc, 0) << r.err;
    for (int k = 0; k < 3; ++k)
        EXPECT_NE(r.err.find(dir + "/f/" + std::to_string(k) + ".png: frame " + std::to_string(k) +
                             " is there with this recipe: skipped"),
                  std::string::npos)
            << r.err;
    EXPECT_NE(r.err.find("0 frames rendered"), std::string::npos) << r.err;
    struct stat after {};
    ::stat((dir + "/f/1.png").c_str(), &after);
    EXPECT_EQ(before.st_ino, after.st_ino); // not written again
    // Frame 1 removed: only it is rendered again, the same bytes.
    fs::remove(dir + "/f/1.png");
    r = run_cli(args);
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(r.err.find("1 frame rendered"), std::string::npos) << r.err;
    EXPECT_EQ(read_file(dir + "/f/1.png"), frame1);
    // Another animation over the same files: refused before anything is rendered, then --force.
    write_file(dir + "/cfg.yaml", fp::test::replace_once(animated, "2: 0.875", "2: 0.625"));
    r = run_cli(args);
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err,
              "'" + dir +
                  "/f/1.png' exists and is not frame 1 of this animation (another recipe): add --force "
                  "to replace it\n");
    EXPECT_EQ(read_file(dir + "/f/1.png"), frame1);
    r = run_cli({"animate", "--quiet", "--force", dir + "/cfg.yaml", "-o", dir + "/f/%d.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(read_file(dir + "/f/1.png"), frame1);
    EXPECT_EQ(read_file(dir + "/f/0.png"), read_file(dir + "/f/0.png"));
}

TEST(Animate, RenderAndValidateTakeTheConfigAsItStands) {
    const std::string dir = scratch_dir("animate_render");
    write_file(dir + "/cfg.yaml", animated);
    write_file(dir + "/still.yaml", base);
    auto r = run_cli({"render", "--quiet", dir + "/cfg.yaml", "-o", dir + "/a.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = run_cli({"render", "--quiet", dir + "/still.yaml", "-o", dir + "/b.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(read_file(dir + "/a.png"), read_file(dir + "/b.png"));
    r = run_cli({"validate", dir + "/cfg.yaml", "-o", dir + "/c.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(r.err.find("valid: an animation of 3 frames (3 keys)"), std::string::npos) << r.err;
    // validate checks every frame: a radius that reaches 0 at frame 1.
    write_file(dir + "/cfg.yaml",
               fp::test::replace_once(animated, "{0: 0.75, 2: 0.875}", "{0: 0.5, 2: -0.5}"));
    r = run_cli({"validate", "--quiet", dir + "/cfg.yaml", "-o", dir + "/c.png"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err,
              dir +
                  "/cfg.yaml:16:5: renderer.maps[0].shape.radius: must be > 0, got 0 (animation frame 1)\n");
}

struct Bad {
    const char* name;
    std::string animation;
    std::string expected;
    std::vector<std::string> args = {"animate", "--quiet", "bad.yaml", "-o", "f/%04d.png"};
};

TEST(Animate, BadAnimationSectionsAreOneExactLine) {
    // Lines: the base config is 12 lines; "animation:" is line 13.
    // An animation that is right, for the cases whose fault is on the command line.
    const std::string three_frames = "animation:\n  frames: 3\n  keys: {renderer.seed: {0: 1}}\n";
    const std::vector<Bad> cases = {
        {"not_a_map", "animation: 3\n",
         "bad.yaml:13:12: animation: expected a mapping (frames, fps, "
         "interpolation, loop, keys), got '3'"},
        {"unknown_key", "animation:\n  frame: 3\n",
         "bad.yaml:14:3: animation: unknown key 'frame' (did you mean 'frames'?)"},
        {"no_frames", "animation:\n  keys: {renderer.seed: {0: 1}}\n",
         "bad.yaml:13:1: animation: missing 'frames:' (the number of frames)"},
        {"zero_frames", "animation:\n  frames: 0\n  keys: {renderer.seed: {0: 1}}\n",
         "bad.yaml:14:11: animation.frames: expected a whole number from 1 to 100000, got '0'"},
        {"interpolation",
         "animation:\n  frames: 3\n  interpolation: cubic\n  keys: {renderer.seed: {0: 1}}\n",
         "bad.yaml:15:18: animation.interpolation: expected linear, smooth or catmull-rom, got 'cubic'"},
        {"loop", "animation:\n  frames: 3\n  loop: yes\n  keys: {renderer.seed: {0: 1}}\n",
         "bad.yaml:15:9: animation.loop: expected true or false, got 'yes'"},
        {"no_keys", "animation:\n  frames: 3\n  keys: {}\n",
         "bad.yaml:15:9: animation.keys: expected a mapping of parameter paths to keyframes {frame: value, "
         "...}, "
         "got an empty mapping"},
        {"frame_out_of_range", "animation:\n  frames: 3\n  keys:\n    renderer.seed: {0: 1, 3: 2}\n",
         "bad.yaml:16:27: animation.keys.renderer.seed: keyframe '3': expected a frame number from 0 to 2 "
         "(frames: 3)"},
        {"frame_not_a_number", "animation:\n  frames: 3\n  keys:\n    renderer.seed: {0: 1, end: 2}\n",
         "bad.yaml:16:27: animation.keys.renderer.seed: keyframe 'end': expected a frame number from 0 to 2 "
         "(frames: 3)"},
        {"frame_twice", "animation:\n  frames: 3\n  keys:\n    renderer.seed: {1: 1, 01: 2}\n",
         "bad.yaml:16:27: animation.keys.renderer.seed: frame 1 is keyed twice"},
        {"not_numeric", "animation:\n  frames: 3\n  keys:\n    renderer.seed: {0: 1, 2: many}\n",
         "bad.yaml:16:30: animation.keys.renderer.seed: frame 2: expected a number, a list of numbers or a "
         "colour \"#rrggbb\", got 'many'"},
        {"shapes_differ",
         "animation:\n  frames: 3\n  keys:\n    renderer.view: {0: [-1, 1, -1, 1], 2: [-1, 1]}\n",
         "bad.yaml:16:43: animation.keys.renderer.view: frame 2: a value of shape [n, n] where the first "
         "keyframe "
         "has [n, n, n, n] (n: a number; a colour is [n, n, n])"},
        {"not_renderer", "animation:\n  frames: 3\n  keys:\n    output.bit_depth: {0: 8, 2: 16}\n",
         "bad.yaml:16:5: animation.keys.output.bit_depth: expected a parameter path under renderer: (as "
         "--set "
         "takes it, e.g. renderer.seed)"},
        {"index_out_of_range",
         "animation:\n  frames: 3\n  keys:\n    renderer.maps[9].shape.radius: {0: 1}\n",
         "bad.yaml:16:5: animation.keys.renderer.maps[9].shape.radius: index 9 out of range ('renderer.maps' "
         "has "
         "3 items)"},
        {"unknown_parameter", "animation:\n  frames: 3\n  keys:\n    renderer.maps[0].shape.radus: {0: 1}\n",
         "bad.yaml:16:5: renderer.maps[0].shape: unknown parameter 'radus' for circle (did you mean "
         "'radius'?) "
         "(animation frame 0)"},
        {"no_animation", "",
         "bad.yaml:1:1: no 'animation:' section (frames, keys: see fixpoint animate --help)"},
        {"pattern",
         three_frames,
         "-o 'f.png': expected a file name with one frame number, %d or %0Nd, as frames/%04d.png",
         {"animate", "--quiet", "bad.yaml", "-o", "f.png"}},
        {"range",
         three_frames,
         "--frames '2..5': expected A..B (or one frame K) with 0 <= A <= B <= 2 (the animation has 3 frames)",
         {"animate", "--quiet", "bad.yaml", "-o", "f/%d.png", "--frames", "2..5"}},
        // Tiles for PNG frames: refused at output.tiled before the first frame renders.
        {"tiled_png",
         three_frames + "output: {tiled: true}\n",
         "bad.yaml:16:17: output.tiled: 'f/0.png': only TIFF and EXR images have tiles (write .tif or .exr)",
         {"animate", "--quiet", "bad.yaml", "-o", "f/%d.png"}},
        {"video_ext",
         three_frames,
         "--video 'v.avi': expected a .mp4, .mkv, .mov or .gif file",
         {"animate", "--quiet", "bad.yaml", "-o", "f/%d.png", "--video", "v.avi"}},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        EXPECT_EQ(run_bad_input(std::string("animate_bad_") + c.name, base + c.animation, c.args),
                  c.expected);
    }
    // A value out of range between the keys: at the key's path, with the frame.
    const std::string mid =
        "animation:\n  frames: 3\n  keys:\n    renderer.maps[0].shape.radius: {0: 0.5, 2: -0.5}\n";
    EXPECT_EQ(
        run_bad_input("animate_bad_mid", base + mid, {"animate", "--quiet", "bad.yaml", "-o", "f/%d.png"}),
        "bad.yaml:16:5: renderer.maps[0].shape.radius: must be > 0, got 0 (animation frame 1)");
}

TEST(Animate, VideoHasEveryFrame) {
    if (!have("ffmpeg") || !have("ffprobe")) GTEST_SKIP() << "ffmpeg is not installed (setup.sh installs it)";
    const std::string dir = scratch_dir("animate_video");
    write_file(dir + "/cfg.yaml", animated);
    auto r = run_cli(
        {"animate", "--quiet", dir + "/cfg.yaml", "-o", dir + "/f/%03d.png", "--video", dir + "/out.mp4"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(
        shell("ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames,width,"
              "height -of csv=p=0 '" +
              dir + "/out.mp4'"),
        "64,64,3\n");
    // Not replaced without --force; a part of the frames with it.
    r = run_cli(
        {"animate", "--quiet", dir + "/cfg.yaml", "-o", dir + "/f/%03d.png", "--video", dir + "/out.mp4"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "--video: '" + dir + "/out.mp4' exists: add --force to replace it\n");
    r = run_cli({"animate", "--quiet", "--force", dir + "/cfg.yaml", "-o", dir + "/f/%03d.png", "--frames",
                 "1..2", "--video", dir + "/out.mp4"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(frames_in(dir + "/out.mp4"), "2\n");
    // A GIF too.
    r = run_cli(
        {"animate", "--quiet", dir + "/cfg.yaml", "-o", dir + "/f/%03d.png", "--video", dir + "/out.gif"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(frames_in(dir + "/out.gif"), "3\n");
}

TEST(Animate, MissingOrFailingFfmpegIsOneLine) {
    const std::string dir = scratch_dir("animate_ffmpeg");
    write_file(dir + "/cfg.yaml", animated);
    fs::create_directories(dir + "/bin");
    {
        PathFor path(dir + "/bin"); // no ffmpeg there: refused before any frame is rendered
        const auto r = run_cli(
            {"animate", "--quiet", dir + "/cfg.yaml", "-o", dir + "/f/%d.png", "--video", dir + "/out.mp4"});
        EXPECT_EQ(r.rc, 2);
        EXPECT_EQ(r.err, "--video: ffmpeg not found on PATH (Debian: apt-get install ffmpeg)\n");
        EXPECT_FALSE(fs::exists(dir + "/f"));
    }
    // An ffmpeg that fails: its last line, and no video left behind.
    write_file(dir + "/bin/ffmpeg",
               "#!/bin/sh\necho 'some detail' >&2\necho 'Unknown encoder libx264' >&2\nexit 1\n");
    fs::permissions(dir + "/bin/ffmpeg", fs::perms::owner_all);
    {
        const std::string saved = std::getenv("PATH") ? std::getenv("PATH") : "";
        PathFor path(dir + "/bin:" + saved);
        const auto r = run_cli(
            {"animate", "--quiet", dir + "/cfg.yaml", "-o", dir + "/f/%d.png", "--video", dir + "/out.mp4"});
        EXPECT_EQ(r.rc, 2);
        EXPECT_EQ(r.err, "--video: ffmpeg failed (exit status 1): Unknown encoder libx264\n");
    }
    EXPECT_TRUE(fs::exists(dir + "/f/2.png"));
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_TRUE(e.path().filename() == "cfg.yaml" || e.path().filename() == "bin" ||
                    e.path().filename() == "f")
            << e.path();
}

} // namespace
