// Renders beyond the memory budget (`fixpoint render --memory SIZE`), streamed to the output file
// band by band. chaos-game in strips (chaos-game/plan.cpp's "Strips"): an image whose
// histogram does not fit the budget is rendered strip by strip, every chain replayed per strip,
// and must come out as the same bytes as one pass. Checked on every colour path the renderer
// has: hits only with the fused step (density), colour with the fused step (flame, affine maps),
// map colours through an iteration scheme (generic step), last colours (set-colour, paper 02's
// Algorithm 2), the centre of mass (centroid-distance, double precision) and the lean path of a
// single orbit; each on 1 and 3 threads, against one pass on 2. A budget too small even for
// strips of one row is refused before rendering, with the least that works, and that least
// does work. orbit-trap in bands (orbit-trap.cpp's "Bands"): the same bytes as the whole image
// in PNG and TIFF (8 and 16 bits) and EXR, on 1 and 3 threads; mfs in bands likewise.
#include "cli.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

struct StripCase {
    const char* name;
    const char* config; ///< under the source tree
    const char* points;
    const char* memory; ///< small enough for several strips at this size
};

std::ostream& operator<<(std::ostream& os, const StripCase& c) { return os << c.name; }

class Strips : public ::testing::TestWithParam<StripCase> {};

TEST_P(Strips, SameBytesAsOnePass) {
    const StripCase& c = GetParam();
    const std::string dir = scratch_dir(std::string("strips_") + c.name);
    const std::string config = source_dir() + "/" + c.config;
    // (A quarter of the points under the sanitizers: the same strips, each chain's replay
    // shorter; set_colour_last took a minute there.)
    const unsigned long long n = std::stoull(c.points) / (cli_sanitized() ? 4 : 1);
    const std::string points = "renderer.points=" + std::to_string(n);
    const auto whole =
        run_cli({"render", "--quiet", "--threads", "2", config, "--set", points, "-o", dir + "/whole.png"});
    ASSERT_EQ(whole.rc, 0) << whole.err;
    for (const char* threads : {"1", "3"}) {
        const std::string out = dir + "/strips-" + threads + ".png";
        const auto r = run_cli(
            {"render", "--threads", threads, "--memory", c.memory, config, "--set", points, "-o", out});
        ASSERT_EQ(r.rc, 0) << r.err;
        // It did render in strips (the summary line says how), and they add up to one pass.
        EXPECT_NE(r.err.find(" strips of "), std::string::npos) << r.err;
        EXPECT_EQ(read_file(out), read_file(dir + "/whole.png"))
            << c.name << " on " << threads << " thread(s)";
    }
}

INSTANTIATE_TEST_SUITE_P(
    ChaosGame, Strips,
    ::testing::Values(StripCase{"density_fused", "bench/circles.yaml", "400000", "24M"},
                      StripCase{"flame_affine_fused", "bench/sierpinski.yaml", "400000", "24M"},
                      StripCase{"map_colour_scheme", "configs/iterations/fig5b.yaml", "400000", "24M"},
                      StripCase{"set_colour_last", "configs/inversion/fig6a.yaml", "400000", "30M"},
                      StripCase{"centroid_double", "configs/gumowski-mira/fig6b.yaml", "30000", "16M"},
                      StripCase{"single_orbit_lean", "bench/gm-orbit.yaml", "400000", "24M"}),
    [](const auto& info) { return std::string(info.param.name); });

// Too small for strips of one row: refused before anything renders, exit 2, nothing written,
// one line that says the least that works.
TEST(Strips, BudgetBelowOneRowIsRefused) {
    const std::string yaml = "renderer:\n  type: chaos-game\n  width: 1000\n  height: 800\n  points: 10000\n"
                             "  view: [-0.012, 1.012, -1.012, 0.012]\n  colourer: {type: density}\n  maps:\n"
                             "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}\n"
                             "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}\n"
                             "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, -0.5]}\n";
    const std::string line =
        run_bad_input("strips_too_small", yaml,
                      {"render", "--quiet", "--threads", "2", "--memory", "4M", "bad.yaml", "-o", "out.png"});
    EXPECT_EQ(
        line,
        "bad.yaml:2:3: renderer: a 1000x800 render needs at least 4.2 MiB of memory with 2 thread(s), in "
        "strips of one row; --memory gives 4.0 MiB");
    // (By hand: a strip of one row, per worker 1001 32-bit counters and 2 MiB of huge-page
    // alignment, plus 1000 hit counts of 8 bytes (density reads hit counts alone): 4.21 MB;
    // its 1000 pixels, 12 kB; the summary's 800 rows of 8 bytes; the workers' block state,
    // about 0.2 MB: 4.2 MiB. The image itself is never whole: the rows go to the file as each
    // strip is shaded.)
    // The least it names is enough (with what rounding to 0.1 MiB leaves: strips of four rows,
    // 28 kB a row, and the pass counting hits in strips of seven, 16 kB a row).
    const std::string dir = scratch_dir("strips_least");
    fp::test::write_file(dir + "/c.yaml", yaml);
    const auto r =
        run_cli({"render", "--threads", "2", "--memory", "4.3M", dir + "/c.yaml", "-o", dir + "/out.png"});
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(r.err.find("in 200 strips of 4 rows after 115 passes counting hits"), std::string::npos)
        << r.err;
}

TEST(Bands, OrbitTrapSameAsWhole) {
    const std::string dir = scratch_dir("bands_orbit_trap");
    const std::string config = source_dir() + "/configs/orbit-trap/fig6a.yaml";
    // Under ASan 4 samples per pixel (a square number, as the p4m pattern needs) rather than the
    // paper's 8, half the height and 3 threads alone: the same bands (fewer of them), a third of
    // the time (it was over two minutes).
    const bool sanitized = cli_sanitized();
    const std::vector<std::string> small = {
        "--set", "renderer.width=600",
        "--set", sanitized ? "renderer.height=200" : "renderer.height=400",
        "--set", sanitized ? "renderer.samples=4" : "renderer.samples=8"};
    auto render = [&](const std::string& out, std::vector<std::string> extra) {
        std::vector<std::string> args = {"render", config, "-o", dir + "/" + out};
        args.insert(args.end(), small.begin(), small.end());
        args.insert(args.end(), extra.begin(), extra.end());
        const auto r = run_cli(args);
        EXPECT_EQ(r.rc, 0) << r.err;
        return r.err;
    };
    for (const char* name : {"a.png", "b.tif"}) {
        for (const char* depth : {"8", "16"}) {
            const std::string bits = std::string("output.bit_depth=") + depth;
            render(std::string("whole-") + depth + name, {"--quiet", "--set", bits});
            for (const char* threads : {"3", "1"}) {
                if (sanitized && threads[0] == '1') continue;
                const std::string out = std::string("bands-") + threads + "-" + depth + name;
                // 1 MiB: bands of about 40 rows of 600 pixels (the whole image: 2.9 MB).
                const std::string err = render(out, {"--threads", threads, "--memory", "1M", "--set", bits});
                EXPECT_NE(err.find(" bands of "), std::string::npos) << err;
                EXPECT_EQ(read_file(dir + "/" + out), read_file(dir + "/whole-" + depth + name)) << out;
            }
        }
    }
    // EXR: the same bytes too (no time of writing in the header).
    render("whole.exr", {"--quiet"});
    render("bands.exr", {"--quiet", "--threads", "3", "--memory", "1M"});
    EXPECT_EQ(read_file(dir + "/bands.exr"), read_file(dir + "/whole.exr"));
}

// Tiled TIFF and EXR (output.tiled; by default images of more than 8192 x 8192 pixels): the
// streamed bands gather into rows of 256 x 256 tiles, with the same bytes as the whole image
// written in tiles; an image whose height and width are not whole tiles, bands that are not
// whole tiles either, 8 and 16 bits. output.tiled: false writes scanlines.
namespace {
bool tiff_is_tiled(const std::string& bytes) {
    // The TileWidth tag (322), little-endian, as SHORT or LONG, in the first directory.
    return bytes.find(std::string("\x42\x01\x03\x00", 4)) != std::string::npos ||
           bytes.find(std::string("\x42\x01\x04\x00", 4)) != std::string::npos;
}
bool exr_is_tiled(const std::string& bytes) {
    return bytes.find(std::string("tiles\0tiledesc\0", 15)) != std::string::npos;
}
} // namespace

TEST(Bands, TiledFilesSameAsWhole) {
    const std::string dir = scratch_dir("bands_tiled");
    const std::string config = source_dir() + "/configs/orbit-trap/fig6a.yaml";
    auto render = [&](const std::string& out, std::vector<std::string> extra) {
        std::vector<std::string> args = {"render",
                                         "--quiet",
                                         config,
                                         "-o",
                                         dir + "/" + out,
                                         "--set",
                                         "renderer.width=700",
                                         "--set",
                                         "renderer.height=530",
                                         "--set",
                                         "renderer.samples=1"};
        args.insert(args.end(), extra.begin(), extra.end());
        const auto r = run_cli(args);
        EXPECT_EQ(r.rc, 0) << r.err;
        return read_file(dir + "/" + out);
    };
    for (const char* depth : {"8", "16"}) {
        const std::string bits = std::string("output.bit_depth=") + depth;
        const std::string whole =
            render(std::string("whole-") + depth + ".tif", {"--set", bits, "--set", "output.tiled=true"});
        EXPECT_TRUE(tiff_is_tiled(whole));
        // 3 MiB: bands of 92 rows, cutting the tiles.
        const std::string bands =
            render(std::string("bands-") + depth + ".tif",
                   {"--set", bits, "--set", "output.tiled=true", "--memory", "3M", "--threads", "3"});
        EXPECT_TRUE(bands == whole) << depth << " bits";
        EXPECT_FALSE(tiff_is_tiled(render(std::string("lines-") + depth + ".tif", {"--set", bits})));
    }
    const std::string whole = render("whole.exr", {"--set", "output.tiled=true"});
    EXPECT_TRUE(exr_is_tiled(whole));
    EXPECT_TRUE(render("bands.exr", {"--set", "output.tiled=true", "--memory", "3M"}) == whole);
    EXPECT_FALSE(exr_is_tiled(render("lines.exr", {"--set", "output.tiled=false"})));
    // A chaos-game render in strips, tiled.
    const std::string fig = source_dir() + "/configs/inversion/fig6a.yaml";
    const std::vector<std::string> common = {
        "render", "--quiet", fig, "--set", "renderer.points=300000", "--set", "output.tiled=true"};
    auto chaos = [&](const std::string& out, std::vector<std::string> extra) {
        std::vector<std::string> args = common;
        args.insert(args.end(), {"-o", dir + "/" + out});
        args.insert(args.end(), extra.begin(), extra.end());
        const auto r = run_cli(args);
        EXPECT_EQ(r.rc, 0) << r.err;
        return read_file(dir + "/" + out);
    };
    EXPECT_TRUE(chaos("chaos-strips.tif", {"--memory", "30M"}) == chaos("chaos-whole.tif", {}));
}

// mfs (paper 05) draws its polygons band by band, the scene moved up by the band's first row: a
// shift by whole pixels, so Cairo covers every pixel as on the whole surface.
TEST(Bands, MfsSameAsWhole) {
    const std::string dir = scratch_dir("bands_mfs");
    for (const char* name : {"fig4-left", "fig5-left", "fig6-left"}) {
        const std::string config = source_dir() + "/configs/mfs/" + name + ".yaml";
        const std::string whole = dir + "/" + name + "-whole.png", bands = dir + "/" + name + "-bands.png";
        const auto w = run_cli({"render", "--quiet", config, "-o", whole});
        ASSERT_EQ(w.rc, 0) << w.err;
        const auto b = run_cli({"render", "--memory", "1M", config, "-o", bands});
        ASSERT_EQ(b.rc, 0) << b.err;
        EXPECT_NE(b.err.find(" bands of "), std::string::npos) << b.err;
        EXPECT_EQ(read_file(bands), read_file(whole)) << name;
    }
}

TEST(Strips, MemorySizeIsChecked) {
    const std::string yaml = "renderer:\n  type: chaos-game\n  points: 1000\n  maps:\n"
                             "    - {type: inversion, shape: {type: circle, centre: [0, 0], radius: 1}}\n"
                             "    - {type: inversion, shape: {type: circle, centre: [1.5, 0], radius: 1}}\n";
    EXPECT_EQ(
        run_bad_input("strips_size_word", yaml, {"render", "--memory", "lots", "bad.yaml", "-o", "out.png"}),
        "--memory 'lots': a size such as 8G, 512M or 1.5GiB (binary units: K, M, G, T)");
    EXPECT_EQ(
        run_bad_input("strips_size_unit", yaml, {"render", "--memory", "3Q", "bad.yaml", "-o", "out.png"}),
        "--memory '3Q': a size such as 8G, 512M or 1.5GiB (binary units: K, M, G, T)");
    EXPECT_EQ(
        run_bad_input("strips_size_tiny", yaml, {"render", "--memory", "12K", "bad.yaml", "-o", "out.png"}),
        "--memory '12K': at least 1M: a render needs more than that");
    EXPECT_EQ(run_bad_input(
                  "strips_size_vary", yaml,
                  {"render", "--memory", "1G", "--vary", "renderer.seed=1,2", "bad.yaml", "-o", "out.png"}),
              "--memory bounds one render (in strips): not with --vary, whose children render whole");
    // Units: binary, with or without B or iB, any case.
    const std::string dir = scratch_dir("strips_units");
    fp::test::write_file(dir + "/c.yaml", yaml);
    for (const char* size : {"1g", "1GiB", "1024M", "1048576k", "1073741824"})
        EXPECT_EQ(run_cli({"validate", "--quiet", "--memory", size, dir + "/c.yaml"}).rc, 0) << size;
}

} // namespace
