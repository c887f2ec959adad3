// `fixpoint to-subdivision`: paper 05's converse construction (Sec. 3.1), affine maps as
// subdivision matrices on a triangle of control points. By hand for the Sierpinski triangle's
// maps on the unit triangle, by round trip for Barnsley's fern on another triangle (the printed
// subdivision map and the affine map agree on every point), and the refusals.
#include "cli.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

std::vector<double> eval(const std::string& map, const std::string& points) {
    const auto r = run_cli({"eval", map}, points);
    EXPECT_EQ(r.rc, 0) << r.err;
    std::istringstream in(r.out);
    std::vector<double> v;
    for (double x; in >> x;) v.push_back(x);
    return v;
}

} // namespace

TEST(ToSubdivision, SierpinskiByHand) {
    // f_1(p) = p / 2 on (0, 0), (1, 0), (0, 1): f_1(p_1) = p_1, f_1(p_2) = (p_1 + p_2) / 2,
    // f_1(p_3) = (p_1 + p_3) / 2; f_2 and f_3 the same towards p_2 and p_3.
    const auto r = run_cli({"to-subdivision", "--points", "[[0, 0], [1, 0], [0, 1]]",
                            "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}",
                            "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}",
                            "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0.5]}"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(
        r.out,
        "- {type: subdivision, points: [[0, 0], [1, 0], [0, 1]], S: [1, 0, 0, 0.5, 0.5, 0, 0.5, 0, 0.5]}\n"
        "- {type: subdivision, points: [[0, 0], [1, 0], [0, 1]], S: [0.5, 0.5, 0, 0, 1, 0, 0, 0.5, 0.5]}\n"
        "- {type: subdivision, points: [[0, 0], [1, 0], [0, 1]], S: [0.5, 0, 0.5, 0, 0.5, 0.5, 0, 0, 1]}\n");
}

TEST(ToSubdivision, BarnsleysFernRoundTrip) {
    const std::vector<std::string> fern = {
        "{type: affine, coefficients: [0, 0, 0, 0.16, 0, 0]}",
        "{type: affine, coefficients: [0.85, 0.04, -0.04, 0.85, 0, 1.6]}",
        "{type: affine, coefficients: [0.2, -0.26, 0.23, 0.22, 0, 1.6]}",
        "{type: affine, coefficients: [-0.15, 0.28, 0.26, 0.24, 0, 0.44]}",
    };
    std::vector<std::string> args = {"to-subdivision", "--points", "[[-1, 0], [2, 0.5], [0, 3]]"};
    args.insert(args.end(), fern.begin(), fern.end());
    const auto r = run_cli(args);
    ASSERT_EQ(r.rc, 0) << r.err;
    std::istringstream lines(r.out);
    std::string line;
    const std::string points = "0 0\n1 1\n-2.5 4\n0.3 -7\n";
    for (const auto& f : fern) {
        ASSERT_TRUE(std::getline(lines, line));
        ASSERT_EQ(line.rfind("- ", 0), 0u);
        const auto a = eval(f, points), s = eval(line.substr(2), points);
        ASSERT_EQ(a.size(), 8u);
        ASSERT_EQ(s.size(), 8u);
        for (std::size_t i = 0; i < 8; ++i)
            EXPECT_NEAR(s[i], a[i], 1e-12 * (1 + std::fabs(a[i]))) << f << " " << i;
    }
}

TEST(ToSubdivision, Refusals) {
    const auto inv = run_cli({"to-subdivision", "--points", "[[0, 0], [1, 0], [0, 1]]",
                              "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}",
                              "{type: inversion, shape: {type: circle, centre: [3, 3]}}"});
    EXPECT_EQ(inv.rc, 2);
    EXPECT_EQ(inv.err,
              "map 2: not an affine map: it sends (0.3, 0.5) to (2.8005908419497785, 2.8153618906942395), "
              "not to (2.805128205128205, 2.8205128205128203): subdivision matrices represent affine maps "
              "only\n");
    const auto line = run_cli({"to-subdivision", "--points", "[[0, 0], [1, 1], [2, 2]]",
                               "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}"});
    EXPECT_EQ(line.rc, 2);
    EXPECT_EQ(line.err, "--points: the three control points lie on a line: they must span a triangle\n");
    const auto two = run_cli({"to-subdivision", "--points", "[[0, 0], [1, 0]]",
                              "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}"});
    EXPECT_EQ(two.rc, 2);
    EXPECT_EQ(two.err, "--points: expected three points [[x1, y1], [x2, y2], [x3, y3]] (a triangle)\n");
}
