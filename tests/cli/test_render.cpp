// End-to-end behaviour of `fixpoint render` and friends, as a user runs them.
#include "cli.hpp"
#include "configs.hpp"

#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <spawn.h>
#include <sys/wait.h>
#include <thread>

using namespace fp::test;
namespace fs = std::filesystem;

extern char** environ;

namespace {

const std::string three_circles = chaos_game(
    {"width: 96", "height: 80", "view: [-1.6, 1.6, -1.4, 1.4]", "points: 300000", "chains: 300", "seed: 7"},
    fp::test::three_circles("0.9", true) + "    - {type: inversion, shape: {type: star-polygon, points: 5, "
                                           "outer_radius: 0.35, inner_radius: 0.2}, weight: 0.5}\n");

std::string render(const std::string& dir, const std::string& out, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"render", "--quiet", dir + "/cfg.yaml", "-o", dir + "/" + out};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(r.err, "");
    return read_file(dir + "/" + out);
}

double lit_fraction(const std::string& path) {
    const fp::Image img = fp::host::read_image(path);
    std::size_t lit = 0;
    for (std::size_t i = 0; i < img.pixels.size(); i += std::size_t(img.channels)) {
        bool any = false;
        for (int c = 0; c < std::min(img.channels, 3); ++c)
            any = any || img.pixels[i + std::size_t(c)] > 0.02f;
        lit += any;
    }
    return double(lit) / double(img.pixels.size() / std::size_t(img.channels));
}

TEST(Render, SameBytesOnOneAndTwoThreads) {
    const auto dir = scratch_dir("determinism");
    write_file(dir + "/cfg.yaml", three_circles);
    const auto one = render(dir, "one.png", {"--threads", "1"});
    const auto two = render(dir, "two.png", {"--threads", "2"});
    const auto three = render(dir, "three.png", {"--threads", "3"});
    ASSERT_FALSE(one.empty());
    EXPECT_TRUE(one == two);
    EXPECT_TRUE(one == three);
    EXPECT_GT(lit_fraction(dir + "/one.png"), 0.05);
    // The double-precision path is deterministic too.
    const auto d1 = render(dir, "d1.png", {"--threads", "1", "--set", "renderer.precision=double"});
    const auto d2 = render(dir, "d2.png", {"--threads", "2", "--set", "renderer.precision=double"});
    EXPECT_TRUE(d1 == d2);
    // So is the hits-only path (a colourer that needs no colour: 32-bit hit counters).
    const std::string density = "renderer.colourer={type: density}";
    const auto h1 = render(dir, "h1.png", {"--threads", "1", "--set", density});
    const auto h2 = render(dir, "h2.png", {"--threads", "2", "--set", density});
    const auto h3 =
        render(dir, "h3.png", {"--threads", "2", "--set", density, "--set", "renderer.precision=double"});
    ASSERT_FALSE(h1.empty());
    EXPECT_TRUE(h1 == h2);
    EXPECT_FALSE(h1 == one);
    EXPECT_GT(lit_fraction(dir + "/h1.png"), 0.05);
    EXPECT_FALSE(h3.empty());
}

TEST(Render, SeedChangesTheImage) {
    const auto dir = scratch_dir("seed");
    write_file(dir + "/cfg.yaml", three_circles);
    const auto a = render(dir, "a.png");
    const auto b = render(dir, "b.png", {"--set", "renderer.seed=8"});
    EXPECT_FALSE(a == b);
}

TEST(Render, RecipeRoundTripReproducesTheImage) {
    const auto dir = scratch_dir("recipe");
    write_file(dir + "/cfg.yaml", three_circles);
    render(dir, "first.png", {"--set", "renderer.maps[3].weight=2"});
    const auto r = run_cli({"recipe", dir + "/first.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    // Every default is filled in, with the version and the seed.
    EXPECT_NE(r.out.find("fixpoint_version:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("seed: 7"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("skip: 20"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("iteration:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("weight: 2"), std::string::npos) << r.out;
    write_file(dir + "/recipe.yaml", r.out);
    const auto again = run_cli({"render", "--quiet", dir + "/recipe.yaml", "-o", dir + "/second.png"});
    ASSERT_EQ(again.rc, 0) << again.err;
    EXPECT_TRUE(read_file(dir + "/first.png") == read_file(dir + "/second.png"));
    // The recipe of the re-render is the same recipe.
    EXPECT_EQ(run_cli({"recipe", dir + "/second.png"}).out, r.out);
}

// FNV-1a (64 bits) of a file, written out here independently of pipeline.cpp's.
std::string fnv1a64(const std::string& path) {
    std::uint64_t h = 14695981039346656037ull;
    for (const char c : read_file(path)) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

// A recipe records every plugin the render used, "VERSION fnv1a64:HASH" of its file; a
// re-render with another version or build of one says so in one line, and still renders.
TEST(Render, RecipeRecordsThePluginsAndWarnsWhenOneDiffers) {
    const auto dir = scratch_dir("recipe_plugins");
    write_file(dir + "/cfg.yaml", three_circles);
    render(dir, "first.png");
    const auto r = run_cli({"recipe", dir + "/first.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto plugins =
        fs::path(fixpoint_bin()).parent_path().parent_path() / "lib" / "fixpoint" / "plugins";
    const std::string circle = "1.0.0 fnv1a64:" + fnv1a64((plugins / "circle.so").string());
    for (const char* name : {"chaos-game", "inversion", "circle"})
        EXPECT_NE(r.out.find(std::string("  ") + name + ": \"1.0.0 fnv1a64:" +
                             fnv1a64((plugins / (std::string(name) + ".so")).string()) + "\"\n"),
                  std::string::npos)
            << name << "\n"
            << r.out;
    // The same plugins: nothing to say.
    write_file(dir + "/same.yaml", r.out);
    auto again = run_cli({"render", "--quiet", dir + "/same.yaml", "-o", dir + "/same.png"});
    EXPECT_EQ(again.rc, 0);
    EXPECT_EQ(again.err, "");
    // Another build of circle.
    write_file(dir + "/other.yaml", fp::test::replace_once(r.out, "circle: \"" + circle + "\"",
                                                           "circle: \"0.9.0 fnv1a64:0123456789abcdef\""));
    again = run_cli({"render", "--quiet", dir + "/other.yaml", "-o", dir + "/other.png"});
    EXPECT_EQ(again.rc, 0);
    EXPECT_EQ(again.err,
              "warning: plugin 'circle' is " + circle +
                  ", the recipe was made with 0.9.0 fnv1a64:0123456789abcdef: the image may differ\n");
    EXPECT_TRUE(read_file(dir + "/same.png") == read_file(dir + "/other.png"));
    // A record that is not a mapping of names to scalars is refused where it stands.
    write_file(dir + "/bad.yaml", fp::test::replace_once(r.out, "circle: \"" + circle + "\"", "circle: [1]"));
    again = run_cli({"render", "--quiet", dir + "/bad.yaml", "-o", dir + "/bad.png"});
    EXPECT_EQ(again.rc, 2);
    EXPECT_NE(again.err.find(": plugins.circle: expected 'VERSION HASH', got "), std::string::npos)
        << again.err;
}

TEST(Render, FormatsFromTheExtension) {
    const auto dir = scratch_dir("formats");
    write_file(dir + "/cfg.yaml", three_circles);
    for (const char* name : {"a.png", "a.exr", "a.tif", "a.tiff"}) {
        render(dir, name);
        const auto r = run_cli({"recipe", dir + "/" + name});
        EXPECT_EQ(r.rc, 0) << name << ": " << r.err;
        EXPECT_NE(r.out.find("type: chaos-game"), std::string::npos) << name;
    }
    EXPECT_GT(lit_fraction(dir + "/a.exr"), 0.05);
    // 16-bit PNG through the config's output section.
    write_file(dir + "/cfg.yaml", std::string(three_circles) + "output:\n  bit_depth: 16\n");
    render(dir, "b16.png");
    const fp::Image a = fp::host::read_image(dir + "/a.png"), b = fp::host::read_image(dir + "/b16.png");
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    double max_diff = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        max_diff = std::max(max_diff, double(std::fabs(a.pixels[i] - b.pixels[i])));
    EXPECT_LE(max_diff, 0.5 / 255 + 1e-6); // same image, finer steps
}

TEST(Render, DefaultOutputPathComesFromTheConfig) {
    const auto dir = scratch_dir("default_output");
    write_file(dir + "/cfg.yaml", std::string(three_circles) + "output:\n  path: " + dir + "/named.png\n");
    const auto r = run_cli({"render", "--quiet", dir + "/cfg.yaml"});
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir + "/named.png"));
}

TEST(Render, SummaryLine) {
    const auto dir = scratch_dir("summary");
    write_file(dir + "/cfg.yaml", three_circles);
    const auto r = run_cli({"render", dir + "/cfg.yaml", "-o", dir + "/x.png", "--threads", "2"});
    EXPECT_EQ(r.rc, 0);
    // Not a terminal: no progress bar, just the summary.
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("300000 points in "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("points/s, 2 threads, "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("restarted chain"), std::string::npos) << r.err;
}

TEST(Render, ValidateRendersNothing) {
    const auto dir = scratch_dir("validate");
    write_file(dir + "/cfg.yaml", three_circles);
    auto r = run_cli({"validate", dir + "/cfg.yaml", "-o", dir + "/x.png"});
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/x.png"));
    write_file(dir + "/bad.yaml", std::string(three_circles) + "  colour: 1\n");
    r = run_cli({"validate", dir + "/bad.yaml"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, dir + "/bad.yaml:14:3: renderer: unknown parameter 'colour' for chaos-game (did you "
                           "mean 'colourer'?)\n");
}

TEST(Render, CtrlCStopsWithinASecondAndLeavesNoFile) {
    const auto dir = scratch_dir("interrupt");
    write_file(dir + "/cfg.yaml", three_circles);
    // Beside two busy processes (a loaded machine): the bound is on the CPU time the render
    // spends after the signal, which they do not inflate (its 2 threads stop at their next
    // poll); the clock only bounds a hang.
    const fp::test::BusyLoad load;
    const auto r = fp::test::interrupt_cli({"render", "--quiet", "cfg.yaml", "-o", "never.png", "--set",
                                            "renderer.points=100000000000", "--threads", "2"},
                                           dir, 0.7);
    ASSERT_FALSE(r.hung) << "render did not stop within 120 s of SIGINT";
    EXPECT_LT(r.cpu, fp::test::cli_address_space_limited() ? 1.0 : 3.0) << r.wall << " s on the clock";
    EXPECT_EQ(r.rc, 130);
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename(), "cfg.yaml") << e.path();
}

TEST(Render, FailedRenderKeepsThePreviousFile) {
    const auto dir = scratch_dir("atomic");
    write_file(dir + "/cfg.yaml", three_circles);
    render(dir, "keep.png");
    const auto before = read_file(dir + "/keep.png");
    const auto r = run_cli(
        {"render", "--quiet", dir + "/cfg.yaml", "-o", dir + "/keep.png", "--set", "renderer.width=-3"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_TRUE(read_file(dir + "/keep.png") == before);
}

TEST(Eval, CircleInversionByHand) {
    // Inversion in the circle |p| = 2: p' = 4 p / |p|^2.
    //   (1, 0) -> (4, 0);  (0, 4) -> (0, 1);  (1, 1) -> (2, 2);  (3, 4) -> (12/25, 16/25).
    const std::string t = "{type: inversion, shape: {type: circle, centre: [0, 0], radius: 2}}";
    auto r = run_cli({"eval", t}, "1 0\n0 4\n1 1\n3 4\n");
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(r.out, "4 0\n0 1\n2 2\n0.47999999999999998 0.64000000000000001\n"); // 12/25, 16/25 rounded
    // Two steps of an involution give the points back.
    r = run_cli({"eval", t, "--steps", "2"}, "1 0\n0 4\n1 1\n");
    EXPECT_EQ(r.out, "1 0\n0 4\n1 1\n");
    r = run_cli({"eval", t, "--scheme", "{type: picard}", "--steps", "0"}, "0.5 0.25\n");
    EXPECT_EQ(r.out, "0.5 0.25\n");
}

TEST(Eval, BadInput) {
    const std::string t = "{type: inversion, shape: {type: circle}}";
    auto r = run_cli({"eval", t}, "1 0\nfoo bar\n");
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "<stdin>:2: expected two finite numbers 'x y', got 'foo bar'\n");
    r = run_cli({"eval", "{type: inversion, shape: {type: circle, radius: 0}}"}, "1 0\n");
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "<transform>:1:49: transform.shape.radius: must be > 0, got 0\n");
    r = run_cli({"eval", "{type: circle}"}, "1 0\n");
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err,
              "<transform>:1:8: transform.type: 'circle' is a shape, but this slot expects a transform\n");
}

TEST(Plugins, ListAndDescribe) {
    auto r = run_cli({"plugins"});
    ASSERT_EQ(r.rc, 0);
    for (const char* name : {"bezier", "circle", "polygon", "star-polygon", "superformula", "inversion",
                             "picard", "map-colour", "flame", "chaos-game"})
        EXPECT_NE(r.out.find(std::string(" ") + name + " "), std::string::npos) << name;
    r = run_cli({"plugins", "--kind", "shape"});
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 5) << r.out;
    r = run_cli({"plugins", "--kind", "shapes"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "--kind: unknown kind 'shapes' (did you mean 'shape'?)\n");
    r = run_cli({"describe", "circle"});
    EXPECT_EQ(r.rc, 0);
    EXPECT_NE(r.out.find("radius           real; default 1; range (0, inf)"), std::string::npos) << r.out;
    r = run_cli({"describe", "circel"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "unknown plugin 'circel' (did you mean 'circle'?)\n");
}

// A file in a plugin folder that does not load is skipped with one warning line each, and
// every other plugin works (issue 13: one stale .so must not block every command); a config
// that asks for a plugin such a file would have provided fails naming the file, and
// `plugins --check` lists every file with its plugin or why it was refused.
TEST(Plugins, BrokenPluginFilesAreSkippedAndNamed) {
    const auto dir = scratch_dir("broken_plugins");
    write_file(dir + "/junk.so", "this is not a shared library");
    const std::string junk = "cannot load plugin '" + dir + "/junk.so': ";
    auto r = run_cli({"--plugin-dir", dir, "plugins"});
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(r.err.rfind("warning: plugin file skipped: " + junk, 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.out.find("shape             circle "), std::string::npos) << r.out;
    // A render that needs none of it runs.
    const std::string small = dir + "/small.yaml";
    write_file(small, three_circles);
    r = run_cli({"--plugin-dir", dir, "render", "-q", small, "-o", dir + "/small.png"});
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir + "/small.png"));
    // Asking for the plugin the file is named after names the file and why.
    r = run_cli({"--plugin-dir", dir, "describe", "junk"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err.substr(r.err.find('\n') + 1).rfind("plugin 'junk' is not available: " + junk, 0), 0u)
        << r.err;
    // --check: one line per file, the refused one with its reason; exit 1.
    r = run_cli({"--plugin-dir", dir, "plugins", "--check"});
    EXPECT_EQ(r.rc, 1);
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find(dir + "/junk.so: refused  " + junk), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("/circle.so: ok       circle\n"), std::string::npos) << r.out;

    // A real shared library that is not a plugin.
    const auto dir2 = scratch_dir("not_a_plugin");
    fs::copy_file(fs::path(fixpoint_bin()).parent_path().parent_path() / "lib" / "libfixpoint_sdk.so",
                  dir2 + "/sdk.so");
    r = run_cli({"--plugin-dir", dir2, "plugins"});
    EXPECT_EQ(r.rc, 0);
    EXPECT_EQ(r.err,
              "warning: plugin file skipped: '" + dir2 +
                  "/sdk.so' is not a fixpoint plugin (it exports no fixpoint_abi/fixpoint_descriptor)\n");

    // The same plugin under two names: listed once; a config that uses the name fails, naming
    // both files (which one is meant is not known), at the type's line and column.
    const auto dir3 = scratch_dir("duplicate");
    const auto plugins =
        fs::path(fixpoint_bin()).parent_path().parent_path() / "lib" / "fixpoint" / "plugins";
    fs::copy_file(plugins / "circle.so", dir3 + "/circle-copy.so");
    const std::string two = "two plugins named 'circle': '" + fs::canonical(plugins / "circle.so").string() +
                            "' and '" + dir3 + "/circle-copy.so'";
    r = run_cli({"--plugin-dir", dir3, "plugins"});
    EXPECT_EQ(r.rc, 0);
    EXPECT_EQ(r.err, "warning: plugin file skipped: " + two + "\n");
    r = run_cli({"--plugin-dir", dir3, "render", "-q", small, "-o", dir3 + "/small.png"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "warning: plugin file skipped: " + two + "\n" + small +
                         ":10:39: renderer.maps[0].shape.type: plugin 'circle' is not available: " + two +
                         "\n");
    EXPECT_FALSE(fs::exists(dir3 + "/small.png"));
}

// ------------------------------------------------------------------ every config renders
std::vector<std::string> all_configs() {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(fp::test::source_dir() + "/configs"))
        if (e.path().extension() == ".yaml" || e.path().extension() == ".flam3") // (flam3 genomes render too)
            out.push_back(fs::relative(e.path(), fp::test::source_dir() + "/configs").string());
    std::sort(out.begin(), out.end());
    return out;
}

class Configs : public testing::TestWithParam<std::string> {};

TEST_P(Configs, RendersAtSmallSize) {
    const std::string cfg = fp::test::source_dir() + "/configs/" + GetParam();
    std::string name = GetParam();
    std::replace(name.begin(), name.end(), '/', '_');
    const auto dir = scratch_dir("config_" + name);
    std::vector<std::string> args = {
        "render", "--quiet",           cfg, "-o", dir + "/out.png", "--set", "renderer.width=96",
        "--set",  "renderer.height=96"};
    // Small renders: fewer points for the point-plotting renderers.
    const std::string text = read_file(cfg);
    if (text.find("type: chaos-game") != std::string::npos)
        args.insert(args.end(), {"--set", "renderer.points=150000"});
    if (text.find("type: superfractal") != std::string::npos)
        args.insert(args.end(), {"--set", "renderer.points_per_buffer=20000"});
    const auto r = run_cli(args);
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_GT(lit_fraction(dir + "/out.png"), 0.01) << "the render is (nearly) black";
}

INSTANTIATE_TEST_SUITE_P(All, Configs, testing::ValuesIn(all_configs()),
                         [](const testing::TestParamInfo<std::string>& i) {
                             std::string s = i.param;
                             for (char& c : s)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return s;
                         });

} // namespace

namespace {

TEST(Collection, ChildrenAndContactSheet) {
    const auto dir = scratch_dir("collection");
    write_file(dir + "/cfg.yaml", three_circles);
    const auto r = run_cli({"render", "--quiet", dir + "/cfg.yaml", "-o", dir + "/sheet.png", "--vary",
                            "renderer.seed=3..5", "--columns", "3"});
    ASSERT_EQ(r.rc, 0) << r.err;
    // Each child is the render of its own recipe: the same bytes as a plain render with that seed.
    for (int k = 1; k <= 3; ++k) {
        const std::string child = dir + "/sheet-" + std::to_string(k) + ".png";
        render(dir, "plain.png", {"--set", "renderer.seed=" + std::to_string(k + 2)});
        EXPECT_TRUE(read_file(child) == read_file(dir + "/plain.png")) << child;
    }
    const fp::Image sheet = fp::host::read_image(dir + "/sheet.png");
    EXPECT_GT(sheet.width, 3 * 96);
    EXPECT_GT(sheet.height, 80);
    EXPECT_LT(sheet.height, 2 * 80); // one row of three
    EXPECT_GT(lit_fraction(dir + "/sheet.png"), 0.03);
    const auto rec = run_cli({"recipe", dir + "/sheet.png"});
    EXPECT_EQ(rec.out.rfind("# contact sheet: --vary renderer.seed=3..5", 0), 0u) << rec.out;
}

TEST(Collection, BadVaryIsRefusedBeforeRendering) {
    const auto dir = scratch_dir("collection_bad");
    write_file(dir + "/cfg.yaml", three_circles);
    auto r =
        run_cli({"render", "--quiet", dir + "/cfg.yaml", "-o", dir + "/s.png", "--vary", "renderer.seed"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "--vary renderer.seed: expected path.to.param=V1,V2,... or A..B\n");
    // The third value is bad: nothing at all is rendered.
    r = run_cli(
        {"render", "--quiet", dir + "/cfg.yaml", "-o", dir + "/s.png", "--vary", "renderer.width=50,60,-1"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err, "--vary renderer.width=-1: renderer.width: must be in [1, 65536], got -1\n");
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename(), "cfg.yaml") << e.path();
}

} // namespace

namespace {

// The example config of docs/configs.md is what users copy first: it must stay valid.
TEST(Docs, ExampleConfigValidates) {
    const std::string readme = read_file(fp::test::source_dir() + "/docs/configs.md");
    const auto begin = readme.find("# Three circles and a star");
    ASSERT_NE(begin, std::string::npos);
    const auto end = readme.find("```", begin);
    const auto dir = scratch_dir("readme");
    write_file(dir + "/example.yaml", readme.substr(begin, end - begin));
    const auto r = run_cli({"validate", "--quiet", dir + "/example.yaml", "-o", dir + "/x.png"});
    EXPECT_EQ(r.rc, 0) << r.err;
}

} // namespace

namespace {

TEST(Collection, AFailingChildLeavesNoFiles) {
    const auto dir = scratch_dir("collection_failing_child");
    write_file(dir + "/cfg.yaml", three_circles);
    const auto r = run_cli({"render", "--quiet", dir + "/cfg.yaml", "-o", dir + "/s.png", "--vary",
                            "renderer.view=[-1.5, 1.5, -1.5, 1.5],[100, 101, 100, 101]"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename(), "cfg.yaml") << e.path();
}

// A periodic list of two q-numbers survives the recipe (two plain numbers would read back as
// one q-number in a q-system).
TEST(Render, RecipeKeepsPeriodicListsOfQNumbers) {
    const auto dir = scratch_dir("recipe_qlist");
    write_file(dir + "/cfg.yaml",
               std::string(three_circles) +
                   "  iteration: {type: mann, numbers: {type: complex}, alpha: [[0.7, 0], [0.9, 0]]}\n");
    render(dir, "a.png");
    const auto rec = run_cli({"recipe", dir + "/a.png"});
    write_file(dir + "/again.yaml", rec.out);
    const auto r = run_cli({"render", "--quiet", dir + "/again.yaml", "-o", dir + "/b.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(read_file(dir + "/a.png") == read_file(dir + "/b.png")) << rec.out;
}

} // namespace
