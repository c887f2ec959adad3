// julia-inverse: the two branches +-sqrt(z - c) of the inverse of f(z) = z^2 + c. Hand values
// (exact squares), the branch cut and the origin, both branches inverting f, the same bits on
// every instruction set and against std::sqrt of std::complex; and the chaos game over the
// branches drawing the Julia set: its points stay bounded under forward iteration, and each
// lies near the basin of infinity's boundary (a point within 0.01 of it escapes).
#include "host.hpp"

#include <fixpoint/host/core/host.hpp>
#include <fixpoint/simd.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::Transform;
using fp::Vec2;

std::shared_ptr<const Transform> branch(const std::string& c, int b) {
    return make<Transform>("{type: julia-inverse, c: " + c + ", branch: " + std::to_string(b) + "}");
}

} // namespace

TEST(JuliaInverse, SquareRootsByHand) {
    // c = 1 + 2i: z = 4 + 6i gives z - c = 3 + 4i = (2 + i)^2.
    expect_point(apply(*branch("[1, 2]", 0), {4, 6}), {2, 1}, 0);
    expect_point(apply(*branch("[1, 2]", 1), {4, 6}), {-2, -1}, 0);
    // Left half-plane (the other formula): -3 + 4i = (1 + 2i)^2; -3 - 4i = (1 - 2i)^2.
    expect_point(apply(*branch("[0, 0]", 0), {-3, 4}), {1, 2}, 0);
    expect_point(apply(*branch("[0, 0]", 0), {-3, -4}), {1, -2}, 0);
    // On the cut: sqrt(-4) = 2i (b = +0), and sqrt of -4 - 0i is -2i, as C's csqrt.
    expect_point(apply(*branch("[0, 0]", 0), {-4, 0}), {0, 2}, 0);
    expect_point(apply(*branch("[0, 0]", 0), {-4, -0.0}), {0, -2}, 0);
    // The critical value c itself goes to 0 (not NaN), on both branches.
    expect_point(apply(*branch("[-0.123, 0.745]", 0), {-0.123, 0.745}), {0, 0}, 0);
    expect_point(apply(*branch("[-0.123, 0.745]", 1), {-0.123, 0.745}), {0, 0}, 0);
    // The default is the Douady rabbit's c, branch 0.
    expect_point(apply(*make<Transform>("{type: julia-inverse}"), {0.877, 0.745}), {1, 0}, 1e-15);
}

// Each branch inverts f to rounding, on every instruction set the same bits as a scalar
// reference of the same formula, and within an ulp or two of std::sqrt(std::complex); float too.
TEST(JuliaInverse, BranchesInvertTheMapOnEveryTarget) {
    const double cr = -0.7269, ci = 0.1889;
    std::vector<double> xs, ys;
    for (int i = 0; i < 203; ++i) { // not a multiple of any lane count: the tail too
        const double a = 0.37 * i, r = 0.05 + 0.02 * i;
        xs.push_back(r * std::cos(a)), ys.push_back(r * std::sin(a));
    }
    const auto plus = branch("[-0.7269, 0.1889]", 0), minus = branch("[-0.7269, 0.1889]", 1);
    std::vector<double> want_x(xs.size()), want_y(xs.size());
    for (size_t i = 0; i < xs.size(); ++i) {
        const std::complex<double> w = std::sqrt(std::complex<double>(xs[i] - cr, ys[i] - ci));
        want_x[i] = w.real(), want_y[i] = w.imag();
    }
    std::vector<double> first_x, first_y;
    for (const auto& target : fp::simd::supported_targets()) {
        ASSERT_TRUE(fp::simd::force_target(target)) << target;
        std::vector<double> x = xs, y = ys, nx = xs, ny = ys;
        plus->apply(fp::Points<double>{x.data(), y.data(), x.size()}, nullptr);
        minus->apply(fp::Points<double>{nx.data(), ny.data(), nx.size()}, nullptr);
        for (size_t i = 0; i < xs.size(); ++i) {
            EXPECT_NEAR(x[i], want_x[i], 4e-16 * (1 + std::fabs(want_x[i]))) << i << " on " << target;
            EXPECT_NEAR(y[i], want_y[i], 4e-16 * (1 + std::fabs(want_y[i]))) << i << " on " << target;
            EXPECT_EQ(nx[i], -x[i]);
            EXPECT_EQ(ny[i], -y[i]);
            EXPECT_GE(x[i], 0.0);
            // f(branch(z)) = z.
            EXPECT_NEAR(x[i] * x[i] - y[i] * y[i] + cr, xs[i], 1e-14);
            EXPECT_NEAR(2 * x[i] * y[i] + ci, ys[i], 1e-14);
        }
        if (first_x.empty()) {
            first_x = x, first_y = y;
        } else {
            EXPECT_EQ(x, first_x) << target;
            EXPECT_EQ(y, first_y) << target;
        }
        // Float, and a mask: the points left out keep their values.
        std::vector<float> fx(xs.begin(), xs.end()), fy(ys.begin(), ys.end());
        std::vector<unsigned char> mask(xs.size());
        for (size_t i = 0; i < mask.size(); ++i) mask[i] = i % 3 != 0;
        plus->apply(fp::Points<float>{fx.data(), fy.data(), fx.size()}, mask.data());
        for (size_t i = 0; i < xs.size(); ++i) {
            if (!mask[i]) {
                EXPECT_EQ(fx[i], float(xs[i]));
                continue;
            }
            EXPECT_NEAR(fx[i], want_x[i], 2e-6 * (1 + std::fabs(want_x[i]))) << i << " on " << target;
            EXPECT_NEAR(fy[i], want_y[i], 2e-6 * (1 + std::fabs(want_y[i]))) << i << " on " << target;
        }
    }
    EXPECT_TRUE(fp::simd::force_target(""));
}

// The chaos game over both branches draws J_c. For the Douady rabbit (c = -0.123 + 0.745i,
// a connected Julia set with interior), 200 000 points from one chain after 100 steps: every
// point stays in |z| <= 2 for 20 forward steps of f (J_c is invariant under f; f expands along
// J_c at the rate 2 a step on average (the Lyapunov exponent of a connected quadratic Julia
// set is log 2), so rounding grows to about 1e-10), and every 1000th point has a point within
// 0.01 that escapes |z| > 2 within 500 steps (it lies on the boundary of the basin of infinity,
// which is J_c), while 0, in the basin of the attracting 3-cycle, never escapes.
TEST(JuliaInverse, TheChaosGameDrawsTheJuliaSet) {
    const double cr = -0.123, ci = 0.745;
    const auto plus = branch("[-0.123, 0.745]", 0), minus = branch("[-0.123, 0.745]", 1);
    fp::Rng rng = fp::chain_stream(7, 0);
    Vec2 z{0.3, 0.1};
    std::vector<Vec2> points;
    for (int n = 0; n < 200100; ++n) {
        const auto& t = fp::uniform_double(rng) < 0.5 ? *plus : *minus;
        z = apply(t, z);
        if (n >= 100) points.push_back(z);
    }
    auto escapes = [&](std::complex<double> w, int steps) {
        for (int k = 0; k < steps; ++k) {
            if (std::abs(w) > 2) return true;
            w = w * w + std::complex<double>(cr, ci);
        }
        return std::abs(w) > 2;
    };
    size_t unbounded = 0;
    for (const Vec2& p : points) unbounded += escapes({p.x, p.y}, 20);
    EXPECT_EQ(unbounded, 0u);
    size_t far = 0, checked = 0;
    for (size_t i = 0; i < points.size(); i += 1000, ++checked) {
        bool near = false;
        for (int k = 0; k < 48 && !near; ++k) {
            const int ring = k / 16; // radii 0.01, 0.005, 0.0033
            const double a = 2 * M_PI * k / 16, r = 0.01 / double(1 + ring);
            near = escapes({points[i].x + r * std::cos(a), points[i].y + r * std::sin(a)}, 500);
        }
        far += !near;
    }
    EXPECT_EQ(checked, 200u);
    EXPECT_EQ(far, 0u);
    EXPECT_FALSE(escapes({0, 0}, 500)); // 0 is in the filled set's interior: not J_c
}
