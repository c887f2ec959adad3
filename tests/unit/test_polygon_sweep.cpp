// The polygon checks that replaced quadratic ones (issue "Hardening": one polygon of 40 000
// vertices took 17.6 s to validate): the Shamos–Hoey sweep agrees with testing every pair of
// edges, and the sorted half-plane intersection with edge-by-edge clipping.
#include "../../plugins/shapes/polygon_core.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

namespace {

using fp::Vec2;
using namespace fp_shapes;

// The check the sweep replaced: every pair of edges that are not neighbours.
std::optional<std::pair<std::size_t, std::size_t>> brute_force(const std::vector<Vec2>& v) {
    const std::size_t n = v.size();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 2; j < n; ++j) {
            if (i == 0 && j == n - 1) continue;
            if (detail::segments_meet(v[i], v[(i + 1) % n], v[j], v[(j + 1) % n]))
                return std::make_pair(i, j);
        }
    return std::nullopt;
}

// What the sweep assumes of its input (validate_polygon refuses the rest): no edge of zero
// length, no edge folding back onto its neighbour.
bool sweep_applies(const std::vector<Vec2>& v) {
    const std::size_t n = v.size();
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2 a = detail::sub(v[(i + 1) % n], v[i]), b = detail::sub(v[(i + 2) % n], v[(i + 1) % n]);
        if ((a.x == 0 && a.y == 0) || (detail::cross(a, b) == 0 && a.x * b.x + a.y * b.y < 0)) return false;
    }
    return true;
}

// Random polygons on a small integer grid, where shared vertices, touching edges, collinear
// overlaps and vertical edges are common and every orientation test is exact.
TEST(PolygonSweep, AgreesWithEveryPairOnDegenerateGridPolygons) {
    std::mt19937 rng(20261123);
    int simple = 0, crossing = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const int n = 3 + int(rng() % 9), side = 2 + int(rng() % 5);
        std::vector<Vec2> v;
        for (int i = 0; i < n; ++i) v.push_back({double(rng() % side), double(rng() % side)});
        if (!sweep_applies(v)) continue;
        const auto expected = brute_force(v);
        const auto got = detail::find_crossing(v, detail::segments_meet);
        ASSERT_EQ(got.has_value(), expected.has_value()) << "trial " << trial;
        if (got) {
            // Any pair it names must really meet.
            EXPECT_TRUE(detail::segments_meet(v[got->first], v[(got->first + 1) % v.size()], v[got->second],
                                              v[(got->second + 1) % v.size()]));
            ++crossing;
        } else {
            ++simple;
        }
    }
    // Both outcomes were exercised many times.
    EXPECT_GT(simple, 500);
    EXPECT_GT(crossing, 500);
}

// The polygon of `n` vertices at the angles 2 pi i / n and the radii rho(i) (called in turn, from
// i = 0) about the origin.
template <class Rho>
std::vector<Vec2> star(std::size_t n, Rho rho) {
    std::vector<Vec2> v;
    for (std::size_t i = 0; i < n; ++i) {
        const double a = 2 * std::numbers::pi * double(i) / double(n), r = rho(i);
        v.push_back({r * std::cos(a), r * std::sin(a)});
    }
    return v;
}

// Star-shaped polygons with random radii (simple) and the same with two vertices swapped
// (crossing, usually), in general position.
TEST(PolygonSweep, AgreesWithEveryPairOnRandomStars) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> r(0.2, 1.0);
    for (int trial = 0; trial < 300; ++trial) {
        const std::size_t n = 5 + rng() % 200;
        std::vector<Vec2> v = star(n, [&](std::size_t) { return r(rng); });
        EXPECT_FALSE(detail::find_crossing(v, detail::segments_meet).has_value()) << "trial " << trial;
        std::swap(v[rng() % n], v[rng() % n]);
        if (!sweep_applies(v)) continue;
        EXPECT_EQ(detail::find_crossing(v, detail::segments_meet).has_value(), brute_force(v).has_value())
            << "trial " << trial;
    }
}

TEST(PolygonSweep, ABowtieCrossesAtEdgesZeroAndTwo) {
    const std::vector<Vec2> v = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
    const auto c = detail::find_crossing(v, detail::segments_meet);
    ASSERT_TRUE(c.has_value());
    EXPECT_EQ(*c, std::make_pair(std::size_t(0), std::size_t(2)));
}

// Area and centroid of a convex polygon, for comparing kernels whose vertices may differ in
// rounding and in near-duplicate points.
std::pair<double, Vec2> area_and_centroid(const std::vector<Vec2>& k) {
    return {detail::signed_area(k), centroid(k)};
}

TEST(PolygonKernel, SortedIntersectionAgreesWithClipping) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> r(0.5, 1.0);
    for (int trial = 0; trial < 40; ++trial) {
        const std::size_t n = 600 + rng() % 1500;
        const double cx = r(rng) - 0.75, cy = r(rng) - 0.75;
        // Mostly convex-ish, with dents every few vertices so that the kernel is smaller.
        std::vector<Vec2> v = star(n, [&](std::size_t i) { return i % 7 == 0 ? 0.6 * r(rng) : r(rng); });
        for (auto& p : v) p = {cx + p.x, cy + p.y};
        const auto a = polygon_kernel_clipped(v), b = polygon_kernel_sorted(v);
        ASSERT_EQ(a.empty(), b.empty()) << "trial " << trial;
        if (a.empty()) continue;
        const auto [area_a, ca] = area_and_centroid(a);
        const auto [area_b, cb] = area_and_centroid(b);
        EXPECT_NEAR(area_b, area_a, 1e-9 * std::abs(area_a)) << "trial " << trial;
        EXPECT_NEAR(cb.x, ca.x, 1e-9) << "trial " << trial;
        EXPECT_NEAR(cb.y, ca.y, 1e-9) << "trial " << trial;
    }
    // A regular 2000-gon is its own kernel.
    std::vector<Vec2> v;
    for (int i = 0; i < 2000; ++i)
        v.push_back({std::cos(i * std::numbers::pi / 1000), std::sin(i * std::numbers::pi / 1000)});
    const auto k = polygon_kernel_sorted(v);
    EXPECT_NEAR(detail::signed_area(k), detail::signed_area(v), 1e-12);
    // A polygon with no kernel: two far lobes joined by a thin neck.
    const std::vector<Vec2> dumbbell = {{0, 0}, {1, 0}, {1, 0.45}, {5, 0.45}, {5, 0}, {6, 0},
                                        {6, 1}, {5, 1}, {5, 0.55}, {1, 0.55}, {1, 1}, {0, 1}};
    EXPECT_TRUE(polygon_kernel_sorted(dumbbell).empty());
    EXPECT_TRUE(polygon_kernel_clipped(dumbbell).empty());
}

} // namespace
