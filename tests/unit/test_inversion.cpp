// Unit tests of the star-shaped set inversion (paper 01, Sec. 3, eq. (4)):
//     p' = o + t_b^2 (p - o),   b = o + t_b (p - o) on the boundary.
// Hand-computed points, the reduction to circle inversion (eq. (2)), the involution law on
// every shape, the kernel check of the centre, and the mask.
#include "host.hpp"

#include <fixpoint/host/core/host.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::Transform;
using fp::Vec2;

std::shared_ptr<const Transform> inversion(const std::string& shape, const std::string& centre = "") {
    const std::string yaml =
        "{type: inversion, shape: " + shape + (centre.empty() ? "" : ", centre: " + centre) + "}";
    return make<Transform>(yaml);
}

// This file's tolerance where a test names none.
using fp::test::expect_point;
void expect_point(Vec2 got, Vec2 want) { expect_point(got, want, 1e-14); }

const std::string unit_circle = "{type: circle, centre: [0, 0], radius: 1}";
const std::string square = "{type: polygon, vertices: [[-1, -1], [1, -1], [1, 1], [-1, 1]]}";
const std::string l_shape = "{type: polygon, vertices: [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]}";

// ------------------------------------------------------------------ hand-computed points

TEST(Inversion, CircleFromItsCentre) {
    auto t = inversion(unit_circle);
    // o = (0, 0), R = 1: p' = p / |p|^2.
    // (2, 0): |p|^2 = 4 -> (0.5, 0).   (0.5, 0.5): |p|^2 = 0.5 -> (1, 1).
    expect_point(apply(*t, {2, 0}), {0.5, 0});
    expect_point(apply(*t, {0.5, 0.5}), {1, 1});
    expect_point(apply(*t, {0, -0.25}), {0, -4});
}

TEST(Inversion, CircleOffCentre) {
    auto t = inversion(unit_circle, "[0.5, 0]");
    // o = (0.5, 0), p = (2, 0): d = (1.5, 0), b = (1, 0), t_b = 0.5 / 1.5 = 1/3,
    //   p' = o + (1/9)(1.5, 0) = (2/3, 0).   Check eq. (3): 1.5 * (1/6) = 0.25 = 0.5^2.
    expect_point(apply(*t, {2, 0}), {2.0 / 3, 0});
    // p = (0.5, 2): d = (0, 2), b = (0.5, sqrt(3)/2), t_b = sqrt(3)/4, t_b^2 = 3/16,
    //   p' = (0.5, 3/8).                      Check: 2 * 3/8 = 3/4 = (sqrt(3)/2)^2.
    expect_point(apply(*t, {0.5, 2}), {0.5, 0.375});
    // p = (-2, 0): d = (-2.5, 0), b = (-1, 0), t_b = 1.5 / 2.5 = 0.6, t_b^2 = 0.36,
    //   p' = 0.5 - 0.36 * 2.5 = -0.4.         Check: 2.5 * 0.9 = 2.25 = 1.5^2.
    expect_point(apply(*t, {-2, 0}), {-0.4, 0});
    // A boundary point is fixed: (-1, 0) has t_b = 1.
    expect_point(apply(*t, {-1, 0}), {-1, 0});
}

TEST(Inversion, SquareFromItsCentre) {
    auto t = inversion(square);
    // o = (0, 0), p = (2, 1): the ray meets x = 1 at t_b = 0.5, b = (1, 0.5),
    //   p' = 0.25 * (2, 1) = (0.5, 0.25); and back.
    expect_point(apply(*t, {2, 1}), {0.5, 0.25});
    expect_point(apply(*t, {0.5, 0.25}), {2, 1});
    // p = (3, 3): through the corner (1, 1), t_b = 1/3, p' = (1/9)(3, 3) = (1/3, 1/3).
    expect_point(apply(*t, {3, 3}), {1.0 / 3, 1.0 / 3});
    // p = (0, -4): bottom edge at t_b = 1/4, p' = (1/16)(0, -4) = (0, -0.25).
    expect_point(apply(*t, {0, -4}), {0, -0.25});
}

TEST(Inversion, SquareOffCentre) {
    auto t = inversion(square, "[0.5, 0]");
    // o = (0.5, 0), p = (0.5, 3): d = (0, 3), top edge y = 1 at t_b = 1/3,
    //   p' = o + (1/9)(0, 3) = (0.5, 1/3).
    expect_point(apply(*t, {0.5, 3}), {0.5, 1.0 / 3});
    // p = (-3, 0): d = (-3.5, 0), x = -1 at t_b = 1.5 / 3.5 = 3/7, t_b^2 = 9/49,
    //   p' = 0.5 - 3.5 * 9/49 = -1/7.         Check: 3.5 * (9/14) = 2.25 = 1.5^2.
    expect_point(apply(*t, {-3, 0}), {-1.0 / 7, 0});
    // p = (2, 1.5): d = (1.5, 1.5), x = 1 at t_b = 1/3 (y = 1 only at 2/3), b = (1, 0.5),
    //   p' = o + (1/9)(1.5, 1.5) = (2/3, 1/6).
    expect_point(apply(*t, {2, 1.5}), {2.0 / 3, 1.0 / 6});
}

// ------------------------------------------------------------------ eq. (2)

TEST(Inversion, CircleWithItsCentreIsClassicalCircleInversion) {
    // Eq. (2): p' = o + R^2 / |p - o|^2 (p - o), to the last bit, in double and in float
    // (the circle gives the factor R^2 / |d|^2 in closed form).
    const Vec2 o{0.3, -1.2};
    const double R = 1.7;
    auto t = inversion("{type: circle, centre: [0.3, -1.2], radius: 1.7}");
    fp::Rng rng = fp::chain_stream(1, 2);
    for (int k = 0; k < 2000; ++k) {
        const Vec2 p{-6 + 12 * fp::uniform_double(rng), -6 + 12 * fp::uniform_double(rng)};
        const double dx = p.x - o.x, dy = p.y - o.y, s = R * R / (dx * dx + dy * dy);
        const Vec2 got = apply(*t, p);
        EXPECT_EQ(got.x, o.x + s * dx) << k;
        EXPECT_EQ(got.y, o.y + s * dy) << k;
        float fx = float(p.x), fy = float(p.y);
        t->apply(fp::Points<float>{&fx, &fy, 1}, nullptr);
        const float fdx = float(p.x) - float(o.x), fdy = float(p.y) - float(o.y);
        const float fs = float(R * R) / (fdx * fdx + fdy * fdy);
        EXPECT_EQ(fx, float(o.x) + fs * fdx) << k;
        EXPECT_EQ(fy, float(o.y) + fs * fdy) << k;
    }
}

// ------------------------------------------------------------------ involution

struct Case {
    std::string shape, centre;
};

void PrintTo(const Case& c, std::ostream* os) {
    *os << c.shape << (c.centre.empty() ? "" : " centre " + c.centre);
}

class Involution : public ::testing::TestWithParam<Case> {};

TEST_P(Involution, TwiceIsIdentity) {
    const Case& c = GetParam();
    auto t = inversion(c.shape, c.centre);
    ASSERT_TRUE(t->is_involution());
    const fp::Box b = t->sample_domain();
    fp::Rng rng = fp::chain_stream(7, 11);
    constexpr std::size_t n = 3000;
    std::vector<double> x(n), y(n);
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = b.xmin + (b.xmax - b.xmin) * fp::uniform_double(rng);
        y[i] = b.ymin + (b.ymax - b.ymin) * fp::uniform_double(rng);
    }
    std::vector<double> x2 = x, y2 = y;
    t->apply(fp::Points<double>{x2.data(), y2.data(), n}, nullptr);
    t->apply(fp::Points<double>{x2.data(), y2.data(), n}, nullptr);
    const double size = (b.xmax - b.xmin) + (b.ymax - b.ymin);
    for (std::size_t i = 0; i < n; ++i) {
        EXPECT_NEAR(x2[i], x[i], 1e-10 * size) << i;
        EXPECT_NEAR(y2[i], y[i], 1e-10 * size) << i;
    }
    // Float path, looser.
    std::vector<float> xf(x.begin(), x.end()), yf(y.begin(), y.end());
    t->apply(fp::Points<float>{xf.data(), yf.data(), n}, nullptr);
    t->apply(fp::Points<float>{xf.data(), yf.data(), n}, nullptr);
    std::size_t off = 0;
    for (std::size_t i = 0; i < n; ++i)
        off += !(std::fabs(xf[i] - x[i]) <= 1e-3 * size && std::fabs(yf[i] - y[i]) <= 1e-3 * size);
    EXPECT_LE(off, n / 200);
    // Inside and outside are swapped.
    std::vector<double> x1 = x, y1 = y;
    t->apply(fp::Points<double>{x1.data(), y1.data(), n}, nullptr);
    std::vector<unsigned char> in0(n), in1(n);
    t->contains(fp::Points<const double>{x.data(), y.data(), n}, in0.data());
    t->contains(fp::Points<const double>{x1.data(), y1.data(), n}, in1.data());
    std::size_t same = 0;
    for (std::size_t i = 0; i < n; ++i) same += in0[i] == in1[i];
    EXPECT_LE(same, 2u); // only points within rounding of the boundary may stay on their side
}

INSTANTIATE_TEST_SUITE_P(
    EveryShape, Involution,
    ::testing::Values(
        Case{unit_circle, ""}, Case{unit_circle, "[0.6, -0.7]"},
        Case{"{type: circle, centre: [3, -2], radius: 0.25}", "[3.1, -2]"}, Case{square, ""},
        Case{square, "[0.9, 0.9]"}, Case{"{type: polygon, vertices: [[-1, -1], [1, -1], [0, 1]]}", ""},
        Case{l_shape, ""}, Case{l_shape, "[0.1, 0.95]"}, Case{"{type: star-polygon}", ""},
        Case{"{type: star-polygon, points: 7, inner_radius: 0.3, rotation: 0.2}", "[0.05, 0.1]"},
        Case{"{type: superformula}", ""}, Case{"{type: superformula}", "[0.05, -0.04]"},
        Case{"{type: superformula, m: 3, n1: 0.8, n2: 1.5, n3: 1.5, a: 1, b: 0.7, scale: 2}", ""},
        Case{"{type: bezier, degree: 2, points: [[-1, 0], [0, 2], [1, 0], [0, -2]]}", "[0.3, 0.2]"},
        Case{"{type: bezier, points: [[-1, -1], [-0.3, -1], [0.3, -1], [1, -1], [1, -0.3], [1, 0.3], [1, 1], "
             "[0.3, -0.2], [-0.3, -0.2], [-1, 1], [-1, 0.3], [-1, -0.3]]}",
             ""}));

// ------------------------------------------------------------------ centre and kernel

TEST(Inversion, CentreOutsideTheKernelRefused) {
    // (1.5, 0.5) lies inside the L-shape but cannot see its upper arm.
    try {
        inversion(l_shape, "[1.5, 0.5]");
        ADD_FAILURE() << "accepted";
    } catch (const fp::InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("centre: inversion centre (1.5, 0.5) is outside the kernel of the shape"),
                  std::string::npos)
            << m;
    }
    // Outside the set altogether.
    try {
        inversion(unit_circle, "[1, 0]");
        ADD_FAILURE() << "accepted";
    } catch (const fp::InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("inversion centre (1, 0) is outside the kernel of the shape"), std::string::npos)
            << m;
    }
}

TEST(Inversion, DefaultCentresAreAccepted) {
    // The L-shape's default centre is its kernel's centroid (0.5, 0.5): o maps to infinity.
    auto t = inversion(l_shape);
    const Vec2 q = apply(*t, {0.5, 0.5});
    EXPECT_FALSE(std::isfinite(q.x) && std::isfinite(q.y));
    // Star polygon: its centre is in the kernel, as a default and when given.
    inversion("{type: star-polygon, points: 6, inner_radius: 0.2, centre: [2, 3]}");
    auto s = inversion("{type: star-polygon, points: 6, inner_radius: 0.2, centre: [2, 3]}", "[2, 3]");
    expect_point(apply(*s, {2, 4}), {2, 4}); // a tip is on the boundary: fixed
}

// ------------------------------------------------------------------ batch behaviour

TEST(Inversion, MaskAndRegion) {
    auto t = inversion(square, "[0.5, 0]");
    ASSERT_TRUE(t->has_region());
    constexpr std::size_t n = 600; // more than one chunk
    std::vector<double> x(n), y(n);
    std::vector<unsigned char> m(n);
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = -3 + 6.0 * double(i) / n;
        y[i] = 2.5 - 0.01 * double(i);
        m[i] = i % 3 != 1;
    }
    std::vector<double> xm = x, ym = y;
    t->apply(fp::Points<double>{xm.data(), ym.data(), n}, m.data());
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2 want = m[i] ? apply(*t, {x[i], y[i]}) : Vec2{x[i], y[i]};
        EXPECT_EQ(xm[i], want.x) << i;
        EXPECT_EQ(ym[i], want.y) << i;
    }
    const double px[3] = {0.5, 1.5, -0.99}, py[3] = {0.5, 0, 0.99};
    unsigned char in[3];
    t->contains(fp::Points<const double>{px, py, 3}, in);
    EXPECT_EQ(in[0], 1);
    EXPECT_EQ(in[1], 0);
    EXPECT_EQ(in[2], 1);
    EXPECT_EQ(t->region_outline(0).size(), 4u);
}

} // namespace
