// The renderers' shared frame (fp::Frame, fixpoint/frame.hpp): each of the four renderers,
// given a reversed region or too many pixels in its own config, refuses it with the same
// message, naming its region parameter (`view`, or `area` for orbit-trap), at the line and
// column of the bad value.
#include "cli.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace fp::test;

namespace {

std::string config(const std::string& name) { return read_file(source_dir() + "/configs/" + name); }

TEST(Frame, EveryRendererChecksItsRegionAlike) {
    // chaos-game and superfractal (their configs give a view), mfs (its view is optional:
    // added), orbit-trap (an area).
    EXPECT_EQ(run_bad_input("frame_chaos",
                            replace_once(config("inversion/fig6a.yaml"), "view: [-1.25, 1.25, -1.25, 1.25]",
                                         "view: [1.25, -1.25, -1.25, 1.25]")),
              "bad.yaml:20:9: renderer.view: the view must be [xmin, xmax, ymin, ymax] with xmin < xmax");
    EXPECT_EQ(run_bad_input("frame_superfractal",
                            replace_once(config("gumowski-mira/fig2-F.yaml"), "view: [0.1, 0.9, 0.1, 0.9]",
                                         "view: [0.1, 0.9, 0.9, 0.9]")),
              "bad.yaml:23:9: renderer.view: the view must be [xmin, xmax, ymin, ymax] with ymin < ymax");
    EXPECT_EQ(run_bad_input("frame_mfs", replace_once(config("mfs/fig3-0101.yaml"), "  height: 600\n",
                                                      "  height: 600\n  view: [0, 1, 2, 1]\n")),
              "bad.yaml:13:9: renderer.view: the view must be [xmin, xmax, ymin, ymax] with ymin < ymax");
    EXPECT_EQ(run_bad_input("frame_orbit_trap", replace_once(config("orbit-trap/fig10a.yaml"),
                                                             "area: [-1, 1, -1, 1]", "area: [1, -1, -1, 1]")),
              "bad.yaml:15:9: renderer.area: the area must be [xmin, xmax, ymin, ymax] with xmin < xmax");
}

TEST(Frame, EveryRendererRefusesTooManyPixels) {
    const std::string message =
        "renderer.height: the image is too large: width * height must be below 4294967295 pixels";
    for (const std::string name :
         {"inversion/fig6a.yaml", "gumowski-mira/fig2-F.yaml", "orbit-trap/fig10a.yaml"}) {
        std::string y = config(name);
        const auto w = y.find("  width: "), h = y.find("  height: ");
        ASSERT_NE(w, std::string::npos) << name;
        ASSERT_NE(h, std::string::npos) << name;
        y = replace_once(y, y.substr(h, y.find('\n', h) - h), "  height: 65536");
        y = replace_once(y, y.substr(w, y.find('\n', w) - w), "  width: 65536");
        const std::string line = run_bad_input("frame_pixels", y);
        EXPECT_NE(line.find(": " + message), std::string::npos) << name << ": " << line;
    }
}

} // namespace
