// `fixpoint explore` on patterns that fill the image (paper 04's wallpapers, issue 48): the
// wallpaper measures on made-up images with known values, the calibration that ranks the
// paper's Figs. 8 and 9 above random coefficients of the same groups, and the genetic search on
// an orbit-trap config.
#include "cli.hpp"

#include <fixpoint/host/tools/measures.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace fp::test;
using namespace fp::host;

namespace {

fp::Image grey_image(int w, int h, double (*f)(int, int)) {
    fp::Image img;
    img.width = w;
    img.height = h;
    img.pixels.resize(std::size_t(w) * std::size_t(h) * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                img.pixels[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3 + std::size_t(c)] =
                    float(f(x, y));
    return img;
}

TEST(WallpaperMeasures, HandComputedValues) {
    // Flat: no colours but one, no edges, no contrast.
    const fp::Image flat = grey_image(96, 96, [](int, int) { return 0.5; });
    EXPECT_EQ(colour_entropy(flat), 0);
    EXPECT_EQ(edge_entropy(flat), 0);
    EXPECT_EQ(rms_contrast(flat), 0);
    // Half black, half white: one bit of colour, contrast 0.5; the gradient is 0 but on the
    // two columns beside the step (|g| = 4, the last bin) and the image's borders are left out:
    // 2 of 94 columns, -(2/94 log2(2/94) + 92/94 log2(92/94)) bits.
    const fp::Image step = grey_image(96, 96, [](int x, int) { return x < 48 ? 0.0 : 1.0; });
    EXPECT_NEAR(colour_entropy(step), 1, 1e-12);
    EXPECT_NEAR(rms_contrast(step), 0.5, 1e-12);
    const double p = 2.0 / 94;
    EXPECT_NEAR(edge_entropy(step), -(p * std::log2(p) + (1 - p) * std::log2(1 - p)), 1e-12);
    // One smooth wave has its power in one ring (spread 0); noise spreads it over all of them.
    const fp::Image wave =
        grey_image(128, 128, [](int x, int) { return 0.5 + 0.4 * std::cos(2 * M_PI * 3 * x / 128.0); });
    EXPECT_LT(spectral_spread(wave), 0.01);
    const fp::Image noise = grey_image(128, 128, [](int x, int y) {
        unsigned v = unsigned(x) * 2654435761u ^ unsigned(y) * 2246822519u;
        v ^= v >> 13, v *= 3266489917u, v ^= v >> 16;
        return double(v & 0xffff) / 65535.0;
    });
    EXPECT_GT(spectral_spread(noise), 0.9);
    // The scores: linear between the calibrated ends (wallpaper_measures.cpp).
    EXPECT_EQ(colour_entropy_score(2), 0);
    EXPECT_NEAR(colour_entropy_score(4.25), 0.5, 1e-12);
    EXPECT_EQ(contrast_score(0.3), 1);
    EXPECT_NEAR(group_score(0.2), 0.25, 1e-12);
}

/// The total score of each candidate of an explore run.
std::vector<double> totals(const std::string& dir) {
    std::vector<double> t;
    for (const auto& r : read_tsv(dir + "/candidates.tsv"))
        if (r.at("refused").empty()) t.push_back(std::stod(r.at("score")));
    return t;
}

// Paper 04's Figs. 8 and 9 (p4m and p4 patterns, S-iteration): each panel's own coefficients
// score above the median of 12 random coefficients of its group (its mapping's `seed`, the
// rest of the config the paper's), and above 70% of all 96 of them.
TEST(ExploreWallpaper, PaperPanelsOfFigs8And9BeatRandomCoefficients) {
    const std::string dir = scratch_dir("explore_wallpaper");
    const std::vector<std::string> size = {"--set",  "renderer.width=120",
                                           "--set",  "renderer.height=120",
                                           "--set",  "renderer.samples=1",
                                           "--keep", "1",
                                           "--seed", "7",
                                           "--quiet"};
    std::size_t beaten = 0, all = 0;
    for (const std::string fig : {"8a", "8b", "8c", "8d", "9a", "9b", "9c", "9d"}) {
        const std::string cfg = source_dir() + "/configs/orbit-trap/fig" + fig + ".yaml";
        const std::string text = read_file(cfg);
        const auto at = text.find("group: ");
        ASSERT_NE(at, std::string::npos);
        const std::string group = text.substr(at + 7, text.find_first_of(" \n#", at + 7) - at - 7);
        auto paper = run_cli(with({"explore", cfg, "-o", dir + "/p" + fig, "--param",
                                   "renderer.mapping.group=" + group + "|" + group, "--candidates", "1"},
                                  size));
        ASSERT_EQ(paper.rc, 0) << paper.err;
        auto random = run_cli(with({"explore", cfg, "-o", dir + "/r" + fig, "--set",
                                    "renderer.mapping={type: wallpaper, group: " + group + ", seed: 1}",
                                    "--param", "renderer.mapping.seed=0..100000", "--candidates", "12"},
                                   size));
        ASSERT_EQ(random.rc, 0) << random.err;
        const auto p = totals(dir + "/p" + fig);
        auto r = totals(dir + "/r" + fig);
        ASSERT_EQ(p.size(), 1u);
        ASSERT_EQ(r.size(), 12u);
        std::sort(r.begin(), r.end());
        EXPECT_GT(p[0], (r[5] + r[6]) / 2) << "fig. " << fig;
        beaten += std::size_t(std::count_if(r.begin(), r.end(), [&](double v) { return p[0] > v; }));
        all += r.size();
    }
    EXPECT_GE(double(beaten), 0.7 * double(all)) << beaten << " of " << all;
}

TEST(ExploreWallpaper, GenerationsBreedAnOrbitTrapConfig) {
    const std::string dir = scratch_dir("explore_wallpaper_breed");
    auto a = run_cli({"explore",
                      source_dir() + "/configs/orbit-trap/fig9a.yaml",
                      "-o",
                      dir + "/a",
                      "--random",
                      "renderer.iteration",
                      "--candidates",
                      "6",
                      "--generations",
                      "1",
                      "--keep",
                      "2",
                      "--seed",
                      "3",
                      "--set",
                      "renderer.width=96",
                      "--set",
                      "renderer.height=96",
                      "--set",
                      "renderer.samples=1",
                      "--quiet"});
    ASSERT_EQ(a.rc, 0) << a.err;
    const auto rows = read_tsv(dir + "/a/candidates.tsv");
    bool child = false;
    for (const auto& r : rows) {
        child = child || r.at("generation") == "1";
        // Ranked by the wallpaper measures: present, and coverage left unweighted (every
        // candidate covers the image).
        EXPECT_FALSE(r.at("group").empty());
        EXPECT_FALSE(r.at("colour_entropy").empty());
        EXPECT_EQ(r.at("coverage"), "1.000000");
    }
    EXPECT_TRUE(child);
    // The best's score is the mean of its five wallpaper scores.
    const auto& b = rows.front();
    double mean = 0;
    for (const char* m : {"colour_entropy", "edge_entropy", "spectrum", "group", "contrast"})
        mean += std::stod(b.at(std::string(m) + "_score")) / 5;
    EXPECT_NEAR(std::stod(b.at("score")), mean, 1e-5);
}

} // namespace
