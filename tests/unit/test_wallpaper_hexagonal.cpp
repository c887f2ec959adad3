// The hexagonal reduction (`reduction: hexagonal`, the SDK's fixpoint/lattice.hpp):
// p minus its nearest point of the hexagonal lattice of periods of p3 ... p6m, into the hexagon
// about 0. Tested:
//   - reductions computed by hand (inside, outside, the tie rule on the boundary);
//   - the map with it is the unreduced map followed by it, bit for bit, and the renderer's
//     reduce_xy is the same function; square groups refuse it with their message;
//   - it commutes with R6 and both mirrors, and the reduced maps of the five groups with their
//     generators, as points (not modulo a lattice), within a few ulps of |p|;
//   - orbits (Picard and the S-iteration through the renderer's reduce_xy): the reduced orbit of
//     g p is g times the reduced orbit of p for 100% of random points with `hexagonal`, for
//     visibly fewer with the paper's square fmod (the figures are printed); Fig. 5(a)'s samples
//     p and R3 p are caught alike (100% against fmod's 97.9%);
//   - the orbit-trap renderer with it gives the same bytes on every SIMD target and thread count
//     (fused and general passes against Algorithm 3: tests/unit/test_orbit_trap.cpp).
#include "host.hpp"

#include "../../plugins/renderers/orbit-trap/reduce.hpp"
#include "../../plugins/transforms/wallpaper_kernel.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/simd.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

using namespace fp::test;

namespace {

using fp::Vec2;
namespace wp = fp_wallpaper;

constexpr double pi = std::numbers::pi;
const double s3 = std::sqrt(3.0);
const char* const hex_groups[] = {"p3", "p3m1", "p31m", "p6", "p6m"};

// Paper 04's Fig. 5 map (p3m1, eq. (8)), as configs/orbit-trap/fig5a.yaml.
const std::string fig5 =
    "group: p3m1, G: [[0.343244, 0.711418], [-0.671499, -0.289951], [-0.959405, -0.868905]], "
    "H: [[-0.224996, 0.0844803], [-0.0571376, 0.0250126], [0.0250892, 0.553883]]";

std::shared_ptr<const fp::Transform> wallpaper(const std::string& params) {
    return host().make<fp::Transform>("{type: wallpaper, " + params + "}");
}

template <class T>
std::vector<Vec2> apply(const fp::Transform& t, const std::vector<Vec2>& pts) {
    std::vector<T> x, y;
    for (const Vec2& p : pts) x.push_back(T(p.x)), y.push_back(T(p.y));
    t.apply(fp::Points<T>{x.data(), y.data(), x.size()}, nullptr);
    std::vector<Vec2> out;
    for (std::size_t i = 0; i < x.size(); ++i) out.push_back({double(x[i]), double(y[i])});
    return out;
}

std::vector<Vec2> random_points(std::uint64_t seed, std::size_t n, double r) {
    fp::Rng rng = fp::chain_stream(seed, 11);
    std::vector<Vec2> pts(n);
    for (Vec2& p : pts) p = {r * (2 * fp::uniform_double(rng) - 1), r * (2 * fp::uniform_double(rng) - 1)};
    return pts;
}

template <class T>
Vec2 red(Vec2 p) {
    T x = T(p.x), y = T(p.y);
    fp::kernels::reduce_hexagonal(x, y);
    return {double(x), double(y)};
}

double dist(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

// R6, R3 and the two mirrors through 0 (the hexagonal groups' point-group generators).
const wp::Op r6{0.5, -s3 / 2, s3 / 2, 0.5, 0, 0}, r3{-0.5, -s3 / 2, s3 / 2, -0.5, 0, 0};
const wp::Op mirror_x{-1, 0, 0, 1, 0, 0}, mirror_y{1, 0, 0, -1, 0, 0};

// ------------------------------------------------------------------ by hand

TEST(WallpaperHexagonal, ReductionsByHand) {
    // Lattice points are (pi k, pi sqrt 3 B) with k = 2 A + B; the hexagon about 0 has its
    // vertices at distance 2 pi / sqrt 3 = 3.628 in the directions 30, 90, ... degrees.
    struct Case {
        Vec2 p, want;
    };
    const Case cases[] = {
        {{3, 0}, {3, 0}},                        // inside (|x| < pi): unchanged
        {{0, 3.6}, {0, 3.6}},                    // inside, just below the vertex (0, 3.628)
        {{4, 0}, {4 - 2 * pi, 0}},               // nearest lattice point (2 pi, 0)
        {{-3.2, 0}, {-3.2 + 2 * pi, 0}},         // (-2 pi, 0)
        {{1, 5}, {1 - pi, 5 - pi * s3}},         // (pi, pi sqrt 3)
        {{-1, -5}, {-1 + pi, -5 + pi * s3}},     // (-pi, -pi sqrt 3)
        {{2 * pi, 0}, {0, 0}},                   // a lattice point: to 0
        {{7, 9}, {7 - 2 * pi, 9 - 2 * pi * s3}}, // (2 pi, 2 pi sqrt 3): a = 0.29, b = 1.65
        {{0, 4}, {pi, 4 - pi * s3}},             // the tie rule: (pi, pi sqrt 3) and (-pi, pi sqrt 3)
        {{0, 3.65}, {pi, 3.65 - pi * s3}},       //   are equally near; the first corner (A, B) =
        {{0, -4}, {pi, pi * s3 - 4}},            //   (floor a, floor b) + (0, 0), (1, 0), (0, 1), (1, 1) wins
    };
    for (const Case& c : cases) {
        const Vec2 d = red<double>(c.p);
        EXPECT_NEAR(d.x, c.want.x, 1e-14) << c.p.x << ", " << c.p.y;
        EXPECT_NEAR(d.y, c.want.y, 1e-14) << c.p.x << ", " << c.p.y;
        const Vec2 f = red<float>(c.p);
        EXPECT_NEAR(f.x, c.want.x, 2e-6) << c.p.x << ", " << c.p.y;
        EXPECT_NEAR(f.y, c.want.y, 2e-6) << c.p.x << ", " << c.p.y;
    }
    // Inside: the very bits (also -0).
    for (double v : {-0.0, 0.0, 1e-300, -3.1}) {
        const Vec2 d = red<double>({v, v / 10});
        EXPECT_EQ(std::signbit(d.x), std::signbit(v));
        EXPECT_EQ(d.x, v);
        EXPECT_EQ(d.y, v / 10);
    }
    // Not finite stays not finite.
    const Vec2 inf = red<double>({INFINITY, 1}), nan = red<float>({NAN, 1});
    EXPECT_FALSE(std::isfinite(inf.x) && std::isfinite(inf.y));
    EXPECT_TRUE(std::isnan(nan.x));
}

TEST(WallpaperHexagonal, ResultsLieInTheHexagon) {
    // Every result of points up to 1000 away is within the hexagon (up to rounding at its rim:
    // the circumradius 2 pi / sqrt 3 and the inradius pi as bounds) and differs from its input by
    // a lattice vector.
    for (const Vec2& p : random_points(3, 20000, 1000)) {
        const Vec2 q = red<double>(p);
        EXPECT_LE(std::hypot(q.x, q.y), 2 * pi / s3 + 1e-12);
        for (double ang : {0.0, pi / 3, 2 * pi / 3})
            EXPECT_LE(std::fabs(q.x * std::cos(ang) + q.y * std::sin(ang)), pi + 1e-12);
        const double B = (p.y - q.y) / (pi * s3), k = (p.x - q.x) / pi;
        EXPECT_NEAR(B, std::nearbyint(B), 1e-9);
        EXPECT_NEAR(k, std::nearbyint(k), 1e-9);
        EXPECT_EQ(std::fmod(std::nearbyint(k) - std::nearbyint(B), 2.0), 0.0); // k = 2 A + B
    }
}

// ------------------------------------------------------------------ the map and the renderer

TEST(WallpaperHexagonal, MapIsTheUnreducedMapThenTheReduction) {
    const auto plain = wallpaper(fig5 + ", reduction: none");
    const auto hex = wallpaper(fig5 + ", reduction: hexagonal");
    const std::vector<Vec2> pts = random_points(5, 3000, 7);
    const auto check = [&](auto zero) {
        using T = decltype(zero);
        const std::vector<Vec2> a = apply<T>(*plain, pts), b = apply<T>(*hex, pts);
        std::vector<T> x, y;
        for (const Vec2& v : a) x.push_back(T(v.x)), y.push_back(T(v.y));
        // The renderer's reduction is the same function (and leaves reduced points alone).
        EXPECT_TRUE(
            fp_orbit_trap::reduce_xy(x.data(), y.data(), x.size(), fp_orbit_trap::Reduction::hexagonal));
        std::size_t inside = 0;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const Vec2 want = red<T>(a[i]);
            ASSERT_EQ(b[i].x, want.x) << i;
            ASSERT_EQ(b[i].y, want.y) << i;
            ASSERT_EQ(double(x[i]), want.x) << i;
            ASSERT_EQ(double(y[i]), want.y) << i;
            inside += fp::kernels::in_cell(x[i], y[i]);
        }
        EXPECT_EQ(inside, pts.size()); // reduced points are in the range (random points: no rim)
        EXPECT_FALSE(
            fp_orbit_trap::reduce_xy(x.data(), y.data(), x.size(), fp_orbit_trap::Reduction::hexagonal));
    };
    check(0.0f);
    check(0.0);
}

TEST(WallpaperHexagonal, SquareGroupsRefuseIt) {
    const auto error_of = [](const std::string& yaml) {
        return fp::test::error_of(fp::Kind::Transform, yaml);
    };
    EXPECT_EQ(
        error_of("{type: wallpaper, group: p4m, seed: 1, reduction: hexagonal}"),
        "transform.reduction: hexagonal is for the hexagonal groups (p3, p3m1, p31m, p6, p6m), "
        "whose lattice of periods is hexagonal; p4m's is the square lattice 2 pi Z^2 (use fmod, centred, "
        "floor or none)");
    for (const char* g : hex_groups)
        EXPECT_EQ(error_of(std::string("{type: wallpaper, group: ") + g + ", seed: 1, reduction: hexagonal}"),
                  "(no error)");
}

// ------------------------------------------------------------------ symmetry

TEST(WallpaperHexagonal, ReductionCommutesWithTheHexagonsSymmetries) {
    // red(g p) = g red(p) as points, up to the rounding of g p (about an ulp of |p| <= 20: 4e-15)
    // and of the reduction's subtraction (an ulp of pi): 1e-12 allows for both many times over.
    // Points within 1e-9 of a cell's rim may go to another lattice point; random points are
    // (practically) never there, so every one must agree.
    const std::vector<Vec2> pts = random_points(9, 20000, 20);
    for (const wp::Op& g : {r6, r3, mirror_x, mirror_y}) {
        std::size_t bad = 0;
        double worst = 0;
        for (const Vec2& p : pts) {
            const double e = dist(red<double>(g(p)), g.linear(red<double>(p)));
            worst = std::max(worst, e);
            bad += e > 1e-12;
        }
        EXPECT_EQ(bad, 0u) << "worst " << worst;
    }
}

// The largest |F(g p) - g F(p)| over the points, F = the map with its reduction.
template <class T>
double worst_commutation(const fp::Transform& t, const std::vector<Vec2>& pts, const wp::Op& g) {
    const std::vector<Vec2> fp_ = apply<T>(t, pts);
    std::vector<Vec2> gp;
    for (const Vec2& p : pts) gp.push_back(g(p));
    const std::vector<Vec2> fgp = apply<T>(t, gp);
    double worst = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) worst = std::max(worst, dist(fgp[i], g.linear(fp_[i])));
    return worst;
}

TEST(WallpaperHexagonal, ReducedMapsCommuteWithTheirGenerators) {
    // F(g p) = g F(p) as points. Floating point does not rotate exactly: g p carries an ulp of
    // |p| <= 7 (9e-16 in double, 5e-7 in float), which f's derivative (up to the sum of
    // |coefficient| |wave vector|, tens here) enlarges, plus the ulps of sin / cos and of the
    // reduction's subtraction. Tolerances: double 1e-11, float 2e-4, a few hundred times the
    // largest differences measured (1.8e-14 and 8.1e-6, printed). Each group's generators, three
    // seeds and Fig. 5's map.
    const std::vector<Vec2> pts = random_points(1, 2000, 7);
    std::vector<std::string> maps;
    for (const char* g : hex_groups)
        for (int seed : {1, 2, 3})
            maps.push_back(std::string("group: ") + g + ", seed: " + std::to_string(seed));
    maps.push_back(fig5);
    double worst_d = 0, worst_f = 0;
    for (const std::string& m : maps) {
        const auto t = wallpaper(m + ", reduction: hexagonal");
        const std::string group = m.substr(7, m.find(',') - 7);
        for (const wp::Op& g : wp::generators(group)) {
            const double d = worst_commutation<double>(*t, pts, g), f = worst_commutation<float>(*t, pts, g);
            EXPECT_LT(d, 1e-11) << m;
            EXPECT_LT(f, 2e-4) << m;
            worst_d = std::max(worst_d, d), worst_f = std::max(worst_f, f);
        }
    }
    std::printf("[ figures  ] largest |F(g p) - g F(p)|: double %.3g, float %.3g\n", worst_d, worst_f);
}

// The fraction of points p whose reduced orbit under F (10 steps) stays within `tol` of g times
// the orbit of g p... i.e. max_k |F^k(g p) - g F^k(p)| < tol, in double.
double orbit_agreement(const fp::Transform& t, const wp::Op& g, const std::vector<Vec2>& pts, int steps,
                       double tol, double* worst_agreeing = nullptr) {
    std::vector<Vec2> a = pts, b;
    for (const Vec2& p : pts) b.push_back(g(p));
    std::vector<double> dev(pts.size(), 0.0);
    for (int k = 0; k < steps; ++k) {
        a = apply<double>(t, a);
        b = apply<double>(t, b);
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const double e = dist(b[i], g.linear(a[i]));
            dev[i] = std::isnan(e) ? INFINITY : std::max(dev[i], e);
        }
    }
    std::size_t n = 0;
    double worst = 0; // of the orbits that agree
    for (double e : dev)
        if (e < tol) ++n, worst = std::max(worst, e);
    if (worst_agreeing) *worst_agreeing = worst;
    return double(n) / double(pts.size());
}

TEST(WallpaperHexagonal, RotatedOrbitsAreRotatedOrbits) {
    // Fig. 5's map (p3m1), 10 steps of Picard from 20000 random points of the paper's area
    // [-2 pi, 2 pi]^2, double. Tolerance 1e-6: the first difference is the rounding of g p
    // (1e-15), which the chaotic map amplifies step by step (measured: the largest difference
    // after 10 steps 1.2e-7 under R3, 4e-8 under the mirror; printed).
    const std::vector<Vec2> pts = random_points(21, 20000, 2 * pi);
    const auto hex = wallpaper(fig5 + ", reduction: hexagonal");
    const auto sq = wallpaper(fig5 + ", reduction: fmod");
    const auto sq_floor = wallpaper(fig5 + ", reduction: floor");
    {
        const auto plain = wallpaper(fig5 + ", reduction: none");
        std::size_t ny = 0;
        double mx = 0, my = 0;
        for (const Vec2& q : apply<double>(*plain, pts)) {
            ny += std::fabs(q.y) >= 2 * pi;
            mx = std::max(mx, std::fabs(q.x)), my = std::max(my, std::fabs(q.y));
        }
        std::printf(
            "[ figures  ] Fig. 5's f on the area: max |f_x| %.3f, max |f_y| %.3f; |f_y| >= 2 pi for %.4f\n",
            mx, my, double(ny) / double(pts.size()));
    }
    for (const auto& [name, g] : {std::pair{"R3", r3}, std::pair{"mirror (-x, y)", mirror_x}}) {
        double worst = 0;
        const double h1 = orbit_agreement(*hex, g, pts, 1, 1e-6),
                     h10 = orbit_agreement(*hex, g, pts, 10, 1e-6, &worst);
        const double s1 = orbit_agreement(*sq, g, pts, 1, 1e-6), s10 = orbit_agreement(*sq, g, pts, 10, 1e-6);
        const double f1 = orbit_agreement(*sq_floor, g, pts, 1, 1e-6),
                     f10 = orbit_agreement(*sq_floor, g, pts, 10, 1e-6);
        std::printf("[ figures  ] %s: orbits agreeing after 1 / 10 steps: hexagonal %.4f / %.4f, fmod %.4f / "
                    "%.4f, floor %.4f / %.4f (hexagonal: largest difference %.3g)\n",
                    name, h1, h10, s1, s10, f1, f10, worst);
        EXPECT_GE(h1, 0.9999) << name;
        EXPECT_GE(h10, 0.999) << name;
        if (std::string(name) == "R3") {
            EXPECT_LT(s10, 0.99) << "fmod does not keep the rotation: the test can fail";
            EXPECT_LT(s10, h10);
        }
    }
}

TEST(WallpaperHexagonal, SIterationOrbitsToo) {
    // Eq. (13) with scalar alpha = 1.1, beta = 0.5 (real multiples commute with R3): the
    // combination leaves the hexagon, so the renderer's reduce_xy (orbit-trap/reduce.hpp) reduces
    // after each step, as the renderer does; double, tolerance 1e-6 as above.
    const auto scheme = host().make<fp::IterationScheme>("{type: s-iteration, alpha: 1.1, beta: 0.5}");
    const std::vector<Vec2> pts = random_points(23, 20000, 2 * pi);
    const auto agree = [&](const std::string& reduction, int steps, bool restart) {
        using fp_orbit_trap::Reduction;
        const auto t = wallpaper(fig5 + ", reduction: " + reduction);
        const Reduction r = reduction == "hexagonal" ? Reduction::hexagonal : Reduction::fmod;
        std::vector<double> ax, ay, bx, by;
        for (const Vec2& p : pts) {
            const Vec2 q = r3(p);
            ax.push_back(p.x), ay.push_back(p.y), bx.push_back(q.x), by.push_back(q.y);
        }
        std::vector<char> ok(pts.size(), 1);
        for (std::uint64_t k = 0; k < std::uint64_t(steps); ++k) {
            if (restart)
                for (std::size_t i = 0; i < pts.size(); ++i) {
                    const Vec2 q = r3({ax[i], ay[i]});
                    bx[i] = q.x, by[i] = q.y;
                }
            scheme->step(*t, fp::Points<double>{ax.data(), ay.data(), ax.size()}, nullptr, k);
            scheme->step(*t, fp::Points<double>{bx.data(), by.data(), bx.size()}, nullptr, k);
            fp_orbit_trap::reduce_xy(ax.data(), ay.data(), ax.size(), r);
            fp_orbit_trap::reduce_xy(bx.data(), by.data(), bx.size(), r);
            for (std::size_t i = 0; i < pts.size(); ++i)
                if (!(dist({bx[i], by[i]}, r3.linear({ax[i], ay[i]})) < 1e-6)) ok[i] = 0;
        }
        std::size_t n = 0;
        for (char c : ok) n += c;
        return double(n) / double(pts.size());
    };
    // Free-running orbits part by chaos alone: the S-iteration's step stretches differences
    // fast (measured: after 10 steps a quarter of the hexagonal pairs differ by more than 1e-6,
    // after 5 none), so: 5 steps free-running, and 10 steps restarted (g applied to the orbit's
    // point before each step: the map's commutation along the orbit, chaos taken out).
    const double hex5 = agree("hexagonal", 5, false), fmod5 = agree("fmod", 5, false);
    const double hex10 = agree("hexagonal", 10, true), fmod10 = agree("fmod", 10, true);
    std::printf(
        "[ figures  ] S-iteration (1.1, 0.5), R3: orbits agreeing after 5 steps: hexagonal %.4f, fmod "
        "%.4f; after 10 steps restarted: hexagonal %.4f, fmod %.4f\n",
        hex5, fmod5, hex10, fmod10);
    EXPECT_GE(hex5, 0.999);
    EXPECT_GE(hex10, 0.999);
    EXPECT_LT(fmod5, 0.9);
    EXPECT_LT(fmod10, 0.9);
}

// Algorithm 3's outcome for one start point under Picard with the map's own reduction and the
// trap of Fig. 1a (the circle |q| < 3.5): the step that caught it (0: never in 100) and d / r.
std::pair<int, double> caught(const fp::Transform& t, Vec2 p) {
    std::vector<Vec2> q = {p};
    for (int k = 1; k <= 100; ++k) {
        q = apply<double>(t, q);
        const double d = std::hypot(q[0].x, q[0].y);
        if (d < 3.5) return {k, d / 3.5};
    }
    return {0, 0.0};
}

TEST(WallpaperHexagonal, Fig5aSamplesKeepTheRotation) {
    // Fig. 5(a) (p3m1 map, one circle r = 3.5 about 0): the fraction of start points p of the
    // paper's area (those whose rotations are in it too: |p| <= 2 pi) where p and R3 p are caught
    // at the same step with the same d / r (within 1e-6): the pattern's 3-fold rotation, sample
    // by sample.
    std::vector<Vec2> pts;
    for (const Vec2& p : random_points(33, 40000, 2 * pi))
        if (std::hypot(p.x, p.y) <= 2 * pi) pts.push_back(p);
    const auto frac = [&](const std::string& reduction) {
        const auto t = wallpaper(fig5 + ", reduction: " + reduction);
        std::size_t same = 0;
        for (const Vec2& p : pts) {
            const auto a = caught(*t, p), b = caught(*t, r3(p));
            same += a.first == b.first && std::fabs(a.second - b.second) < 1e-6;
        }
        return double(same) / double(pts.size());
    };
    const double hex = frac("hexagonal"), fmod = frac("fmod"), none = frac("none"), floor = frac("floor");
    std::printf("[ figures  ] Fig. 5(a), %zu samples: caught alike under R3: hexagonal %.4f, fmod %.4f, none "
                "%.4f, floor %.4f\n",
                pts.size(), hex, fmod, none, floor);
    EXPECT_GE(hex, 0.999);
    EXPECT_LT(fmod, hex);
}

// ------------------------------------------------------------------ renders

TEST(WallpaperHexagonal, EveryTargetGivesTheSameBytes) {
    // The map's loops (per target) and the renderer's passes (fused: circles; general: the
    // Chebyshev metric) with the hexagonal reduction, Picard and the S-iteration (whose
    // combination leaves the hexagon, so the renderer reduces), float and double.
    const std::string map = "{type: wallpaper, " + fig5 + ", reduction: hexagonal}";
    const std::string base =
        "type: orbit-trap, width: 48, height: 48, max_iterations: 60, reduction: hexagonal, "
        "mapping: " +
        map + ", ";
    const std::vector<std::string> recipes = {
        base + "samples: 1, traps: {type: circles, preset: fig-1b}",
        base + "samples: 8, traps: {type: circles, preset: fig-1d}",
        base + "samples: 1, traps: {type: circles, preset: fig-1b, metric: {type: chebyshev}}",
        base + "samples: 1, iteration: {type: s-iteration, alpha: 1.1, beta: 0.5}, traps: {type: circles, "
               "preset: fig-1b}",
        base + "samples: 1, precision: double, iteration: {type: s-iteration, alpha: 1.1, beta: 0.5}, traps: "
               "{type: circles, preset: fig-1b}",
    };
    const std::vector<std::string> targets = fp::simd::supported_targets();
    ASSERT_FALSE(targets.empty());
    for (const auto& r : recipes) {
        ASSERT_TRUE(fp::simd::force_target(""));
        const Render best = render("{" + r + "}", 2);
        EXPECT_GT(best.stats.drawn, 0u) << r;
        for (const auto& t : targets) {
            ASSERT_TRUE(fp::simd::force_target(t)) << t;
            const Render other = render("{" + r + "}", t == targets.back() ? 1 : 3);
            EXPECT_TRUE(best.img.pixels == other.img.pixels) << t << ": " << r;
            EXPECT_EQ(best.stats.drawn, other.stats.drawn) << t << ": " << r;
        }
    }
    EXPECT_TRUE(fp::simd::force_target(""));
}

} // namespace
