// The bezier shape (paper 01, Sec. 3: star-shaped sets bounded by polynomial curves): ray
// exits by hand (straight cubics, parabolas) and against a dense polyline, the winding-number
// inside test against the ray exit and against a polygon, and the exact kernel test that
// refuses a centre which cannot see the whole curve.
#include "host.hpp"
#include "shape_probe.hpp"

#include <fixpoint/fixpoint.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::Shape;
using fp::Vec2;

std::string refusal(const std::string& yaml) {
    try {
        host().make<Shape>(yaml);
    } catch (const fp::InputError& e) {
        return e.what();
    }
    return "accepted";
}

// The square [-1, 1]^2 as four straight cubics (control points a third of the way along).
const std::string square =
    "{type: bezier, points: [[-1, -1], [-0.3333333333333333, -1], [0.3333333333333333, -1], "
    "[1, -1], [1, -0.3333333333333333], [1, 0.3333333333333333], [1, 1], "
    "[0.3333333333333333, 1], [-0.3333333333333333, 1], [-1, 1], [-1, 0.3333333333333333], "
    "[-1, -0.3333333333333333]]}";
// |y| < 1 - x^2: two quadratics, (-1, 0) over (0, 2) to (1, 0) and back under (0, -2);
// clockwise as given.
const std::string lens = "{type: bezier, degree: 2, points: [[-1, 0], [0, 2], [1, 0], [0, -2]]}";
// A square whose top side is a cubic dented down to y = 0.1 at x = 0.
const std::string dented =
    "{type: bezier, points: [[-1, -1], [-0.3, -1], [0.3, -1], [1, -1], [1, -0.3], [1, 0.3], "
    "[1, 1], [0.3, -0.2], [-0.3, -0.2], [-1, 1], [-1, 0.3], [-1, -0.3]]}";

TEST(Bezier, StraightCubicsAreTheSquare) {
    auto s = make<Shape>(square);
    EXPECT_NEAR(s->centre().x, 0, 1e-12);
    EXPECT_NEAR(s->centre().y, 0, 1e-12);
    EXPECT_NEAR(ray(*s, {0, 0}, {1, 0.5}), 1, 1e-14);
    EXPECT_NEAR(ray(*s, {0, 0}, {-2, -2}), 0.5, 1e-14); // through the corner
    EXPECT_NEAR(ray(*s, {0.5, 0.25}, {0, 1}), 0.75, 1e-14);
    EXPECT_NEAR(ray(*s, {0.5, 0.25}, {-3, 0}), 0.5, 1e-14);
    EXPECT_EQ(ray(*s, {0, 0}, {0, 0}), std::numeric_limits<double>::infinity());
    EXPECT_TRUE(inside(*s, 0.99, -0.99));
    EXPECT_FALSE(inside(*s, 1.01, 0));
    EXPECT_FALSE(inside(*s, 0, -1.01));
    EXPECT_TRUE(inside(*s, -0.999, 0.5));
}

TEST(Bezier, QuadraticsBoundTheLens) {
    auto s = make<Shape>(lens);
    // Up the axis to (0, 1); along y = x to x = (sqrt 5 - 1) / 2, where x = 1 - x^2.
    EXPECT_NEAR(ray(*s, {0, 0}, {0, 1}), 1, 1e-14);
    EXPECT_NEAR(ray(*s, {0, 0}, {1, 1}), (std::sqrt(5.0) - 1) / 2, 1e-14);
    EXPECT_NEAR(ray(*s, {0, 0}, {-1, -1}), (std::sqrt(5.0) - 1) / 2, 1e-14);
    // From (0.5, 0) to the right: the corner (1, 0).
    EXPECT_NEAR(ray(*s, {0.5, 0}, {1, 0}), 0.5, 1e-14);
    // From (0, 0.5) straight down to y = -1.
    EXPECT_NEAR(ray(*s, {0, 0.5}, {0, -1}), 1.5, 1e-14);
    EXPECT_TRUE(inside(*s, 0.5, 0.74));
    EXPECT_FALSE(inside(*s, 0.5, 0.76));
    EXPECT_TRUE(inside(*s, -0.9, -0.18));
    EXPECT_FALSE(inside(*s, -0.9, -0.2));
    // Convex: every inner point is in the kernel, a point above the top is not.
    EXPECT_TRUE(s->in_kernel({0, 0.99}));
    EXPECT_TRUE(s->in_kernel({0.95, 0}));
    EXPECT_FALSE(s->in_kernel({0, 1.01}));
}

/// The exit along d from o through the polyline of `outline` points, exactly.
double polyline_exit(const std::vector<Vec2>& p, Vec2 o, Vec2 d) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec2 a = p[i], b = p[(i + 1) % p.size()];
        const double ex = b.x - a.x, ey = b.y - a.y, den = d.x * ey - d.y * ex;
        if (den == 0) continue;
        const double wx = a.x - o.x, wy = a.y - o.y;
        const double t = (wx * ey - wy * ex) / den, s = (wx * d.y - wy * d.x) / den;
        if (t > 0 && s >= 0 && s <= 1) best = std::min(best, t);
    }
    return best;
}

TEST(Bezier, RayExitsMatchADensePolyline) {
    // A wavy five-lobed cubic set, from its centre and from another point of its kernel.
    std::string pts;
    for (int k = 0; k < 10; ++k) { // ten segments: tips at radius 1, waists at 0.7
        const double a0 = 2 * M_PI * k / 10, a1 = 2 * M_PI * (k + 1) / 10, r0 = k % 2 ? 0.7 : 1,
                     r1 = k % 2 ? 1 : 0.7;
        const auto pt = [&](double r, double a) {
            return "[" + std::to_string(r * std::cos(a)) + ", " + std::to_string(r * std::sin(a)) + "], ";
        };
        pts += pt(r0, a0) + pt(r0 * 1.05, a0 + 0.2) + pt(r1 * 1.05, a1 - 0.2);
    }
    auto s = make<Shape>("{type: bezier, points: [" + pts.substr(0, pts.size() - 2) + "]}");
    const auto line = s->outline(100000);
    for (const Vec2 o : {s->centre(), Vec2{0.1, -0.05}}) {
        ASSERT_TRUE(s->in_kernel(o));
        std::vector<double> dx(300), dy(300), t(300);
        for (int i = 0; i < 300; ++i) dx[i] = std::cos(0.07 * i * i), dy[i] = std::sin(0.07 * i * i);
        s->ray_exit(o, fp::Points<const double>{dx.data(), dy.data(), dx.size()}, t.data());
        for (int i = 0; i < 300; ++i) {
            // The chords' sag at 10 000 points per segment is below 1e-8.
            ASSERT_NEAR(t[i], polyline_exit(line, o, {dx[i], dy[i]}), 1e-8) << i;
            const double ix = o.x + t[i] * dx[i], iy = o.y + t[i] * dy[i];
            EXPECT_TRUE(inside(*s, o.x + 0.999 * (ix - o.x), o.y + 0.999 * (iy - o.y))) << i;
            EXPECT_FALSE(inside(*s, o.x + 1.001 * (ix - o.x), o.y + 1.001 * (iy - o.y))) << i;
        }
        // Float: within its precision.
        std::vector<float> fx(dx.begin(), dx.end()), fy(dy.begin(), dy.end()), ft(300);
        s->ray_exit(o, fp::Points<const float>{fx.data(), fy.data(), fx.size()}, ft.data());
        for (int i = 0; i < 300; ++i) EXPECT_NEAR(ft[i], t[i], 1e-6 * t[i]) << i;
    }
}

TEST(Bezier, InsideIsTheWindingNumber) {
    // The straight square agrees with the polygon on a grid, the dented one below its dent.
    auto s = make<Shape>(square), d = make<Shape>(dented);
    for (int i = 0; i <= 40; ++i)
        for (int j = 0; j <= 40; ++j) {
            const double x = -1.25 + 2.5 * i / 40 + 1e-3, y = -1.25 + 2.5 * j / 40 + 1e-3;
            EXPECT_EQ(inside(*s, x, y), std::abs(x) < 1 && std::abs(y) < 1) << x << ", " << y;
        }
    // The dent's bottom is at (0, 0.1); its sides rise to the corners.
    EXPECT_TRUE(inside(*d, 0, 0.09));
    EXPECT_FALSE(inside(*d, 0, 0.11));
    EXPECT_FALSE(inside(*d, 0, 0.9));
    EXPECT_TRUE(inside(*d, 0.97, 0.9));
    EXPECT_TRUE(inside(*d, -0.97, 0.9));
    EXPECT_FALSE(inside(*d, 0.9, 0.9)); // above the dent's flank
    // Either orientation: the same curve given backwards.
    auto back = make<Shape>("{type: bezier, degree: 2, points: [[-1, 0], [0, -2], [1, 0], [0, 2]]}");
    EXPECT_TRUE(inside(*back, 0.5, 0.74));
    EXPECT_FALSE(inside(*back, 0.5, 0.76));
}

TEST(Bezier, ACentreOutsideTheKernelIsRefused) {
    auto d = make<Shape>(dented);
    EXPECT_TRUE(d->in_kernel(d->centre()));
    // The dent's steep flanks hide the top corners from all but the bottom of the square: the
    // tangent at the corner (1, 1), of slope 12 / 7, meets x = 0 at y = -5 / 7.
    EXPECT_TRUE(d->in_kernel({0, -0.9}));
    EXPECT_FALSE(d->in_kernel({0, -0.6}));
    EXPECT_LT(d->centre().y, -5.0 / 7);
    // Inside the set, but the dent hides the far corner: refused, naming the tangent.
    EXPECT_TRUE(inside(*d, 0.9, 0.5));
    EXPECT_FALSE(d->in_kernel({0.9, 0.5}));
    const std::string m = refusal(dented.substr(0, dented.size() - 1) + ", centre: [0.9, 0.5]}");
    EXPECT_NE(m.find("bezier set's centre (0.9, 0.5) is not in its kernel: the tangent of segment"),
              std::string::npos)
        << m;
    // Outside the set altogether.
    EXPECT_FALSE(d->in_kernel({2, 0}));
    // The inversion refuses it as a centre of inversion too.
    try {
        host().make<fp::Transform>("{type: inversion, shape: " + dented + ", centre: [0.9, 0.5]}");
        ADD_FAILURE() << "accepted";
    } catch (const fp::InputError& e) {
        EXPECT_NE(
            std::string(e.what()).find("inversion centre (0.9, 0.5) is outside the kernel of the shape"),
            std::string::npos)
            << e.what();
    }
}

TEST(Bezier, ACircleOfManyArcs) {
    // The unit circle as 600 cubic arcs (handles 4/3 tan(theta / 4) long): past 128 segments
    // the default centre samples fewer tangents per segment; it is still the circle's centre,
    // and the exits its radius (the arcs' error is below 1e-13 at this size).
    const int m = 600;
    const double th = 2 * M_PI / m, k = 4.0 / 3 * std::tan(th / 4);
    std::string pts;
    for (int i = 0; i < m; ++i) {
        const double a = th * i, b = a + th;
        const auto pt = [&](double x, double y) {
            char buf[80];
            std::snprintf(buf, sizeof buf, "[%.17g, %.17g], ", x, y);
            return std::string(buf);
        };
        pts += pt(std::cos(a), std::sin(a)) +
               pt(std::cos(a) - k * std::sin(a), std::sin(a) + k * std::cos(a)) +
               pt(std::cos(b) + k * std::sin(b), std::sin(b) - k * std::cos(b));
    }
    auto s = make<Shape>("{type: bezier, points: [" + pts.substr(0, pts.size() - 2) + "]}");
    EXPECT_NEAR(s->centre().x, 0, 1e-6);
    EXPECT_NEAR(s->centre().y, 0, 1e-6);
    const auto line = s->outline(60000);
    for (int i = 0; i < 50; ++i) {
        const Vec2 d{std::cos(0.37 * i), std::sin(0.37 * i)};
        EXPECT_NEAR(ray(*s, {0.2, -0.1}, d), polyline_exit(line, {0.2, -0.1}, d), 1e-8) << i;
    }
}

TEST(Bezier, BadCurvesAreRefusedWithTheReason) {
    EXPECT_NE(
        refusal("{type: bezier, points: [[0, 0], [1, 0], [1, 1], [0, 1]]}")
            .find("a closed curve of degree 3 takes a multiple of 3 control points (3 per segment), got 4"),
        std::string::npos);
    EXPECT_NE(refusal("{type: bezier, degree: 2, points: [[0, 0], [1, 0], [1, 0], [0, 1]]}")
                  .find("control points 1 and 2 coincide at (1, 0)"),
              std::string::npos);
    EXPECT_NE(refusal("{type: bezier, degree: 2, points: [[0, 0], [1, 0]]}").find("encloses no area"),
              std::string::npos);
    // A symmetric figure eight: its lobes' areas cancel.
    EXPECT_NE(
        refusal(
            "{type: bezier, degree: 2, points: [[0, 0], [1, 1], [2, 0], [1, -1], [0, 0.5], [-1, 1], [-2, 0], "
            "[-1, -1]]}")
            .find("bezier"),
        std::string::npos);
    // Lobes of two sizes: no point sees the whole curve.
    const std::string eight =
        refusal("{type: bezier, degree: 2, points: [[0, 0], [2, 2], [4, 0], [2, -2], [0, 0.1], "
                "[-1, 1], [-2, 0], [-1, -1]]}");
    EXPECT_NE(eight.find("bezier set is not star-shaped: no point sees the whole curve"), std::string::npos)
        << eight;
}

} // namespace
