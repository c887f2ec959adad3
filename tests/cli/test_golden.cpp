// Golden images: two configs rendered small and compared with tests/golden/*.png through
// OpenImageIO's ImageBufAlgo::compare.
//
// Tolerance: a channel may differ by at most 1.5/255 (above half an LSB of the 8-bit PNG, so
// a different rounding of one float sum passes), and at most 0.2% of the pixels may exceed
// that. On the machine that wrote the goldens the render is bit-identical; the slack is for
// other libm versions and compilers. Regenerate after an intended change with
//   FIXPOINT_UPDATE_GOLDEN=1 build/bin/fixpoint_tests --gtest_filter='Golden*'
// and look at the new images before committing them.
#include "cli.hpp"

#include <fixpoint/host/image_io.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

namespace {

struct Golden {
    const char* config; // under configs/
    const char* golden; // under tests/golden/
};

void PrintTo(const Golden& g, std::ostream* os) { *os << g.config; }

class GoldenImage : public testing::TestWithParam<Golden> {};

TEST_P(GoldenImage, MatchesWithinTolerance) {
    const Golden g = GetParam();
    const std::string dir = fp::test::scratch_dir(std::string("golden_") + g.golden);
    const std::string out = dir + "/render.png";
    const std::string golden = fp::test::source_dir() + "/tests/golden/" + g.golden;
    const auto r = fp::test::run_cli({"render", "--quiet", fp::test::source_dir() + "/configs/" + g.config,
                                      "-o", out, "--set", "renderer.width=128", "--set",
                                      "renderer.height=128", "--set", "renderer.points=400000"});
    ASSERT_EQ(r.rc, 0) << r.err;
    if (std::getenv("FIXPOINT_UPDATE_GOLDEN")) {
        std::filesystem::copy_file(out, golden, std::filesystem::copy_options::overwrite_existing);
        GTEST_SKIP() << "golden image written: " << golden;
    }
    ASSERT_TRUE(std::filesystem::exists(golden)) << golden;
    const auto c = fp::host::compare_images(out, golden, 1.5 / 255);
    ASSERT_FALSE(c.size_mismatch);
    EXPECT_LE(double(c.n_fail), 0.002 * 128 * 128)
        << "max error " << c.max_error << ", mean " << c.mean_error;
    EXPECT_LT(c.mean_error, 0.002);
}

INSTANTIATE_TEST_SUITE_P(Paper01, GoldenImage,
                         testing::Values(Golden{"inversion/fig4b.yaml", "fig4b.png"},
                                         Golden{"inversion/fig6c.yaml", "fig6c.png"}),
                         [](const testing::TestParamInfo<Golden>& i) {
                             std::string s = i.param.golden;
                             return s.substr(0, s.find('.'));
                         });

} // namespace
