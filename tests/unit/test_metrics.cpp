// The metrics of paper 04, eqs. (14)-(16): hand-computed distances, the unit circles of Fig. 2
// (points built on each metric's unit circle are at distance 1 from the centre), the float path,
// and the circles trap (first trap wins, d / r). The metric axioms are in the conformance suite.
#include "host.hpp"

#include <fixpoint/fixpoint.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::Metric;
using fp::Vec2;

std::shared_ptr<const Metric> metric_of(const std::string& yaml) { return host().make<Metric>(yaml); }

double dist(const Metric& m, Vec2 p, Vec2 c) {
    double d = -1;
    m.distance(fp::Points<const double>{&p.x, &p.y, 1}, c, &d);
    return d;
}

TEST(Metrics, HandComputed) {
    // p = (4, -3), c = (1, 1): |dx| = 3, |dy| = 4.
    const Vec2 p{4, -3}, c{1, 1};
    EXPECT_EQ(dist(*make<Metric>("{type: lp, p: 1}"), p, c), 7.0);
    EXPECT_EQ(dist(*make<Metric>("{type: lp}"), p, c), 5.0); // p = 2 by default: the 3-4-5 triangle
    EXPECT_EQ(dist(*make<Metric>("{type: lp, p: .inf}"), p, c), 4.0);
    EXPECT_EQ(dist(*make<Metric>("{type: chebyshev}"), p, c), 4.0);
    // (3^3 + 4^3)^(1/3) = 91^(1/3) = 4.497941445275415...
    EXPECT_NEAR(dist(*make<Metric>("{type: lp, p: 3}"), p, c), 4.497941445275415, 1e-14);
    // Rickman, gamma = 0.5: 3 + 4^0.5 = 5; gamma = 0.25: 3 + 4^0.25 = 3 + sqrt 2.
    EXPECT_NEAR(dist(*make<Metric>("{type: rickman, gamma: 0.5}"), p, c), 5.0, 1e-15);
    EXPECT_NEAR(dist(*make<Metric>("{type: rickman, gamma: 0.25}"), p, c), 3 + std::sqrt(2.0), 1e-15);
    // Rickman is not symmetric in x and y: |dx| enters linearly.
    EXPECT_NEAR(dist(*make<Metric>("{type: rickman, gamma: 0.5}"), {1, 5}, c), 0 + 2.0, 1e-15);
}

// Fig. 2: circles of radius 1 about the origin. For lp, (sgn c |c|^(2/p), sgn s |s|^(2/p)) with
// (c, s) = (cos t, sin t) satisfies |x|^p + |y|^p = c^2 + s^2 = 1.
TEST(Metrics, UnitCirclesOfFig2) {
    for (double p : {1.0, 1.5, 2.0, 2.5, 3.0, 7.5}) {
        auto m = make<Metric>("{type: lp, p: " + std::to_string(p) + "}");
        for (int k = 0; k < 360; ++k) {
            const double t = 2 * std::numbers::pi * k / 360.0, c = std::cos(t), s = std::sin(t);
            const Vec2 q{std::copysign(std::pow(std::fabs(c), 2 / p), c),
                         std::copysign(std::pow(std::fabs(s), 2 / p), s)};
            EXPECT_NEAR(dist(*m, q, {0, 0}), 1.0, 1e-12) << "p = " << p << ", t = " << t;
            // The same circle moved to another centre.
            EXPECT_NEAR(dist(*m, {q.x + 3, q.y - 2}, {3, -2}), 1.0, 1e-12) << "p = " << p;
        }
    }
    // Chebyshev (and lp with p = .inf): the square with corners (+-1, +-1).
    for (const char* y : {"{type: chebyshev}", "{type: lp, p: .inf}"}) {
        auto m = make<Metric>(y);
        for (int k = 0; k <= 20; ++k) {
            const double t = -1 + k / 10.0;
            for (Vec2 q : {Vec2{1, t}, Vec2{-1, t}, Vec2{t, 1}, Vec2{t, -1}})
                EXPECT_EQ(dist(*m, q, {0, 0}), 1.0) << y;
        }
    }
    // Rickman: |x| + |y|^gamma = 1, i.e. y = +-(1 - |x|)^(1 / gamma).
    for (double g : {0.1, 0.5, 0.7, 0.9}) {
        auto m = make<Metric>("{type: rickman, gamma: " + std::to_string(g) + "}");
        for (int k = 0; k <= 40; ++k) {
            const double x = -1 + k / 20.0, y = std::pow(1 - std::fabs(x), 1 / g);
            EXPECT_NEAR(dist(*m, {x, y}, {0, 0}), 1.0, 1e-12) << "gamma = " << g << ", x = " << x;
            EXPECT_NEAR(dist(*m, {x, -y}, {0, 0}), 1.0, 1e-12) << "gamma = " << g << ", x = " << x;
        }
    }
}

TEST(Metrics, FloatPathAgreesWithDouble) {
    for (const char* y : {"{type: lp, p: 1}", "{type: lp}", "{type: lp, p: 2.5}", "{type: chebyshev}",
                          "{type: rickman, gamma: 0.3}"}) {
        auto m = make<Metric>(y);
        std::vector<float> xf, yf;
        std::vector<double> xd, yd;
        for (int i = 0; i < 300; ++i) {
            const float a = float(std::sin(i * 0.37) * 6), b = float(std::cos(i * 1.13) * 6);
            xf.push_back(a), yf.push_back(b), xd.push_back(a), yd.push_back(b);
        }
        std::vector<float> df(300);
        std::vector<double> dd(300);
        m->distance(fp::Points<const float>{xf.data(), yf.data(), 300}, {0.5, -1}, df.data());
        m->distance(fp::Points<const double>{xd.data(), yd.data(), 300}, {0.5, -1}, dd.data());
        for (int i = 0; i < 300; ++i)
            EXPECT_NEAR(df[size_t(i)], dd[size_t(i)], 2e-6 * (1 + dd[size_t(i)])) << y;
    }
}

TEST(Metrics, BadInput) {
    EXPECT_EQ(error_of(fp::Kind::Metric, "{type: lp, p: 0.5}"),
              "metric.p: the lp metric needs p >= 1 (for p < 1 the triangle inequality fails), got 0.5");
    EXPECT_EQ(error_of(fp::Kind::Metric, "{type: lp, p: .nan}"),
              "metric.p: the lp metric needs p >= 1 (for p < 1 the triangle inequality fails), got nan");
    EXPECT_EQ(error_of(fp::Kind::Metric, "{type: rickman, gamma: 1}"),
              "metric.gamma: Rickman's rug metric needs gamma in the open interval (0, 1), got 1");
    EXPECT_EQ(error_of(fp::Kind::Metric, "{type: rickman, gamma: 0}"),
              "metric.gamma: Rickman's rug metric needs gamma in the open interval (0, 1), got 0");
}

// ------------------------------------------------------------------ the circles trap

struct Hit {
    std::int32_t trap;
    double ratio;
};

Hit test_point(const fp::Trap& t, Vec2 p) {
    Hit h{-2, -1};
    t.test(fp::Points<const double>{&p.x, &p.y, 1}, &h.trap, &h.ratio);
    return h;
}

TEST(CirclesTrap, FirstTrapWinsWithRatio) {
    // Two overlapping circles: (0, 0) r 2 and (1, 0) r 2; (1, 0) lies in both: the first wins.
    auto t = host().make<fp::Trap>("{type: circles, centres: [[0, 0], [1, 0]], radii: [2, 2]}");
    ASSERT_TRUE(t);
    EXPECT_EQ(t->count(), 2u);
    Hit h = test_point(*t, {1, 0});
    EXPECT_EQ(h.trap, 0);
    EXPECT_EQ(h.ratio, 0.5);
    h = test_point(*t, {2.5, 0}); // only the second: d = 1.5, r = 2
    EXPECT_EQ(h.trap, 1);
    EXPECT_EQ(h.ratio, 0.75);
    EXPECT_EQ(test_point(*t, {3, 0}).trap, -1); // on the boundary: d < r is strict
    EXPECT_EQ(test_point(*t, {0, 5}).trap, -1);
    // One radius for all; another metric: Chebyshev squares of half-side 1.
    auto sq =
        host().make<fp::Trap>("{type: circles, metric: {type: chebyshev}, centres: [[0, 0]], radii: [1]}");
    h = test_point(*sq, {0.9, -0.9});
    EXPECT_EQ(h.trap, 0);
    EXPECT_NEAR(h.ratio, 0.9, 1e-15);
}

TEST(CirclesTrap, Presets) {
    const double s3 = std::sqrt(3.0);
    struct P {
        const char* name;
        std::vector<Vec2> centres;
        double r;
    };
    const std::vector<P> presets = {
        {"fig-1a", {{0, 0}}, 3.5},
        {"fig-1b", {{-3.5, -2}, {3.5, -2}, {0, -2 + 3.5 * s3}}, 3.5},
        {"fig-1c", {{-3.5, 3.5}, {3.5, 3.5}, {-3.5, -3.5}, {3.5, -3.5}}, 3.5},
        {"fig-1d",
         {{0, 0}, {0, 7}, {-3.5 * s3, 3.5}, {-3.5 * s3, -3.5}, {0, -7}, {3.5 * s3, -3.5}, {3.5 * s3, 3.5}},
         3.5},
        {"fig-3a", {{0, 3.5}, {0, -3.5}}, 3.5},
        {"fig-3b", {{4, 0}, {-4, 0}, {0, 4}, {0, -4}}, 2 * std::sqrt(2.0)},
        {"fig-3c", {{0, 0}, {-6, 0}, {6, 0}, {0, -6}, {0, 6}}, 3},
    };
    for (const auto& p : presets) {
        auto t = host().make<fp::Trap>(std::string("{type: circles, preset: ") + p.name + "}");
        ASSERT_EQ(t->count(), p.centres.size()) << p.name;
        for (std::size_t i = 0; i < p.centres.size(); ++i) {
            // The centre is caught by its own circle with ratio 0 (circles only touch), and a
            // point at 0.99 r from it (away from the others' tangent points) at 0.99.
            Hit h = test_point(*t, p.centres[i]);
            EXPECT_EQ(h.trap, std::int32_t(i)) << p.name;
            EXPECT_EQ(h.ratio, 0.0) << p.name;
        }
    }
    // Fig. 3b: the circles are pairwise tangent (|c_i - c_j| = 4 sqrt 2 = 2 r for neighbours), so
    // the origin is in none of them; neither is (2, 2), their common tangent point.
    auto t = host().make<fp::Trap>("{type: circles, preset: fig-3b}");
    EXPECT_EQ(test_point(*t, {0, 0}).trap, -1);
    EXPECT_EQ(test_point(*t, {2, 2}).trap, -1);
    Hit h = test_point(*t, {4 + 2.8 * 0.5, 0});
    EXPECT_EQ(h.trap, 0);
    EXPECT_NEAR(h.ratio, 1.4 / (2 * std::sqrt(2.0)), 1e-15);
}

// The trap compares keys (squared Euclidean distances, no root) but must catch exactly the points
// whose distance is below r (Algorithm 3, line 12), at the rim too, in float and double.
TEST(CirclesTrap, KeysDecideAsTheDistanceDoes) {
    for (const char* metric :
         {"{type: lp}", "{type: lp, p: 3}", "{type: chebyshev}", "{type: rickman, gamma: 0.5}"}) {
        auto m = metric_of(metric);
        auto t = host().make<fp::Trap>(std::string("{type: circles, metric: ") + metric +
                                       ", centres: [[4, 0], [0.3, -0.7]], radii: [2.8284271247461903, 1.1]}");
        std::vector<double> x, y;
        for (int k = 0; k < 2000; ++k) {
            const double a = 0.0031 * k * k, r = k % 2 ? 2.8284271247461903 : 1.1;
            const Vec2 c = k % 2 ? Vec2{4, 0} : Vec2{0.3, -0.7};
            const double px = c.x + r * std::cos(a), py = c.y + r * std::sin(a); // on the rim, rounded
            for (double e : {-1.0, 0.0, 1.0}) {
                x.push_back(px + e * 1e-15 * (k % 3)), y.push_back(py);
            }
        }
        x.push_back(2), y.push_back(2); // the tangent point of two circles of Fig. 3b
        const std::size_t n = x.size();
        std::vector<std::int32_t> trap(n);
        std::vector<double> ratio(n);
        t->test(fp::Points<const double>{x.data(), y.data(), n}, trap.data(), ratio.data());
        std::vector<float> xf(x.begin(), x.end()), yf(y.begin(), y.end()), ratio_f(n);
        std::vector<std::int32_t> trap_f(n);
        t->test(fp::Points<const float>{xf.data(), yf.data(), n}, trap_f.data(), ratio_f.data());
        const Vec2 centres[2] = {{4, 0}, {0.3, -0.7}};
        const double radii[2] = {2.8284271247461903, 1.1};
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < n; ++i) {
            std::int32_t want = -1, want_f = -1;
            for (int k = 1; k >= 0; --k) {
                double d;
                m->distance(fp::Points<const double>{&x[i], &y[i], 1}, centres[k], &d);
                if (d < radii[k]) want = k;
                float df;
                m->distance(fp::Points<const float>{&xf[i], &yf[i], 1}, centres[k], &df);
                if (df < float(radii[k])) want_f = k;
            }
            wrong += trap[i] != want || trap_f[i] != want_f;
        }
        EXPECT_EQ(wrong, 0u) << metric;
    }
}

TEST(CirclesTrap, BadInput) {
    EXPECT_EQ(error_of(fp::Kind::Trap, "{type: circles}"),
              "trap: no traps: give centres and radii, or a preset (fig-1a, fig-1b, fig-1c, fig-1d, fig-3a, "
              "fig-3b, fig-3c)");
    EXPECT_EQ(error_of(fp::Kind::Trap, "{type: circles, centres: [[0, 0], [1, 1]], radii: [1, 2, 3]}"),
              "trap.radii: expected 1 radius (for all) or 2 (one per centre), got 3");
    EXPECT_EQ(error_of(fp::Kind::Trap, "{type: circles, centres: [[0, 0]], radii: [0]}"),
              "trap.radii[0]: must be > 0, got 0");
    EXPECT_EQ(error_of(fp::Kind::Trap, "{type: circles, centres: [], radii: [1]}"),
              "trap.centres: the list of points is empty");
    EXPECT_EQ(error_of(fp::Kind::Trap, "{type: circles, centres: [[0, 0]]}"),
              "trap.centres: centres without radii: give radii (one per centre, or one)");
    EXPECT_EQ(error_of(fp::Kind::Trap, "{type: circles, preset: fig-3b, radii: [1]}"),
              "trap.radii: give either a preset or centres and radii, not both");
}

} // namespace
