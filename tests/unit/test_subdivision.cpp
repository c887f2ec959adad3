// The subdivision transform (paper 05, eq. (3.1)): f(A) = A P^-1 S P.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/vertex_map.hpp>

#include "host.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace {

const std::string square = "points: [[0, 0], [1, 0], [0, 1], [1, 1]]";
const std::string triangle = "points: [[0, 0], [1, 0], [0.5, 0.6666666666666666]]";

// Example 1's S_1 .. S_9 (times 9) and the triangle maps' S_1 .. S_4 (times 2), row major.
const std::vector<std::string> quad_S = {
    "[9, 0, 0, 0, 6, 3, 0, 0, 6, 0, 3, 0, 4, 2, 2, 1]", "[6, 3, 0, 0, 3, 6, 0, 0, 4, 2, 2, 1, 2, 4, 1, 2]",
    "[3, 6, 0, 0, 0, 9, 0, 0, 2, 4, 1, 2, 0, 6, 0, 3]", "[6, 0, 3, 0, 4, 2, 2, 1, 3, 0, 6, 0, 2, 1, 4, 2]",
    "[4, 2, 2, 1, 2, 4, 1, 2, 2, 1, 4, 2, 1, 2, 2, 4]", "[2, 4, 1, 2, 0, 6, 0, 3, 1, 2, 2, 4, 0, 3, 0, 6]",
    "[3, 0, 6, 0, 2, 1, 4, 2, 0, 0, 9, 0, 0, 0, 6, 3]", "[2, 1, 4, 2, 1, 2, 2, 4, 0, 0, 6, 3, 0, 0, 3, 6]",
    "[1, 2, 2, 4, 0, 3, 0, 6, 0, 0, 3, 6, 0, 0, 0, 9]"};
const std::vector<std::string> tri_S = {"[2, 0, 0, 1, 1, 0, 1, 0, 1]", "[1, 1, 0, 0, 1, 1, 1, 0, 1]",
                                        "[1, 1, 0, 0, 2, 0, 0, 1, 1]", "[1, 0, 1, 0, 1, 1, 0, 0, 2]"};

std::shared_ptr<const fp::VertexMap> make(const std::string& yaml) {
    auto t = fp::test::host().make<fp::Transform>(yaml);
    auto v = std::dynamic_pointer_cast<const fp::VertexMap>(t);
    if (!v) throw std::runtime_error("not a VertexMap");
    return v;
}

std::string quad(int i) {
    return "{type: subdivision, " + square + ", divisor: 9, S: " + quad_S[i - 1] + "}";
}
std::string tri(int i) {
    return "{type: subdivision, " + triangle + ", divisor: 2, S: " + tri_S[i - 1] + "}";
}

fp::Vec2 apply(const fp::VertexMap& m, fp::Vec2 p) {
    double x = p.x, y = p.y;
    m.apply(fp::Points<double>{&x, &y, 1}, nullptr);
    return {x, y};
}

std::string error_of(const std::string& yaml) {
    try {
        fp::test::host().make<fp::Transform>(yaml);
    } catch (const fp::InputError& e) {
        const std::string m = e.what();
        const auto at = m.find(": ");
        return at == std::string::npos ? m : m.substr(at + 2);
    }
    return "(no error)";
}

// The carpet maps are affine maps of the unit square onto its ninths (1 2 3 the bottom row).
TEST(Subdivision, CarpetMapsTakeTheSquareToItsNinths) {
    for (int i = 1; i <= 9; ++i) {
        const auto m = make(quad(i));
        const double x0 = double((i - 1) % 3) / 3, y0 = double((i - 1) / 3) / 3;
        for (const fp::Vec2 p :
             {fp::Vec2{0, 0}, fp::Vec2{1, 0}, fp::Vec2{0, 1}, fp::Vec2{1, 1}, fp::Vec2{0.3, 0.8}}) {
            const fp::Vec2 q = apply(*m, p);
            EXPECT_NEAR(q.x, x0 + p.x / 3, 1e-14) << "f" << i;
            EXPECT_NEAR(q.y, y0 + p.y / 3, 1e-14) << "f" << i;
        }
    }
}

// f(P) = P P^-1 S P = S P: the point map on the control points is the subdivision rule.
TEST(Subdivision, PointMapOnControlPointsIsSubdivision) {
    std::vector<std::string> all;
    for (int i = 1; i <= 9; ++i) all.push_back(quad(i));
    for (int i = 1; i <= 4; ++i) all.push_back(tri(i));
    for (const auto& y : all) {
        const auto m = make(y);
        const auto P = m->control_points();
        const size_t n = m->vertex_count();
        ASSERT_EQ(P.size(), n);
        std::vector<double> px, py, cx(n), cy(n);
        for (auto p : P) px.push_back(p.x), py.push_back(p.y);
        m->subdivide({px.data(), py.data(), n}, {cx.data(), cy.data(), n});
        for (size_t k = 0; k < n; ++k) {
            const fp::Vec2 q = apply(*m, P[k]);
            EXPECT_NEAR(q.x, cx[k], 1e-14) << y;
            EXPECT_NEAR(q.y, cy[k], 1e-14) << y;
        }
    }
}

// Triangle map f_1 halves towards p_0, f_2 is the middle triangle (hand-computed).
TEST(Subdivision, TriangleMaps) {
    const auto f1 = make(tri(1)), f2 = make(tri(2));
    const fp::Vec2 a = apply(*f1, {1, 0}), b = apply(*f1, {0.5, 2.0 / 3});
    EXPECT_NEAR(a.x, 0.5, 1e-15);
    EXPECT_NEAR(a.y, 0, 1e-15);
    EXPECT_NEAR(b.x, 0.25, 1e-15);
    EXPECT_NEAR(b.y, 1.0 / 3, 1e-15);
    // f_2 takes p0 -> mid(p0, p1) = (0.5, 0), p1 -> mid(p1, p2) = (0.75, 1/3), p2 -> mid(p0, p2).
    const fp::Vec2 c = apply(*f2, {0, 0}), d = apply(*f2, {1, 0}), e = apply(*f2, {0.5, 2.0 / 3});
    EXPECT_NEAR(c.x, 0.5, 1e-15);
    EXPECT_NEAR(c.y, 0, 1e-15);
    EXPECT_NEAR(d.x, 0.75, 1e-15);
    EXPECT_NEAR(d.y, 1.0 / 3, 1e-15);
    EXPECT_NEAR(e.x, 0.25, 1e-15);
    EXPECT_NEAR(e.y, 1.0 / 3, 1e-15);
}

// The paper's P of Example 1 written out gives the same map as the lifted points.
TEST(Subdivision, ExplicitPEqualsLiftedPoints) {
    const auto a = make(quad(5));
    const auto b =
        make("{type: subdivision, P: [0, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 1, 1, 1, 1, 1], divisor: 9, S: " +
             quad_S[4] + "}");
    for (const fp::Vec2 p : {fp::Vec2{0.2, 0.7}, fp::Vec2{-1, 2}}) {
        EXPECT_NEAR(apply(*a, p).x, apply(*b, p).x, 1e-14);
        EXPECT_NEAR(apply(*a, p).y, apply(*b, p).y, 1e-14);
    }
}

// A rule that bends the square (the 4th child point is the centre, not the affine image of
// (1, 1)) is no map of the plane: it says so (renderers that map points refuse it when they are
// built: tests/cli/test_mfs_cli.cpp), apply() refuses, subdivide() works.
TEST(Subdivision, NonPlaneMapRefusesPointsButSubdivides) {
    const auto m = make("{type: subdivision, " + square +
                        ", divisor: 4, S: [4, 0, 0, 0, 0, 4, 0, 0, 0, 0, 4, 0, 1, 1, 1, 1]}");
    double x = 0.5, y = 0.5;
    try {
        m->apply(fp::Points<double>{&x, &y, 1}, nullptr);
        FAIL() << "no error";
    } catch (const fp::InputError& e) {
        EXPECT_EQ(std::string(e.what()), m->plane_map_problem());
    }
    EXPECT_EQ(m->plane_map_problem(),
              "this subdivision map is no map of the plane (its lifted coordinates feed x "
              "and y): use it in the mfs renderer, which subdivides vertex sets");
    std::vector<double> px = {0, 1, 0, 1}, py = {0, 0, 1, 1}, cx(4), cy(4);
    m->subdivide({px.data(), py.data(), 4}, {cx.data(), cy.data(), 4});
    EXPECT_DOUBLE_EQ(cx[3], 0.5);
    EXPECT_DOUBLE_EQ(cy[3], 0.5);
}

TEST(Subdivision, BadInput) {
    EXPECT_EQ(error_of("{type: subdivision, " + triangle + ", S: [1, 0, 0, 0, 1, 0, 0, 0, 1, 0]}"),
              "transform.S: S has 10 entries; 3 control points need a 3 x 3 matrix (9 entries, row major)");
    EXPECT_EQ(error_of("{type: subdivision, " + triangle + ", divisor: 2, S: [2, 0, 0, 1, 1, 0, 1, 0, 0]}"),
              "transform.S: row 3 of S sums to 0.5 (after dividing by the divisor 2), not 1: a subdivision "
              "rule takes affine "
              "combinations");
    EXPECT_EQ(
        error_of("{type: subdivision, points: [[0, 0], [1, 1], [2, 2]], S: [1, 0, 0, 0, 1, 0, 0, 0, 1]}"),
        "transform.points: the P of these control points is singular: f(A) = A P^-1 S P needs affinely "
        "independent "
        "(lifted) points (these three lie on one line)");
    EXPECT_EQ(
        error_of("{type: subdivision, P: [0, 0, 1, 1, 0, 1, 0, 1, 0.5], S: [1, 0, 0, 0, 1, 0, 0, 0, 1]}"),
        "transform.P: the last column of P must be all ones (row 3 ends in 0.5)");
    EXPECT_EQ(error_of("{type: subdivision, P: [0, 0, 1, 1, 0, 1, 2, 0, 1], S: [1, 0, 0, 0, 1, 0, 0, 0, 1]}"),
              "transform.P: P is singular: f(A) = A P^-1 S P needs affinely independent (lifted) points");
    EXPECT_EQ(
        error_of(
            "{type: subdivision, points: [[0, 0], [1, 0], [0, 1], [1, 1], [2, 2]], S: [1, 0, 0, 0, 0, 0, "
            "1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1]}"),
        "transform.points: with 5 control points give P (n x n, last column ones): only 3 points (the plane) "
        "and 4 "
        "(lifted with z = x y) are lifted automatically");
}

} // namespace
