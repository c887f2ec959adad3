// flam3 genomes in fixpoint (docs/flam3.md): `fixpoint import` and `fixpoint render x.flam3`.
// Checked: a genome of flam3-genome renders directly and through its imported config to the
// same bytes; import is deterministic; the picture is flam3-render's own (camera, y axis,
// palette, variations, tone: its structural similarity to flam3's is above 0.9, or as high
// as that of flam3's own picture with other random numbers where noise keeps that lower, and
// far above the mirrored picture's); bad genomes get one positioned line, exit 2, and nothing written.
#include "cli.hpp"
#include "ssim.hpp"

#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

bool have(const char* tool) {
    return std::system((std::string("command -v ") + tool + " >/dev/null 2>&1").c_str()) == 0;
}

/// A random genome of flam3-genome (its seed fixes it), as flam3-render would read it.
std::string genome(const std::string& dir, int seed) {
    std::string path = dir + "/g" + std::to_string(seed) + ".flam3";
    const std::string cmd = "env seed=" + std::to_string(seed) + " flam3-genome > " + path + " 2>/dev/null";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return path;
}

TEST(Flam3Import, AGenomeRendersDirectlyAsItsConfigDoes) {
    if (!have("flam3-genome")) GTEST_SKIP() << "flam3-genome (Debian's flam3-utils) is not installed";
    const std::string dir = scratch_dir("flam3_import_direct");
    const std::string g = genome(dir, 11);
    const auto a = run_cli({"import", g, "-o", dir + "/a.yaml"});
    ASSERT_EQ(a.rc, 0) << a.err;
    // Deterministic: the same text twice (to standard output), the file's but for its output.
    const auto b = run_cli({"import", g}), c = run_cli({"import", g});
    ASSERT_EQ(b.rc, 0) << b.err;
    EXPECT_EQ(b.out, c.out);
    EXPECT_EQ(b.out + "output:\n  path: a.png\n", read_file(dir + "/a.yaml"));
    EXPECT_NE(read_file(dir + "/a.yaml").find("y_axis: down"), std::string::npos);
    // Again without --force: refused, the config kept.
    const auto again = run_cli({"import", g, "-o", dir + "/a.yaml"});
    EXPECT_EQ(again.rc, 2);
    const auto direct = run_cli({"render", "--quiet", g, "-o", dir + "/direct.png"});
    ASSERT_EQ(direct.rc, 0) << direct.err;
    const auto via = run_cli({"render", "--quiet", dir + "/a.yaml", "-o", dir + "/via.png"});
    ASSERT_EQ(via.rc, 0) << via.err;
    const fp::Image x = fp::host::read_image(dir + "/direct.png"), y = fp::host::read_image(dir + "/via.png");
    EXPECT_EQ(x.width, 100);
    EXPECT_EQ(x.pixels, y.pixels);
}

TEST(Flam3Import, ThePictureIsFlam3Renders) {
    if (!have("flam3-render")) GTEST_SKIP() << "flam3-render (Debian's flam3-utils) is not installed";
    const std::string dir = scratch_dir("flam3_import_parity");
    // Genomes flam3-genome made, kept as fixtures: two of its runs with the same seed give
    // different genomes.
    for (int seed : {3, 7, 19}) {
        const std::string g =
            fp::test::source_dir() + "/tests/fixtures/flam3/genome-" + std::to_string(seed) + ".flam3";
        // flam3-render at twice the genome's size (ss), 100 times its quality (qs), one thread,
        // twice with other random numbers (isaac_seed; by default it is the time): a picture
        // can be no closer to flam3's than flam3's own other one.
        auto flam3 = [&](const std::string& isaac) {
            const std::string out = dir + "/flam3-" + std::to_string(seed) + "-" + isaac + ".png";
            const std::string cmd = "cd " + dir + " && env ss=2 qs=100 nthreads=1 isaac_seed=" + isaac +
                                    " out=" + out + " flam3-render < " + g + " >/dev/null 2>&1";
            EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
            return fp::host::read_image(out);
        };
        const fp::Image f = flam3("one"), f2 = flam3("two");
        // The genome itself at that size and density (the genomes' quality is 1).
        const std::string ours = dir + "/ours-" + std::to_string(seed) + ".png";
        const auto r =
            run_cli({"render", "--quiet", g, "-o", ours, "--set", "renderer.width=" + std::to_string(f.width),
                     "--set", "renderer.height=" + std::to_string(f.height), "--set",
                     "renderer.points=" + std::to_string(100 * f.width * f.height)});
        ASSERT_EQ(r.rc, 0) << r.err;
        const fp::Image o = fp::host::read_image(ours);
        ASSERT_EQ(o.width, f.width);
        ASSERT_EQ(o.height, f.height);
        const std::vector<double> gf = grey(f), go = grey(o);
        std::vector<double> mirrored(go.size());
        for (int yy = 0; yy < o.height; ++yy)
            for (int xx = 0; xx < o.width; ++xx)
                mirrored[std::size_t(yy) * std::size_t(o.width) + std::size_t(xx)] =
                    go[std::size_t(o.height - 1 - yy) * std::size_t(o.width) + std::size_t(xx)];
        const double same = ssim(gf, go, o.width, o.height), own = ssim(gf, grey(f2), o.width, o.height),
                     flipped = ssim(gf, mirrored, o.width, o.height);
        // (Above 0.9, or no further than flam3's own other picture where noise keeps that below.)
        EXPECT_GT(same, std::min(0.9, own) - 0.02) << "seed " << seed << ": flam3's own " << own;
        EXPECT_GT(same, flipped + 0.1) << "seed " << seed << ": mirrored " << flipped;
    }
}

TEST(Flam3Import, BadGenomesGetOnePositionedLine) {
    const std::string dir = scratch_dir("flam3_import_bad");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"<flames>\n<flame size=\"64 64\" scale=\"20\">\n  <xform weight=\"1\" coefs=\"1 0 0 1 0 0\" "
         "julai=\"1\"/>\n"
         "</flame>\n</flames>\n",
         ":3:41: julai: unknown variation or xform attribute (did you mean 'julia'?)\n"},
        {"<flame size=\"64 64\">\n  <xform weight=\"1\" coefs=\"1 0 nan 1 0 0\"/>\n</flame>\n",
         ":2:21: coefs: 'nan' is not a finite number\n"},
        {"<flame size=\"640000 64\">\n  <xform weight=\"1\" coefs=\"1 0 0 1 0 0\"/>\n</flame>\n",
         ":1:8: size: width and height must be whole numbers from 1 to 65536\n"},
        {"<flame size=\"64 64\">\n  <xform weight=\"1\" coefs=\"1 0 0 1 0 0\"\n</flame>\n",
         ":2:1: malformed XML: XML_ERROR_PARSING_ELEMENT\n"},
        {"<flame size=\"64 64\">\n  <xform weight=\"1\" coefs=\"1 0 0 1\"/>\n</flame>\n",
         ":2:21: coefs: expected 6 numbers, got 4\n"},
        {"<flame size=\"64 64\">\n</flame>\n", ":1:1: the flame has no xform of positive weight\n"},
    };
    int i = 0;
    for (const auto& [xml, want] : cases) {
        const std::string g = dir + "/bad" + std::to_string(i++) + ".flam3";
        write_file(g, xml);
        const auto r = run_cli({"render", g, "-o", dir + "/out.png"});
        EXPECT_EQ(r.rc, 2) << xml;
        EXPECT_EQ(r.err, g + want) << xml;
        const auto m = run_cli({"import", g, "-o", dir + "/out.yaml"});
        EXPECT_EQ(m.rc, 2);
        EXPECT_FALSE(std::filesystem::exists(dir + "/out.png"));
        EXPECT_FALSE(std::filesystem::exists(dir + "/out.yaml"));
    }
}

} // namespace
