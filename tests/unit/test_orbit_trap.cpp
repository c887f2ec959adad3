// The orbit-trap renderer (paper 04, Algorithm 3): pixels computed by hand, the S-iteration
// with alpha = 1, beta = 0 equal to Picard, a p4m pattern invariant pixel for pixel under the
// square's symmetries, the lattice period of Picard patterns, threads, and the exact reduction.
#include "host.hpp"

#include "../../plugins/renderers/orbit-trap/reduce.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

using namespace fp::test;

namespace {

const std::string& p4m = fp::test::p4m_fig8;

std::string orbit_trap(const std::string& extra, int size = 64) {
    return "{type: orbit-trap, width: " + std::to_string(size) + ", height: " + std::to_string(size) +
           ", mapping: " + p4m + ", traps: {type: circles, preset: fig-3b}, " + extra + "}";
}

#define REQUIRE_WALLPAPER()                                                                                  \
    if (!has_plugin(p4m)) GTEST_SKIP() << "the wallpaper transform is not built"

std::array<float, 3> px(const fp::Image& img, int i, int j) {
    const float* p = img.pixels.data() + 3 * (std::size_t(j) * std::size_t(img.width) + std::size_t(i));
    return {p[0], p[1], p[2]};
}

TEST(OrbitTrap, PixelsByHand) {
    // The identity map, one Euclidean circle of radius 1.6 about the origin, a 5 x 5 image of
    // [-2, 2]^2 (pixel points -2, -1, 0, 1, 2), black to white with E = 1 (entry i is the grey
    // i / (1 + i)), blue background. Every point is caught at step 1 or never:
    //   (0, 0): d / r = 0, entry 0: black;
    //   (+-1, 0), (0, +-1): d / r = 0.625, v / (1 - v) = 1.67, entry 1: grey 1/2;
    //   (+-1, +-1): d / r = sqrt 2 / 1.6 = 0.884, v / (1 - v) = 7.6, entry 7: grey 7/8;
    //   the rest (|x| or |y| = 2): d >= 2 > 1.6: blue.
    const auto r = render("{type: orbit-trap, width: 5, height: 5, area: [-2, 2, -2, 2], samples: 1, "
                          "mapping: {type: affine, coefficients: [1, 0, 0, 1, 0, 0]}, reduction: none, "
                          "traps: {type: circles, centres: [[0, 0]], radii: [1.6]}, background: [0, 0, 1], "
                          "colourer: {type: colour-map, colours: [0, 0, 0, 255, 255, 255], ratios: [0, 1], "
                          "E: 1, Nc: 100}}");
    ASSERT_EQ(r.img.width, 5);
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) {
            const int x = i - 2, y = 2 - j; // row 0 is the top: y = ymax
            std::array<float, 3> want{0, 0, 1};
            if (x == 0 && y == 0) {
                want = {0, 0, 0};
            } else if (std::abs(x) + std::abs(y) == 1) {
                want = {0.5f, 0.5f, 0.5f};
            } else if (std::abs(x) == 1 && std::abs(y) == 1) {
                want = {0.875f, 0.875f, 0.875f};
            }
            const auto got = px(r.img, i, j);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[size_t(c)], want[size_t(c)], 1e-6) << i << ", " << j;
        }
    EXPECT_EQ(r.stats.samples, 25u);
    EXPECT_EQ(r.stats.drawn, 9u);
    EXPECT_EQ(r.stats.unit, "pixel samples");
}

TEST(OrbitTrap, SIterationWithAlphaOneBetaZeroIsPicard) {
    REQUIRE_WALLPAPER();
    // Eq. (13) with alpha = [1, 0], beta = [0, 0] in the complex numbers: u = p, p' = f(u) = f(p).
    for (const char* precision : {"float", "double"}) {
        const std::string common = "samples: 1, max_iterations: 60, precision: " + std::string(precision);
        const auto a = render(orbit_trap(common));
        const auto b =
            render(orbit_trap(common + ", iteration: {type: s-iteration, numbers: {type: complex}, "
                                       "alpha: [1, 0], beta: [0, 0]}"));
        EXPECT_TRUE(a.img.pixels == b.img.pixels) << precision;
        EXPECT_GT(a.stats.drawn, 0u);
    }
}

// The eight symmetries of the square as maps of pixel (i, j) of an n x n image; a p4m map with
// the traps of Fig. 3b is invariant under all of them (paper 04, Sec. 4: the traps share the
// map's rotations and mirrors).
std::vector<std::function<std::pair<int, int>(int, int, int)>> square_symmetries() {
    return {
        [](int i, int j, int n) {
            return std::pair{n - 1 - i, j};
        }, // x -> -x
        [](int i, int j, int n) {
            return std::pair{i, n - 1 - j};
        }, // y -> -y
        [](int i, int j, int) {
            return std::pair{j, i};
        }, // (x, y) -> (-y, -x)
        [](int i, int j, int n) {
            return std::pair{n - 1 - j, n - 1 - i};
        }, // (x, y) -> (y, x)
        [](int i, int j, int n) {
            return std::pair{j, n - 1 - i};
        }, // rotation by 90 degrees
        [](int i, int j, int n) {
            return std::pair{n - 1 - i, n - 1 - j};
        }, // by 180 degrees
        [](int i, int j, int n) {
            return std::pair{n - 1 - j, i};
        }, // by 270 degrees
    };
}

void expect_square_symmetric(const fp::Image& img, const std::string& what) {
    const int n = img.width;
    const auto syms = square_symmetries();
    for (std::size_t s = 0; s < syms.size(); ++s) {
        std::size_t differ = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const auto [a, b] = syms[s](i, j, n);
                differ += px(img, i, j) != px(img, a, b);
            }
        EXPECT_EQ(differ, 0u) << what << ": symmetry " << s << " moves " << differ << " pixels";
    }
}

TEST(OrbitTrap, P4mPatternIsSymmetricPixelForPixel) {
    REQUIRE_WALLPAPER();
    // Picard and Fig. 8(d)'s S-iteration (alpha = 2, beta = -1.1; scalar parameters are
    // symmetric: real multiples commute with every rotation and mirror), one sample and eight,
    // even and odd sizes (an odd size puts pixels on the axes).
    const std::string s8d = "iteration: {type: s-iteration, alpha: 2, beta: -1.1}";
    for (int size : {64, 65}) {
        expect_square_symmetric(render(orbit_trap("samples: 1", size)).img, "picard " + std::to_string(size));
        expect_square_symmetric(render(orbit_trap("samples: 1, " + s8d, size)).img,
                                "fig-8d " + std::to_string(size));
    }
    expect_square_symmetric(render(orbit_trap("samples: 8, " + s8d, 48)).img, "fig-8d, 8 samples");
    expect_square_symmetric(render(orbit_trap("samples: 4, precision: double", 48)).img, "picard, double");
}

TEST(OrbitTrap, PicardPatternRepeatsWithTheLatticePeriod) {
    REQUIRE_WALLPAPER();
    // [-2 pi, 2 pi]^2 with W = H = 2m + 1: pixel i is at 2 pi (i - m) / m, so pixels i and i + m
    // are exactly 2 pi apart (in exact arithmetic). The start points themselves are rounded to
    // float, so p + 2 pi is not exactly the float above p, f(p + 2 pi) is not bitwise f(p), and
    // orbits that pass near a trap's rim or are chaotic can part: most pixels agree exactly, a few
    // along the pattern's fine structure differ (measured: 99.5% of the pairs equal; at least
    // 99% required).
    const int m = 64, n = 2 * m + 1;
    const auto r = render(orbit_trap("samples: 1", n));
    std::size_t same = 0, total = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i + m < n; ++i) {
            same += px(r.img, i, j) == px(r.img, i + m, j);
            same += px(r.img, j, i) == px(r.img, j, i + m);
            total += 2;
        }
    const double frac = double(same) / double(total);
    EXPECT_GT(frac, 0.99) << same << " of " << total << " pixel pairs equal";
    // The S-iteration mixes the unreduced point into u (eq. (13)), so it need not repeat; no check.
}

TEST(OrbitTrap, SameImageOnOneAndTwoThreads) {
    REQUIRE_WALLPAPER();
    const std::string y = orbit_trap("samples: 8, iteration: {type: s-iteration, numbers: {type: complex}, "
                                     "alpha: [1.1, 0.5], beta: [0.5, 0]}",
                                     40);
    EXPECT_TRUE(render(y, 1).img.pixels == render(y, 2).img.pixels);
}

TEST(OrbitTrap, RefusesWhatItCannotDo) {
    auto error_of = [](const std::string& yaml) { return fp::test::error_of(fp::Kind::Renderer, yaml); };
    const std::string base = "{type: orbit-trap, mapping: {type: affine, coefficients: [1, 0, 0, 1, 0, 0]}, "
                             "traps: {type: circles, preset: fig-1a}";
    EXPECT_EQ(error_of(base + ", colourer: {type: density}}"),
              "renderer.colourer: this colourer cannot colour orbit-trap hits (use colour-map)");
    EXPECT_EQ(
        error_of(base + ", samples: 3}"),
        "renderer.samples: expected 1, 8 or a square number (4, 9, 16, ...) of samples: patterns closed "
        "under the square's symmetries, got 3");
    EXPECT_EQ(error_of(base + ", area: [1, -1, -1, 1]}"),
              "renderer.area: the area must be [xmin, xmax, ymin, ymax] with xmin < xmax");
}

// The float reduction (exact through double) against the C library, bit for bit.
TEST(OrbitTrap, FloatReductionIsExact) {
    using fp_orbit_trap::Reduction;
    std::vector<float> v;
    const float a = fp_orbit_trap::period<float>;
    for (int k = -2000; k <= 2000; ++k) {
        const float x = float(k) * 0.01731f * float(1 + std::abs(k) % 7);
        v.push_back(x);
        v.push_back(std::nextafter(float(k) * a, 0.0f)); // just below a multiple of the period
        v.push_back(float(k) * a);
        v.push_back(std::nextafter(float(k) * a, 1e30f));
    }
    for (float x : {0.0f, -0.0f, 1e-30f, -1e-30f, a / 2, -a / 2, 3e7f, -3e7f, 1e12f, -1e12f}) v.push_back(x);
    for (Reduction r : {Reduction::fmod, Reduction::centred, Reduction::floor}) {
        std::vector<float> got = v;
        fp_orbit_trap::reduce(got.data(), got.size(), r);
        for (std::size_t i = 0; i < v.size(); ++i) {
            const float x = v[i];
            float want;
            if (r == Reduction::fmod) {
                want = std::fmod(x, a);
            } else if (r == Reduction::centred) {
                want = std::remainder(x, a);
                if (want >= a / 2) want -= a;
            } else {
                want = std::fmod(x, a);
                if (want < 0) want += a;
                if (want >= a) want = 0;
            }
            EXPECT_EQ(std::memcmp(&got[i], &want, sizeof(float)), 0)
                << "reduction " << int(r) << " of " << x << ": got " << got[i] << ", want " << want;
        }
        // Range.
        for (float g : got) {
            const bool in = r == Reduction::fmod      ? g > -a && g < a
                            : r == Reduction::centred ? g >= -a / 2 && g < a / 2
                                                      : g >= 0 && g < a;
            EXPECT_TRUE(in) << "reduction " << int(r) << ": " << g;
        }
    }
    // Not finite stays not finite.
    float bad[2] = {std::numeric_limits<float>::infinity(), std::nanf("")};
    fp_orbit_trap::reduce(bad, 2, Reduction::fmod);
    EXPECT_TRUE(std::isnan(bad[0]) && std::isnan(bad[1]));
}

// Algorithm 3 for one sample per pixel, written out through the plugins' interfaces point by
// point (scheme step, reduction, Trap::test, colour_hits, the renderer's pixel points and its
// 24-bit quantisation of the mean): the renderer's fused pass (circles of the Euclidean metric
// tested inline, TrapKernel) and its general pass must give exactly these bytes.
template <class T>
std::vector<float> algorithm3(const std::string& mapping, const std::string& iteration,
                              const std::string& traps, const std::string& reduction, int n, double h,
                              int max_iterations, int samples) {
    using fp_orbit_trap::Reduction;
    const auto map = host().make<fp::Transform>(mapping);
    const auto scheme = host().make<fp::IterationScheme>(iteration);
    const auto trap = host().make<fp::Trap>(traps);
    const auto colourer = host().make<fp::Colourer>("{type: colour-map, preset: fig-4a}");
    const Reduction red = reduction == "fmod"        ? Reduction::fmod
                          : reduction == "hexagonal" ? Reduction::hexagonal
                                                     : Reduction::centred;
    // The renderer's sample offsets (in pixels): 1 sample, or the eight rooks.
    std::vector<std::pair<double, double>> off = {{0, 0}};
    if (samples == 8)
        off = {{-0.375, -0.125}, {-0.125, 0.375},  {0.125, -0.375}, {0.375, 0.125},
               {-0.375, 0.125},  {-0.125, -0.375}, {0.125, 0.375},  {0.375, -0.125}};
    const std::size_t np = std::size_t(n) * std::size_t(n), ns = off.size();
    std::vector<std::int32_t> caught(np * ns, -1);
    std::vector<float> ratio(np * ns, 0.0f);
    std::vector<std::uint32_t> its(np * ns, std::uint32_t(max_iterations));
    const double inv = 1.0 / double(n - 1), n1 = double(n - 1);
    for (std::size_t pix = 0; pix < np; ++pix)
        for (std::size_t q = 0; q < ns; ++q) {
            const double i = double(pix % std::size_t(n)), j = double(pix / std::size_t(n));
            T x = T(0 + h * (((2 * i - n1) + 2 * off[q].first) * inv));
            T y = T(0 - h * (((2 * j - n1) + 2 * off[q].second) * inv));
            const std::size_t k = pix * ns + q;
            for (int step = 0; step < max_iterations; ++step) {
                scheme->step(*map, fp::Points<T>{&x, &y, 1}, nullptr, std::uint64_t(step));
                fp_orbit_trap::reduce_xy(&x, &y, 1, red);
                std::int32_t t = -1;
                T r = 0;
                trap->test(fp::Points<const T>{&x, &y, 1}, &t, &r);
                if (t >= 0) {
                    caught[k] = t, ratio[k] = float(r), its[k] = std::uint32_t(step + 1);
                    break;
                }
            }
        }
    std::vector<float> rgb(3 * np * ns), image(3 * np);
    colourer->colour_hits(caught.data(), ratio.data(), its.data(), np * ns, nullptr, rgb.data());
    for (std::size_t pix = 0; pix < np; ++pix)
        for (std::size_t ch = 0; ch < 3; ++ch) {
            std::uint64_t sum = 0;
            for (std::size_t q = 0; q < ns; ++q) {
                const float v = rgb[3 * (pix * ns + q) + ch];
                const float v01 = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
                sum += std::uint64_t(double(v01) * 16777216.0 + 0.5);
            }
            image[3 * pix + ch] = float(double(sum) * (1.0 / (16777216.0 * double(ns))));
        }
    return image;
}

TEST(OrbitTrap, FusedAndGeneralPassesAreAlgorithm3) {
    REQUIRE_WALLPAPER();
    const int n = 40, m = 100;
    const std::string s8d = "{type: s-iteration, alpha: 2, beta: -1.1}", picard = "{type: picard}";
    struct Case {
        std::string iteration, traps, reduction, precision;
        int samples = 1;
        std::string mapping = p4m;
        double h = 6.283185307179586; // the area [-h, h]^2
    };
    // p <- 2 p (no reduction of its own): the first steps stay in range, so the renderer checks
    // the range inline, until blocks leave it and are reduced there (then the whole batch again).
    const std::string doubling = "{type: affine, coefficients: [2, 0, 0, 2, 0, 0]}";
    const std::string hex5 = "{type: wallpaper, group: p3m1, reduction: hexagonal, G: [[0.343244, 0.711418], "
                             "[-0.671499, -0.289951], [-0.959405, -0.868905]], H: [[-0.224996, 0.0844803], "
                             "[-0.0571376, 0.0250126], [0.0250892, 0.553883]]}";
    const std::string s11 = "{type: s-iteration, alpha: 1.1, beta: 0.5}";
    // 17 circles: more than one vector's worth of radii (the renderer's scalar record path).
    std::string many = "{type: circles, radii: [0.9], centres: [";
    for (int i = 0; i < 17; ++i)
        many += (i ? ", [" : "[") + std::to_string(-4.0 + 0.5 * i) + ", " +
                std::to_string(0.37 * (i % 5) - 1) + "]";
    many += "]}";
    const std::vector<Case> cases = {
        {picard, many, "fmod", "float"},
        {picard, "{type: circles, centres: [[5, 5], [-2, 4]], radii: [0.4, 0.3]}", "fmod", "float", 1,
         doubling},
        {picard, "{type: circles, centres: [[2, -2.5]], radii: [0.3]}", "centred", "float", 1, doubling,
         0.03},
        {s8d, "{type: circles, preset: fig-3b}", "fmod", "float", 8}, // Fig. 8(d) with 8 samples
        {picard, "{type: circles, preset: fig-3c}", "fmod", "double", 8},
        {picard, "{type: circles, preset: fig-3b}", "fmod", "float"}, // fused, the benchmark's traps
        {picard, "{type: circles, preset: fig-1d}", "centred",
         "float"},                                                  // fused, 7 circles, overlapping order
        {s8d, "{type: circles, preset: fig-3b}", "fmod", "float"},  // fused, Fig. 8(d)
        {s8d, "{type: circles, preset: fig-3c}", "fmod", "double"}, // fused, double lanes
        {picard, "{type: circles, centres: [[1, 1], [-2, 0.5], [0, -3]], radii: [2.5, 1, 3]}", "fmod",
         "float"},
        {picard, "{type: circles, preset: fig-3b, metric: {type: chebyshev}}", "fmod",
         "float"}, // general pass
        {picard, "{type: circles, preset: fig-3b, metric: {type: lp, p: 1.5}}", "fmod", "double"},
        // The hexagonal reduction (x and y together; the range a hexagon): Fig. 5's p3m1 map reducing
        // itself (Picard: nothing left to reduce), the S-iteration (the renderer reduces), fused and
        // general passes, float and double, and the doubling map's blocks leaving the hexagon.
        {picard, "{type: circles, preset: fig-1b}", "hexagonal", "float", 1, hex5},
        {s11, "{type: circles, preset: fig-1d}", "hexagonal", "float", 8, hex5},
        {s11, "{type: circles, preset: fig-1b, metric: {type: chebyshev}}", "hexagonal", "float", 1, hex5},
        {s11, "{type: circles, preset: fig-1b}", "hexagonal", "double", 1, hex5},
        {picard, "{type: circles, centres: [[2, -1.5], [-1, 2.5]], radii: [0.3, 0.4]}", "hexagonal", "float",
         1, doubling, 0.03},
    };
    for (const Case& c : cases) {
        char area[128];
        std::snprintf(area, sizeof area, "[%.17g, %.17g, %.17g, %.17g]", -c.h, c.h, -c.h, c.h);
        const std::string y = "{type: orbit-trap, area: " + std::string(area) +
                              ", width: " + std::to_string(n) + ", height: " + std::to_string(n) +
                              ", samples: " + std::to_string(c.samples) +
                              ", max_iterations: " + std::to_string(m) + ", mapping: " + c.mapping +
                              ", iteration: " + c.iteration + ", traps: " + c.traps +
                              ", reduction: " + c.reduction + ", precision: " + c.precision + "}";
        const auto got = render(y);
        const auto want =
            c.precision == "float"
                ? algorithm3<float>(c.mapping, c.iteration, c.traps, c.reduction, n, c.h, m, c.samples)
                : algorithm3<double>(c.mapping, c.iteration, c.traps, c.reduction, n, c.h, m, c.samples);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < want.size(); ++i) differ += got.img.pixels[i] != want[i];
        EXPECT_EQ(differ, 0u) << y;
        EXPECT_GT(got.stats.drawn, 0u) << y;
    }
}

// The circles trap's TrapKernel (what the renderer tests inline) against its own test().
TEST(OrbitTrap, CirclesKernelIsTheirTest) {
    const auto t = host().make<fp::Trap>("{type: circles, preset: fig-1d}");
    const fp::TrapKernel k = t->kernel();
    ASSERT_EQ(k.kind, fp::TrapKernel::Kind::euclidean_circles);
    ASSERT_EQ(k.n, 7u);
    EXPECT_EQ(
        host().make<fp::Trap>("{type: circles, preset: fig-1d, metric: {type: lp, p: 1}}")->kernel().kind,
        fp::TrapKernel::Kind::none);
    std::vector<float> x, y;
    for (int j = -60; j <= 60; ++j)
        for (int i = -60; i <= 60; ++i) x.push_back(float(i) * 0.1731f), y.push_back(float(j) * 0.1699f);
    // Points on the rims too (distance 3.5 = r from the centre (0, 7), and next to it).
    for (float d : {3.5f, std::nextafter(3.5f, 0.0f), std::nextafter(3.5f, 9.0f)})
        x.push_back(0), y.push_back(7 - d);
    std::vector<std::int32_t> trap(x.size());
    std::vector<float> ratio(x.size());
    t->test(fp::Points<const float>{x.data(), y.data(), x.size()}, trap.data(), ratio.data());
    for (std::size_t p = 0; p < x.size(); ++p) {
        std::int32_t want = -1;
        float wr = 0;
        for (std::size_t i = 0; i < k.n && want < 0; ++i) {
            const float dx = x[p] - float(k.cx[i]), dy = y[p] - float(k.cy[i]), kk = dx * dx + dy * dy;
            if (kk < k.key_f[i])
                want = std::int32_t(i),
                wr = std::min(std::sqrt(kk) / float(k.r[i]), std::nextafter(1.0f, 0.0f));
        }
        ASSERT_EQ(trap[p], want) << x[p] << ", " << y[p];
        if (want >= 0) {
            ASSERT_EQ(ratio[p], wr) << x[p] << ", " << y[p];
        }
    }
}

// colour-map's index of a trap ratio without pow (a table of thresholds) against Algorithm 1's
// table and the index rule of Algorithm 3 computed here with pow, at and next to every threshold
// and on a sweep: exactly the same colours.
TEST(OrbitTrap, ColourMapIndexIsPowsIndex) {
    const std::vector<double> colours = {0, 0,   0,   255, 0,   0,   255, 128, 0, 0, 0,
                                         0, 255, 128, 0,   255, 255, 255, 26,  0, 0};
    const std::vector<double> ratios = {0.0, 0.7, 0.75, 0.8, 0.85, 0.9, 1.0}; // Table 1, Fig. 4a
    std::string cs, qs;
    for (double c : colours) cs += (cs.empty() ? "" : ", ") + std::to_string(int(c));
    for (double q : ratios) qs += (qs.empty() ? "" : ", ") + std::to_string(q);
    for (const auto& [e, nc] :
         std::vector<std::pair<double, std::size_t>>{{16, 300}, {2.5, 50}, {16, 3000}, {0.3, 40}}) {
        const auto cm =
            host().make<fp::Colourer>("{type: colour-map, colours: [" + cs + "], ratios: [" + qs +
                                      "], E: " + std::to_string(e) + ", Nc: " + std::to_string(nc) + "}");
        // Algorithm 1 (colour-map.cpp's build) and the index rule (its index), with pow.
        std::vector<fp::Rgb> table(nc);
        for (std::size_t i = 0, k = 1; i < nc; ++i) {
            const double q = std::pow(double(i) / double(1 + i), e);
            while (k < ratios.size() - 1 && q > ratios[k]) ++k;
            const double t = std::clamp((ratios[k] - q) / (ratios[k] - ratios[k - 1]), 0.0, 1.0);
            auto mix = [&](int ch) {
                return float(t * (colours[3 * (k - 1) + std::size_t(ch)] / 255.0) +
                             (1 - t) * (colours[3 * k + std::size_t(ch)] / 255.0));
            };
            table[i] = {mix(0), mix(1), mix(2)};
        }
        // e and nc named explicitly: clang 14 does not capture structured bindings.
        auto index = [&, e = e, nc = nc](float ratio) {
            const double v = std::pow(double(ratio), 1.0 / e);
            if (!(v < 1)) return nc - 1;
            const double f = v / (1 - v);
            return f >= double(nc - 1) ? nc - 1 : std::size_t(f);
        };
        std::vector<float> r;
        for (std::size_t k = 1; k < nc; ++k) {
            // Around the exact threshold (k / (k + 1))^E: 3 floats either side of where the rule
            // changes (found by stepping with the rule itself).
            float t = float(std::pow(double(k) / double(k + 1), e));
            while (t > 0 && index(t) >= k) t = std::nextafter(t, -1.0f);
            while (t < 1 && index(t) < k) t = std::nextafter(t, 2.0f);
            for (int d = 0; d < 3; ++d) t = std::nextafter(t, -1.0f);
            for (int d = 0; d < 7; ++d, t = std::nextafter(t, 2.0f)) r.push_back(t);
        }
        for (int i = 0; i <= 100000; ++i) r.push_back(float(i) / 100000.0f);
        for (float x : {0.0f, 1e-30f, std::nextafter(1.0f, 0.0f), 1.0f, 1.5f}) r.push_back(x);
        std::vector<std::int32_t> trap(r.size(), 0);
        std::vector<std::uint32_t> it(r.size(), 1);
        std::vector<float> rgb(3 * r.size());
        cm->colour_hits(trap.data(), r.data(), it.data(), r.size(), nullptr, rgb.data());
        for (std::size_t i = 0; i < r.size(); ++i) {
            const fp::Rgb want = table[index(r[i])];
            ASSERT_TRUE(rgb[3 * i] == want.r && rgb[3 * i + 1] == want.g && rgb[3 * i + 2] == want.b)
                << "E " << e << ", Nc " << nc << ", ratio " << r[i] << " (index " << index(r[i]) << ")";
        }
    }
}

} // namespace
