// `render --draft` and `fixpoint watch`: a draft is the same recipe made small (its image
// renders again to the same bytes), and watch renders a draft, then the full image, at each
// save, and keeps the last good image when a save is refused.
#include "cli.hpp"
#include "configs.hpp"

#include <fixpoint/host/job/draft.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <filesystem>
#include <functional>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace fp::test;
namespace fs = std::filesystem;

namespace {

// Three circles at 256 x 128: a draft is 64 x 32 with 1/16 of the points.
const std::string config =
    "# three circles\n" + chaos_game({"width: 256", "height: 128", "view: [-3.2, 3.2, -1.6, 1.6]",
                                      "points: 160000", "chains: 16", "seed: 5"},
                                     three_circles("0.9", true));

std::string recipe_of(const std::string& image) {
    const auto r = run_cli({"recipe", image});
    return r.rc == 0 ? r.out : "";
}

// Wait (up to 60 s: the sanitizer build is slow) for `ok`; false when it never held.
bool eventually(const std::function<bool()>& ok) {
    for (int i = 0; i < 600; ++i) {
        if (ok()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
}

} // namespace

TEST(Draft, FactorsOfThePreview) {
    EXPECT_EQ(fp::host::preview_factors(512, 512), (std::vector<int>{8, 4, 2, 1}));
    EXPECT_EQ(fp::host::preview_factors(100, 300), (std::vector<int>{8, 4, 2, 1}));
    EXPECT_EQ(fp::host::preview_factors(100, 100), (std::vector<int>{2, 1}));
    EXPECT_EQ(fp::host::preview_factors(40, 30), (std::vector<int>{1}));
}

TEST(Draft, SmallerSameRecipeAndItsBytesAgain) {
    const std::string dir = scratch_dir("draft_render");
    write_file(dir + "/c.yaml", config);
    const auto r = run_cli({"render", "--quiet", "--draft", dir + "/c.yaml", "-o", dir + "/d.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const std::string recipe = recipe_of(dir + "/d.png");
    EXPECT_NE(recipe.find("width: 64\n"), std::string::npos) << recipe;
    EXPECT_NE(recipe.find("height: 32\n"), std::string::npos) << recipe;
    EXPECT_NE(recipe.find("points: 10000\n"), std::string::npos) << recipe; // 160000 / 16
    EXPECT_NE(recipe.find("chains: 16\n"), std::string::npos) << recipe;
    // The draft is an ordinary recipe: rendering its image gives it again, byte for byte.
    ASSERT_EQ(run_cli({"render", "--quiet", dir + "/d.png", "-o", dir + "/again.png"}).rc, 0);
    EXPECT_EQ(read_file(dir + "/d.png"), read_file(dir + "/again.png"));
}

TEST(Draft, NamedBesideTheFullRender) {
    const std::string dir = scratch_dir("draft_name");
    write_file(dir + "/c.yaml", config + "output: {path: " + dir + "/full.png}\n");
    ASSERT_EQ(run_cli({"render", "--quiet", "--draft", dir + "/c.yaml"}).rc, 0);
    EXPECT_TRUE(fs::exists(dir + "/full-draft.png"));
    EXPECT_FALSE(fs::exists(dir + "/full.png"));
}

TEST(Draft, OrbitTrapTakesOneSample) {
    const std::string dir = scratch_dir("draft_orbit_trap");
    const auto r = run_cli({"render", "--quiet", "--draft",
                            fp::test::source_dir() + "/configs/orbit-trap/fig5a.yaml", "-o", dir + "/d.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const std::string recipe = recipe_of(dir + "/d.png");
    EXPECT_NE(recipe.find("samples: 1\n"), std::string::npos) << recipe;
    EXPECT_NE(recipe.find("width: 200\n"), std::string::npos) << recipe; // 800 / 4
}

TEST(Draft, NotForPrint) {
    const std::string dir = scratch_dir("draft_print");
    write_file(dir + "/c.yaml", config);
    const auto r = run_cli({"render", "--draft", "--dpi", "300", dir + "/c.yaml", "-o", dir + "/d.png"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "--draft: a quick small image: not with --dpi or --print-size\n");
    EXPECT_FALSE(fs::exists(dir + "/d.png"));
}

// `fixpoint watch CFG -o OUT --threads 1` in the background, its stderr in LOG.
pid_t start_watch(const std::string& cfg, const std::string& out, const std::string& log) {
    const std::string bin = fp::test::fixpoint_bin(); // (before the fork: no allocation after it)
    const pid_t pid = fork();
    if (pid == 0) {
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(fd, 2);
        ::execl(bin.c_str(), bin.c_str(), "watch", cfg.c_str(), "-o", out.c_str(), "--threads", "1",
                static_cast<char*>(nullptr));
        ::_exit(127);
    }
    return pid;
}

// Kills a watch a failed assertion left running, so that it cannot outlive the test.
struct Reaper {
    pid_t& pid; // (-1 once interrupt() has reaped it)
    ~Reaper() {
        if (pid <= 0) return;
        ::kill(pid, SIGKILL);
        ::waitpid(pid, nullptr, 0);
    }
};

// SIGINT, and the exit status (-1: did not exit normally).
int interrupt(pid_t& pid) {
    ::kill(pid, SIGINT);
    int status = 0;
    const bool ended = ::waitpid(pid, &status, 0) == pid;
    if (ended) pid = -1;
    if (!ended || !WIFEXITED(status)) return -1;
    return WEXITSTATUS(status);
}

// How many times `needle` is in `text`.
std::size_t count(const std::string& text, const std::string& needle) {
    std::size_t n = 0;
    for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
    return n;
}

// watch: a draft then the full image at start; a save renders the new version; a refused
// save prints the CLI's line and leaves the last good image; SIGINT ends it with 0.
TEST(Watch, RendersEachSaveAndKeepsTheLastGoodImage) {
    const std::string dir = scratch_dir("watch");
    const std::string cfg = dir + "/c.yaml", out = dir + "/w.png", log = dir + "/log.txt";
    write_file(cfg, config);
    pid_t pid = start_watch(cfg, out, log);
    ASSERT_GE(pid, 0);
    const Reaper reaper{pid};
    const auto has = [&](const std::string& needle) {
        return [&, needle] { return read_file(log).find(needle) != std::string::npos; };
    };
    ASSERT_TRUE(eventually(has("w.png: full 256x128"))) << read_file(log);
    EXPECT_NE(read_file(log).find("w.png: draft 64x32, 10000 points"), std::string::npos) << read_file(log);
    const std::string first = read_file(out);

    // A new radius: the full image of the new version, the same bytes as render gives.
    write_file(cfg, fp::test::replace_once(config, "radius: 0.9}, colour: [1", "radius: 0.8}, colour: [1"));
    ASSERT_TRUE(eventually([&] {
        return recipe_of(out).find("radius: 0.8") != std::string::npos &&
               recipe_of(out).find("width: 256") != std::string::npos;
    })) << read_file(log);
    ASSERT_EQ(run_cli({"render", "--quiet", cfg, "-o", dir + "/cli.png"}).rc, 0);
    EXPECT_EQ(read_file(out), read_file(dir + "/cli.png"));
    EXPECT_NE(read_file(out), first);

    // A typo: the CLI's error line, and the image stays.
    const std::string good = read_file(out);
    write_file(cfg, fp::test::replace_once(config, "  seed: 5", "  sede: 5"));
    ASSERT_TRUE(eventually(has("c.yaml:9:3: renderer: unknown parameter 'sede' for chaos-game")))
        << read_file(log);
    EXPECT_EQ(read_file(out), good);

    // A version whose full image is refused (memory) before anything is written: not even its
    // draft (which alone would fit) replaces the last good image.
    write_file(cfg, fp::test::replace_once(fp::test::replace_once(config, "width: 256", "width: 60000"),
                                           "height: 128", "height: 60000"));
    ASSERT_TRUE(eventually(has("c.yaml:3:3: renderer: ")));
    EXPECT_NE(read_file(log).find(" of memory with 1 thread"), std::string::npos) << read_file(log);
    EXPECT_EQ(read_file(out), good);
    EXPECT_EQ(read_file(log).find("draft 16384x16384"), std::string::npos) << read_file(log);

    EXPECT_EQ(interrupt(pid), 0) << read_file(log);
}

// A save while a long render runs cancels it and renders the new version; Ctrl-C during a
// render ends watch like Ctrl-C while it waits (exit 0, no "interrupted" line).
TEST(Watch, ASaveDuringARenderStartsTheNewVersion) {
    const std::string dir = scratch_dir("watch_during");
    const std::string cfg = dir + "/c.yaml", out = dir + "/w.png", log = dir + "/log.txt";
    const std::string slow = fp::test::replace_once(config, "points: 160000", "points: 4000000000");
    write_file(cfg, slow);
    pid_t pid = start_watch(cfg, out, log);
    ASSERT_GE(pid, 0);
    const Reaper reaper{pid};
    ASSERT_TRUE(eventually([&] { return read_file(log).find("watching") != std::string::npos; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(300)); // (the draft of 2.5e8 points runs)
    write_file(cfg, config);
    ASSERT_TRUE(eventually([&] {
        return read_file(log).find("w.png: full 256x128, 160000 points") != std::string::npos;
    })) << read_file(log);
    EXPECT_EQ(count(read_file(log), "w.png: full"), 1u) << read_file(log); // the slow one never finished
    EXPECT_EQ(recipe_of(out).find("points: 4000000000"), std::string::npos);

    write_file(cfg, slow);
    std::this_thread::sleep_for(std::chrono::milliseconds(500)); // (its draft runs)
    EXPECT_EQ(interrupt(pid), 0) << read_file(log);
    EXPECT_EQ(read_file(log).find("interrupted"), std::string::npos) << read_file(log);
}

// A config watch will never read (too large, as render refuses it) says why at the start.
TEST(Watch, SaysWhyItCannotReadTheConfig) {
    const std::string dir = scratch_dir("watch_large");
    write_file(dir + "/c.yaml", config + "# " + std::string(5u << 20, 'x') + "\n");
    const auto rendered = run_cli({"render", dir + "/c.yaml", "-o", dir + "/r.png"});
    ASSERT_EQ(rendered.rc, 2);
    const auto r = run_cli({"watch", dir + "/c.yaml", "-o", dir + "/w.png"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, rendered.err); // one line, the CLI's
    EXPECT_FALSE(fs::exists(dir + "/w.png"));
}

TEST(Watch, RefusesVectorOutput) {
    const std::string dir = scratch_dir("watch_svg");
    write_file(dir + "/c.yaml", config);
    const auto r = run_cli({"watch", dir + "/c.yaml", "-o", dir + "/w.svg"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err,
              "cannot write '" + dir + "/w.svg': watch writes images (.png, .exr, .tif), not SVG or PDF\n");
}

TEST(Watch, RefusesToWriteOverTheConfig) {
    const std::string dir = scratch_dir("watch_self");
    write_file(dir + "/c.yaml", config);
    const auto r = run_cli({"watch", dir + "/c.yaml", "-o", dir + "/c.yaml"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "cannot write '" + dir + "/c.yaml': it is the config being watched\n");
}
