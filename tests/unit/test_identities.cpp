// Identities the papers state and the code relies on, not tested elsewhere (issue 16, item 7):
//   - paper 02 Sec. 4: q-system addition and multiplication (eqs. (12), (14)) are associative
//     and multiplication distributes over addition ("following elementary calculations");
//   - paper 03: the Gumowski-Mira map with alpha = 0 preserves area (Jacobian determinant 1);
//   - paper 04 after eq. (13): the S-iteration with vector parameters alpha = [x_a, 0],
//     beta = [x_b, 0] reduces to the S-iteration with scalar parameters x_a, x_b.
// Plugins are built through the host, as a config builds them.
#include "host.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::Mat2;
using fp::NumberSystem;
using fp::Transform;
using fp::Vec2;

constexpr double eps = std::numeric_limits<double>::epsilon();

// ================================================================== q-system numbers (paper 02)

std::shared_ptr<const NumberSystem> qsystem(double A, double B) {
    const std::string yaml = "{type: q-system, A: " + std::to_string(A) + ", B: " + std::to_string(B) + "}";
    auto ns = host().make<NumberSystem>(yaml);
    EXPECT_TRUE(ns) << yaml;
    return ns;
}

Vec2 mul(const NumberSystem& ns, Vec2 u, Vec2 v) {
    Vec2 out;
    ns.multiply({&u.x, &u.y, 1}, {&v.x, &v.y, 1}, {&out.x, &out.y, 1});
    return out;
}

// Addition and subtraction are componentwise (eqs. (12)-(13)); the NumberSystem interface has no
// add() because the schemes add points componentwise (Chunk::lin), so this is the addition the
// code uses.
Vec2 add(Vec2 u, Vec2 v) { return {u.x + v.x, u.y + v.y}; }

Mat2 matmul(const Mat2& p, const Mat2& q) {
    return {p.a * q.a + p.b * q.c, p.a * q.b + p.b * q.d, p.c * q.a + p.d * q.c, p.c * q.b + p.d * q.d};
}

bool same_bits(double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

bool same_bits(Vec2 a, Vec2 b) { return same_bits(a.x, b.x) && same_bits(a.y, b.y); }

bool same(const Mat2& p, const Mat2& q) { return p.a == q.a && p.b == q.b && p.c == q.c && p.d == q.d; }

// Exact arithmetic: operands are multiples of 1/4 in [-2, 2] and A, B multiples of 1/4 with
// |A|, |B| <= 3. Then A b, 2B b and a c are multiples of 1/16 below 2^4, a product uv has
// components that are multiples of 1/64 below 2^6, a triple product multiples of 2^-12 below
// 2^12 (matrix products of multipliers likewise): at most 24 significant bits, far below
// double's 53, so no operation rounds and both sides of each identity are the same number.
// The identities must then hold exactly: any mistake in eq. (14) that still looks like a
// bilinear product but is not associative, or a multiplier() that disagrees with multiply(),
// shows up as a plain mismatch, with no tolerance to hide in. Exactly means equal values (==),
// not equal bits: an exact zero takes its sign from the order of the terms ((-1) * 0 = -0, and
// -0 + 0 = +0), which differs between the two sides of an identity without being a different
// number.
TEST(QSystemIdentities, AssociativeAndDistributiveExactlyOnDyadicValues) {
    const std::vector<std::pair<double, double>> systems = {{-1, 0}, {1, 0},  {0, 0},       {2, 1},
                                                            {-3, 0}, {3, -1}, {-1.5, 0.25}, {0.75, -2.5}};
    std::mt19937_64 rng(16);
    std::uniform_int_distribution<int> quarter(-8, 8); // k / 4 in [-2, 2]
    auto draw = [&] { return Vec2{quarter(rng) / 4.0, quarter(rng) / 4.0}; };
    for (auto [A, B] : systems) {
        auto ns = qsystem(A, B);
        std::size_t bad_assoc = 0, bad_dist = 0, bad_add = 0, bad_hom = 0;
        for (int i = 0; i < 2000; ++i) {
            const Vec2 u = draw(), v = draw(), w = draw();
            bad_assoc += !(mul(*ns, mul(*ns, u, v), w) == mul(*ns, u, mul(*ns, v, w)));
            bad_dist += !(mul(*ns, u, add(v, w)) == add(mul(*ns, u, v), mul(*ns, u, w)));
            bad_dist += !(mul(*ns, add(u, v), w) == add(mul(*ns, u, w), mul(*ns, v, w)));
            bad_add += !(add(add(u, v), w) == add(u, add(v, w)));
            // u -> M(u) is a homomorphism: M(u + v) = M(u) + M(v) (the schemes' I - M(c) is
            // M(1 - c)) and M(u v) = M(u) M(v) (multiplying by u v is multiplying by v, then u).
            bad_hom += !same(ns->multiplier(add(u, v)), ns->multiplier(u) + ns->multiplier(v));
            bad_hom += !same(ns->multiplier(mul(*ns, u, v)), matmul(ns->multiplier(u), ns->multiplier(v)));
        }
        EXPECT_EQ(bad_assoc, 0u) << "(uv)w != u(vw) in Q_{" << A << "," << B << "}";
        EXPECT_EQ(bad_dist, 0u) << "distributivity fails in Q_{" << A << "," << B << "}";
        EXPECT_EQ(bad_add, 0u) << "(u+v)+w != u+(v+w) in Q_{" << A << "," << B << "}";
        EXPECT_EQ(bad_hom, 0u) << "multiplier() is not a homomorphism in Q_{" << A << "," << B << "}";
    }
}

// General real operands (uniform in [-3, 3]) and non-dyadic A, B (the paper's Q_{-1.5,0.2} of
// Figs. 7 and 12), where the products round. Tolerance, from the rounding of eq. (14) as
// qsystem.hpp evaluates it: with N(a + qb) = |a| + |b| and K = max(1, |A| + 2|B|), every term
// of a product is bounded by its share of K N(u) N(v), so N(uv) <= K N(u) N(v), and each of the
// two components is a sum of two rounded products of rounded coefficients (A b, a + 2B b): at
// most 4 roundings of relative size eps/2, so |fl(uv) - uv| <= 4 eps K N(u) N(v) (sum over both
// components, generously). For (uv)w that error is multiplied by at most K N(w), and the second
// product adds its own 4 eps K N(uv) N(w) <= 4 eps K^2 N(u) N(v) N(w): 8 eps K^2 N(u) N(v) N(w)
// per side, 16 for the difference of the two groupings. For u(v + w) against uv + uw the sums
// add eps/2 each: within 9 eps K N(u) (N(v) + N(w)); the test allows 16. A wrong formula is off
// by O(1), not by ulps.
TEST(QSystemIdentities, AssociativeAndDistributiveWithinRoundingOnRandomValues) {
    const std::vector<std::pair<double, double>> systems = {{-1, 0}, {1, 0},  {0, 0}, {-1.5, 0.2}, {-3, 0},
                                                            {3, 0},  {-4, 2}, {2, 1}, {0.3, -0.7}};
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> d(-3, 3);
    auto draw = [&] { return Vec2{d(rng), d(rng)}; };
    auto N = [](Vec2 u) { return std::fabs(u.x) + std::fabs(u.y); };
    for (auto [A, B] : systems) {
        auto ns = qsystem(A, B);
        const double K = std::max(1.0, std::fabs(A) + 2 * std::fabs(B));
        std::size_t bad = 0;
        double worst = 0; // the largest error found, in units of its bound
        for (int i = 0; i < 5000; ++i) {
            const Vec2 u = draw(), v = draw(), w = draw();
            const Vec2 l = mul(*ns, mul(*ns, u, v), w), r = mul(*ns, u, mul(*ns, v, w));
            const double tol_assoc = 16 * eps * K * K * N(u) * N(v) * N(w);
            const double e_assoc = std::max(std::fabs(l.x - r.x), std::fabs(l.y - r.y));
            const Vec2 dl = mul(*ns, u, add(v, w)), dr = add(mul(*ns, u, v), mul(*ns, u, w));
            const double tol_dist = 16 * eps * K * N(u) * (N(v) + N(w));
            const double e_dist = std::max(std::fabs(dl.x - dr.x), std::fabs(dl.y - dr.y));
            bad += e_assoc > tol_assoc;
            bad += e_dist > tol_dist;
            worst = std::max({worst, e_assoc / tol_assoc, e_dist / tol_dist});
        }
        EXPECT_EQ(bad, 0u) << "Q_{" << A << "," << B << "}: worst error " << worst << " of its bound";
    }
}

// Products worked out by hand from q^2 = A + 2B q (eq. (11)), grouped both ways.
TEST(QSystemIdentities, HandComputedProducts) {
    // Q_{2,1}: q^2 = 2 + 2q. (1 + q)(1 - q) = 1 - q^2 = -1 - 2q; times (2 + q):
    //   -2 - q - 4q - 2q^2 = -2 - 5q - 2(2 + 2q) = -6 - 9q.
    // Other grouping: (1 - q)(2 + q) = 2 - q - q^2 = -3q; (1 + q)(-3q) = -3q - 3q^2 = -6 - 9q.
    auto q21 = qsystem(2, 1);
    EXPECT_TRUE(same_bits(mul(*q21, {1, 1}, {1, -1}), Vec2{-1, -2}));
    EXPECT_TRUE(same_bits(mul(*q21, {1, -1}, {2, 1}), Vec2{0, -3}));
    EXPECT_TRUE(same_bits(mul(*q21, mul(*q21, {1, 1}, {1, -1}), {2, 1}), Vec2{-6, -9}));
    EXPECT_TRUE(same_bits(mul(*q21, {1, 1}, mul(*q21, {1, -1}, {2, 1})), Vec2{-6, -9}));
    // Distributivity: (1 + q)((1 - q) + (2 + q)) = (1 + q) 3 = 3 + 3q, and
    //   (1 + q)(1 - q) + (1 + q)(2 + q) = (-1 - 2q) + (2 + 3q + q^2) = (-1 - 2q) + (4 + 5q) = 3 + 3q.
    EXPECT_TRUE(same_bits(mul(*q21, {1, 1}, {2, 1}), Vec2{4, 5}));
    EXPECT_TRUE(same_bits(mul(*q21, {1, 1}, {3, 0}), Vec2{3, 3}));
    // Q_{-1.5,0.2} (paper 02 Fig. 7(c)): q^2 = -1.5 + 0.4q. The parameters alpha = 0.5 + 0.5q and
    // a = 0.9 + 0.5q: 0.45 + 0.25q + 0.45q + 0.25q^2 = 0.45 + 0.7q + 0.25(-1.5 + 0.4q)
    //   = 0.075 + 0.8q. 0.9, 0.2 and the result are not binary fractions: within an ulp or two.
    auto q = qsystem(-1.5, 0.2);
    const Vec2 p = mul(*q, {0.5, 0.5}, {0.9, 0.5});
    EXPECT_NEAR(p.x, 0.075, 4 * eps);
    EXPECT_NEAR(p.y, 0.8, 4 * eps);
    // q itself squared is A + 2B q, by definition.
    EXPECT_TRUE(same_bits(mul(*q, {0, 1}, {0, 1}), Vec2{-1.5, 2 * 0.2}));
}

// ================================================================== Gumowski-Mira (paper 03)

std::shared_ptr<const Transform> gm(double alpha, double mu) {
    const std::string yaml =
        "{type: gumowski-mira, alpha: " + std::to_string(alpha) + ", mu: " + std::to_string(mu) + "}";
    return make<Transform>(yaml);
}

// det of the Jacobian of one step of the plugin's own map at p, by central differences.
double jacobian_det(const Transform& t, Vec2 p, double h) {
    const Vec2 xp = apply(t, {p.x + h, p.y}), xm = apply(t, {p.x - h, p.y});
    const Vec2 yp = apply(t, {p.x, p.y + h}), ym = apply(t, {p.x, p.y - h});
    const double j11 = (xp.x - xm.x) / (2 * h), j21 = (xp.y - xm.y) / (2 * h);
    const double j12 = (yp.x - ym.x) / (2 * h), j22 = (yp.y - ym.y) / (2 * h);
    return j11 * j22 - j12 * j21;
}

// The Jacobian by hand (paper 03 eq. (1), sigma = 0.05): with g(y) = y + alpha (1 - sigma y^2) y,
// x' = g(y) + f(x), y' = -x + f(x'):
//   dx'/dx = f'(x),              dx'/dy = g'(y) = 1 + alpha (1 - 3 sigma y^2),
//   dy'/dx = -1 + f'(x') f'(x),  dy'/dy = f'(x') g'(y),
//   det = f'(x) f'(x') g'(y) - g'(y) (-1 + f'(x') f'(x)) = g'(y) = 1 + alpha (1 - 0.15 y^2).
// So alpha = 0 gives det = 1 everywhere (the map preserves area, as the paper says of the
// conservative case), and alpha != 0 gives det != 1 except on the lines y^2 = 1 / 0.15.
//
// Tolerance: the grid is [-12, 12]^2 (the attractors of the configs stay within it) and h = 1e-5.
// Truncation: each entry is off by h^2 / 6 times a third derivative of the map; with
// |mu| <= 0.76, |f'| <= 3, |f''| <= 7, |f'''| <= 17, and the worst third derivative of
// y' = -x + f(x') is about 17 * 27 + 3 * 7 * 3 * 7 + 3 * 17 < 1000: under 2e-8 per entry.
// Rounding: the steps' values are below 40 and are exact to a few ulps, divided by 2h: under
// 40 * 4 eps / 2e-5 ~ 2e-9. The entries are below 10 in size, so det = j11 j22 - j12 j21 is off
// by at most about 2 * 2 * 10 * 2.2e-8 < 1e-6. The tolerance is 1e-6; the alpha term of the
// configs (alpha = 0.008) moves det by up to 0.008 (1 - 0.15 * 144) = -0.165, and by 0.008 at
// y = 0.
constexpr double jac_h = 1e-5, jac_tol = 1e-6;

std::vector<Vec2> jacobian_grid() {
    std::vector<Vec2> pts;
    for (int i = 0; i <= 48; ++i)
        for (int j = 0; j <= 48; ++j) pts.push_back({-12 + 0.5 * i + 0.013, -12 + 0.5 * j - 0.007});
    return pts;
}

TEST(GumowskiMiraIdentities, AlphaZeroPreservesArea) {
    for (double mu : {-0.31, -0.15, -0.7509, -0.05, 0.2}) {
        auto t = gm(0, mu);
        double worst = 0;
        Vec2 at{};
        for (Vec2 p : jacobian_grid()) {
            const double e = std::fabs(jacobian_det(*t, p, jac_h) - 1);
            if (e > worst) worst = e, at = p;
        }
        EXPECT_LE(worst, jac_tol) << "mu = " << mu << ": det - 1 = " << worst << " at (" << at.x << ", "
                                  << at.y << ")";
    }
}

TEST(GumowskiMiraIdentities, AlphaNonZeroScalesAreaBy1PlusAlphaTimes1Minus015YSquared) {
    for (double alpha : {0.008, 0.1, -0.05}) {
        auto t = gm(alpha, -0.7509);
        double worst = 0, largest_change = 0;
        for (Vec2 p : jacobian_grid()) {
            const double det = jacobian_det(*t, p, jac_h);
            worst = std::max(worst, std::fabs(det - (1 + alpha * (1 - 0.15 * p.y * p.y))));
            largest_change = std::max(largest_change, std::fabs(det - 1));
        }
        EXPECT_LE(worst, jac_tol) << "alpha = " << alpha;
        // Not area-preserving: at the grid's |y| = 11.993, |det - 1| = |alpha| (0.15 * 143.8 - 1).
        EXPECT_GT(largest_change, 20 * std::fabs(alpha)) << "alpha = " << alpha;
        // At y = 0 exactly (not on the grid), det = 1 + alpha.
        EXPECT_NEAR(jacobian_det(*t, {0.37, 0}, jac_h), 1 + alpha, jac_tol) << "alpha = " << alpha;
    }
}

// ================================================================== vector S-iteration (paper 04)

const std::string& p4m = fp::test::p4m_fig8;

// `a` and `b` equal as numbers; NaN equals NaN (the same lanes blow up on both sides).
template <class T>
bool same_value(T a, T b) {
    return a == b || (std::isnan(a) && std::isnan(b));
}

// Equal, not within a tolerance: the vector parameter [x, 0] in the complex numbers (or any
// q-system) has the multiplier M(x + 0q) = [[x, A * 0], [0, x + 2B * 0]] = [[x, -0 or 0], [0, x]],
// and the real scalar x has [[x, 0], [0, x]]. The schemes' combinations (fixpoint/scheme-inl.hpp) compute
// (a x0 + b y0) + (e x1 + f y1) in that order with no FMA, so the zero entries add a signed zero
// to each product a x0, which leaves a nonzero product unchanged: both forms compute the same
// numbers, in float and in double. The one possible difference is the sign of an exact zero
// (-0 + 0 against -0 + -0); the comparison is ==, which does not see it, and it runs after every
// one of 30 steps, so such a zero could not grow unseen into a different value later.
template <class T>
void expect_vector_equals_scalar(const Transform& map, const std::string& vector_yaml,
                                 const std::string& scalar_yaml) {
    auto sv = host().make<fp::IterationScheme>(vector_yaml);
    auto ss = host().make<fp::IterationScheme>(scalar_yaml);
    ASSERT_TRUE(sv && ss);
    // 1024 starting points over [-2 pi, 2 pi]^2 (paper 04's area), 30 steps each.
    std::vector<T> vx, vy;
    fp::Rng rng = fp::chain_stream(4, 13);
    for (int i = 0; i < 1024; ++i) {
        vx.push_back(T(-6.283185307179586 + 12.566370614359172 * fp::uniform_double(rng)));
        vy.push_back(T(-6.283185307179586 + 12.566370614359172 * fp::uniform_double(rng)));
    }
    std::vector<T> sx = vx, sy = vy;
    for (std::uint64_t n = 0; n < 30; ++n) {
        sv->step(map, fp::Points<T>{vx.data(), vy.data(), vx.size()}, nullptr, n);
        ss->step(map, fp::Points<T>{sx.data(), sy.data(), sx.size()}, nullptr, n);
        std::size_t bad = 0;
        for (std::size_t i = 0; i < vx.size(); ++i)
            bad += !same_value(vx[i], sx[i]) || !same_value(vy[i], sy[i]);
        ASSERT_EQ(bad, 0u) << vector_yaml << " against " << scalar_yaml << " at step " << n << " ("
                           << (sizeof(T) == 8 ? "double" : "float") << ")";
    }
}

TEST(VectorSIteration, AlphaAndBetaOnTheRealAxisAreTheScalarSIteration) {
    if (!has_plugin(p4m)) GTEST_SKIP() << "the wallpaper transform is not built";
    const auto wallpaper = host().make<Transform>(p4m);
    const auto inversion = host().make<Transform>(
        "{type: inversion, shape: {type: star-polygon, points: 5, outer_radius: 3, inner_radius: 1.5}}");
    // Fig. 8(a) (alpha = beta = [1.1, 0]) and Fig. 8(d) (alpha = [2, 0], beta = [-1.1, 0]), in the
    // complex numbers as paper 04 computes, and in two other q-systems ([x, 0] is x + 0q in each).
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"alpha: [1.1, 0], beta: [1.1, 0]", "alpha: 1.1, beta: 1.1"},
        {"alpha: [2, 0], beta: [-1.1, 0]", "alpha: 2, beta: -1.1"},
        {"alpha: [0.7, 0], beta: [0.35, 0]", "alpha: 0.7, beta: 0.35"},
    };
    for (const char* numbers :
         {"{type: complex}", "{type: q-system, A: -1.5, B: 0.2}", "{type: q-system, A: 2, B: 1}"})
        for (const auto& [vec, sca] : cases)
            for (const Transform* map : {wallpaper.get(), inversion.get()}) {
                const std::string v =
                    std::string("{type: s-iteration, numbers: ") + numbers + ", " + vec + "}";
                const std::string s = "{type: s-iteration, " + sca + "}";
                expect_vector_equals_scalar<double>(*map, v, s);
                expect_vector_equals_scalar<float>(*map, v, s);
            }
}

fp::Image render(const std::string& yaml) {
    auto r = host().make<fp::Renderer>(yaml);
    fp::host::Runtime rt(2, nullptr);
    fp::RenderStats stats;
    return r->render(rt, stats);
}

// The whole orbit-trap pipeline (paper 04 Algorithm 3 with the reduction mod 2 pi after each
// step): Fig. 8(a)'s vector form and its scalar form give the same pixels. The counter-check:
// a non-zero y component (Fig. 9's [1.1, 0.5]) changes the image, so the comparison can tell.
TEST(VectorSIteration, OrbitTrapImageIsTheScalarOne) {
    if (!has_plugin(p4m)) GTEST_SKIP() << "the wallpaper transform is not built";
    auto yaml = [](const std::string& iteration, const char* precision) {
        return "{type: orbit-trap, width: 48, height: 48, samples: 4, precision: " + std::string(precision) +
               ", mapping: " + p4m + ", traps: {type: circles, preset: fig-3b}, iteration: " + iteration +
               "}";
    };
    for (const char* precision : {"float", "double"}) {
        const fp::Image vec = render(yaml(
            "{type: s-iteration, numbers: {type: complex}, alpha: [1.1, 0], beta: [1.1, 0]}", precision));
        const fp::Image sca = render(yaml("{type: s-iteration, alpha: 1.1, beta: 1.1}", precision));
        const fp::Image tilted = render(yaml(
            "{type: s-iteration, numbers: {type: complex}, alpha: [1.1, 0.5], beta: [1.1, 0]}", precision));
        ASSERT_EQ(vec.pixels.size(), std::size_t(48 * 48 * 3));
        EXPECT_TRUE(vec.pixels == sca.pixels) << precision;
        std::size_t differ = 0;
        for (std::size_t i = 0; i < vec.pixels.size(); ++i) differ += vec.pixels[i] != tilted.pixels[i];
        EXPECT_GT(differ, vec.pixels.size() / 10) << precision;
    }
}

} // namespace
