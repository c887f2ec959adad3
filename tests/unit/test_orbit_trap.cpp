// The orbit-trap renderer (paper 04, Algorithm 3): pixels computed by hand, the S-iteration
// with alpha = 1, beta = 0 equal to Picard, a p4m pattern invariant pixel for pixel under the
// square's symmetries, the lattice period of Picard patterns, threads, and the exact reduction.
#include "host.hpp"

#include "../../plugins/renderers/orbit_trap_reduce.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/runtime.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace {

using fp::test::host;

struct Render {
    fp::Image img;
    fp::RenderStats stats;
};

Render render(const std::string& yaml, unsigned threads = 2) {
    auto r = host().make<fp::Renderer>(yaml);
    fp::host::Runtime rt(threads, nullptr);
    Render out;
    out.img = r->render(rt, out.stats);
    return out;
}

bool has_plugin(const std::string& yaml) {
    try {
        host().make_object(fp::Kind::Transform, yaml, "<string>");
        return true;
    } catch (const fp::InputError&) {
        return false;
    }
}

// Paper 04's p4m example (Fig. 8), with the misprint P32 = [0.422963, 0] fixed to 0.429163 (the
// p4m condition P32.x = P23.y).
const std::string p4m =
    "{type: wallpaper, group: p4m, P03: [0, -0.234602], P04: [0, -0.231376], P13: [0, -0.931333], "
    "P14: [0, -0.982975], P23: [0, 0.429163], P24: [0, 0.363704], P30: [-0.234602, 0], P31: [-0.931333, 0], "
    "P32: [0.429163, 0], P40: [-0.231376, 0], P41: [-0.982975, 0], P42: [0.363704, 0]}";

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
    auto error_of = [](const std::string& yaml) -> std::string {
        try {
            host().make_object(fp::Kind::Renderer, yaml, "<string>");
        } catch (const fp::InputError& e) {
            const std::string m = e.what();
            const auto at = m.find(": ");
            return m.rfind("<string>:", 0) == 0 && at != std::string::npos ? m.substr(at + 2) : m;
        }
        return "(no error)";
    };
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

} // namespace
