// Paper 01, Sec. 3 (after Algorithm 1): "the fractal approximation obtained with the algorithm
// will lie entirely inside the region bounded by the star-shaped sets that define the
// transformations". A map is only applied to a point outside its set (the second restriction),
// and an inversion takes the outside of its set into the inside (property 1), so every plotted
// point (each one past the skipped start of its chain) lies in the set of the map that made it.
//
// The check renders each of paper 01's figures (configs/inversion/*.yaml, all with the Picard
// step and the rules on) small, through the CLI, and maps every lit pixel back to the plane: the
// pixel, widened by one pixel on every side, must meet the union of the maps' sets, as the
// inversions' own inside tests (Transform::contains) see them. The sets are read from the same
// config file, so the test follows the configs.
//
// The claim is paper 01's, for Algorithm 1. It does not hold for paper 02's iteration processes
// (configs/iterations/): a Mann or S step mixes p with T(p), and that combination can lie outside
// every set (configs/iterations/fig7c.yaml says so of its pattern, which reaches radius 2.2 while
// the sets end at 1.8); those configs are not tested here.
#include "cli.hpp"
#include "host.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

struct Union {
    std::vector<std::shared_ptr<const fp::Transform>> maps;
    double view[4]; // xmin, xmax, ymin, ymax

    /// Whether any of the points lies in some map's set.
    bool meets(const std::vector<double>& x, const std::vector<double>& y) const {
        std::vector<unsigned char> in(x.size());
        for (const auto& m : maps) {
            m->contains(fp::Points<const double>{x.data(), y.data(), x.size()}, in.data());
            if (std::any_of(in.begin(), in.end(), [](unsigned char c) { return c != 0; })) return true;
        }
        return false;
    }
};

/// The maps and view of a config, built as the renderer builds them (less the keys the
/// renderer reads for itself: colour and weight).
Union union_of(const std::string& config) {
    fp::host::CNode root = fp::host::load_yaml_file(config);
    const fp::host::CNode* r = root.find("renderer");
    EXPECT_TRUE(r);
    Union u;
    const fp::host::CNode* view = r->find("view");
    EXPECT_TRUE(view && view->items.size() == 4u) << config;
    for (std::size_t i = 0; i < 4; ++i) u.view[i] = std::stod(view->items[i].scalar);
    for (fp::host::CNode m : r->find("maps")->items) {
        std::erase_if(m.keys, [](const auto& k) { return k.first == "colour" || k.first == "weight"; });
        m.key_marks.clear();
        auto t = host().make<fp::Transform>(fp::host::emit_yaml(m));
        EXPECT_TRUE(t && t->has_region()) << fp::host::emit_yaml(m);
        u.maps.push_back(t);
    }
    return u;
}

struct Check {
    std::size_t lit = 0, outside = 0;
    std::string first; // where the first lit pixel outside the union is
};

constexpr int size = 128;

/// Render `config` at size x size and check every lit pixel against its sets (all but map
/// `drop`, when given).
Check check(const std::string& config, int drop = -1) {
    const std::string name = config.substr(config.rfind('/') + 1);
    const std::string dir = fp::test::scratch_dir("inversion_union_" + name);
    std::vector<std::string> args = {"render", "--quiet", config, "-o", dir + "/out.png", "--set",
                                     "renderer.width=" + std::to_string(size), "--set",
                                     "renderer.height=" + std::to_string(size), "--set",
                                     "renderer.points=200000",
                                     // Every hit pixel fully lit, whatever its density.
                                     "--set", "renderer.colourer={type: map-colour, density: flat}", "--set",
                                     "renderer.background=[0, 0, 0]"};
    const auto r = fp::test::run_cli(args);
    Check c;
    EXPECT_EQ(r.rc, 0) << r.err;
    if (r.rc != 0) return c;
    Union u = union_of(config);
    if (drop >= 0) u.maps.erase(u.maps.begin() + drop);
    const fp::Image img = fp::host::read_image(dir + "/out.png");
    EXPECT_EQ(img.width, size);
    EXPECT_EQ(img.height, size);
    const double dx = (u.view[1] - u.view[0]) / size, dy = (u.view[3] - u.view[2]) / size;
    // Pixel (col, row) holds the points of [xmin + col dx, xmin + (col + 1) dx] x
    // [ymax - (row + 1) dy, ymax - row dy] (row 0 at the top). One pixel of margin on every side
    // (for the float chains' rounding and the binning at pixel edges): the 3 x 3 block around it,
    // sampled on a 13 x 13 grid of quarter-pixel spacing. The sets are circles of radius >= 0.2
    // (7 pixels and more) and polygons whose narrowest parts are wider than a quarter pixel where
    // they hold plotted points, so a point of a set inside the pixel has a sample point of that
    // set within the block.
    std::vector<double> sx, sy;
    for (int row = 0; row < img.height; ++row)
        for (int col = 0; col < img.width; ++col) {
            const std::size_t i = (std::size_t(row) * std::size_t(img.width) + std::size_t(col)) * 3;
            if (img.pixels[i] == 0 && img.pixels[i + 1] == 0 && img.pixels[i + 2] == 0) continue;
            ++c.lit;
            sx.clear(), sy.clear();
            for (int a = 0; a <= 12; ++a)
                for (int b = 0; b <= 12; ++b) {
                    sx.push_back(u.view[0] + (col - 1 + a / 4.0) * dx);
                    sy.push_back(u.view[3] - (row - 1 + b / 4.0) * dy);
                }
            if (!u.meets(sx, sy) && c.outside++ == 0)
                c.first = "pixel (" + std::to_string(col) + ", " + std::to_string(row) + ")";
        }
    return c;
}

class InversionUnion : public testing::TestWithParam<const char*> {};

TEST_P(InversionUnion, EveryPlottedPointLiesInTheUnionOfTheSets) {
    const std::string config = fp::test::source_dir() + "/configs/inversion/" + GetParam();
    const Check c = check(config);
    EXPECT_EQ(c.outside, 0u) << c.outside << " of " << c.lit << " lit pixels away from every set; first at "
                             << c.first;
    // Not a vacuous pass: a fractal, not a few pixels.
    EXPECT_GT(c.lit, std::size_t(size * size / 50)) << c.lit << " lit pixels";
}

INSTANTIATE_TEST_SUITE_P(Paper01, InversionUnion,
                         testing::Values("fig4a.yaml", "fig4b.yaml", "fig4c.yaml", "fig4d.yaml", "fig5a.yaml",
                                         "fig5b.yaml", "fig5c.yaml", "fig5d.yaml", "fig6a.yaml", "fig6b.yaml",
                                         "fig6c.yaml", "fig6d.yaml"),
                         [](const testing::TestParamInfo<const char*>& i) {
                             std::string s = i.param;
                             return s.substr(0, s.find('.'));
                         });

// The counter-checks. The check can fail: against the union less one of fig4b's large circles,
// the part of the gasket inside that circle is away from every remaining set.
TEST(InversionUnion, CheckSeesAMissingSet) {
    const Check c = check(fp::test::source_dir() + "/configs/inversion/fig4b.yaml", 0);
    EXPECT_GT(c.outside, std::size_t(size)) << c.lit << " lit pixels";
}

// And the claim is Algorithm 1's: under paper 02's SP iteration in Q_{-1.5,0.2} (Fig. 7(c)) the
// combination of p with T(p) leaves the sets, and the pattern covers pixels far from all of them.
TEST(InversionUnion, DoesNotHoldForPaper02Iterations) {
    const Check c = check(fp::test::source_dir() + "/configs/iterations/fig7c.yaml");
    EXPECT_GT(c.outside, std::size_t(size)) << c.lit << " lit pixels";
}

} // namespace
