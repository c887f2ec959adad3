// Unit tests of the number systems of paper 02 Sec. 4: the q-system numbers Q_{A,B}
// (q^2 = A + 2B q, eq. (11)) with multiplication eq. (14) and division eq. (15), and `complex`,
// which is Q_{-1,0}. The plugins are built through the host, as a config builds them.
#include "host.hpp"

#include <fixpoint/host/core/host.hpp>

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <complex>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::NumberSystem;
using fp::Vec2;

std::string qsystem(double A, double B) {
    return "{type: q-system, A: " + std::to_string(A) + ", B: " + std::to_string(B) + "}";
}

Vec2 mul(const NumberSystem& ns, Vec2 u, Vec2 v) {
    Vec2 out;
    ns.multiply({&u.x, &u.y, 1}, {&v.x, &v.y, 1}, {&out.x, &out.y, 1});
    return out;
}

bool same_bits(double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

struct Operands {
    std::vector<double> ux, uy, vx, vy;
};

Operands random_operands(std::size_t n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> d(-3, 3);
    Operands o;
    for (std::size_t i = 0; i < n; ++i) {
        o.ux.push_back(d(rng));
        o.uy.push_back(d(rng));
        o.vx.push_back(d(rng));
        o.vy.push_back(d(rng));
    }
    return o;
}

// The (A, B) the tests run over: complex, split-complex (A = 1), dual (A = 0), the paper's
// q-systems of Figs. 7, 12 and 13, and A = 2, B = 1 of the hand-computed products.
const std::vector<std::pair<double, double>> systems = {{-1, 0}, {1, 0}, {0, 0},  {-1.5, 0.2},
                                                        {-3, 0}, {3, 0}, {-4, 2}, {2, 1}};

// ------------------------------------------------------------------ complex numbers

// q-system(-1, 0) and complex multiply exactly as std::complex<double>: eq. (14) with A = -1,
// B = 0 is (ac - bd) + q(bc + ad); the plugins compute a c + (A b) d and b c + (a + 2B b) d,
// where A b = -b and a + 0 b = a are exact, so each part is the same two products and one
// sum as std::complex's (ac - bd, ad + bc), rounded the same way (no FMA: -ffp-contract=off).
TEST(QSystemNumbers, MinusOneZeroIsComplexBitwise) {
    const std::size_t n = 1000;
    const Operands o = random_operands(n, 1);
    for (const std::string yaml : {"{type: complex}", "{type: q-system, A: -1, B: 0}", "{type: q-system}"}) {
        auto ns = make<NumberSystem>(yaml);
        std::vector<double> ox(n), oy(n);
        ns->multiply({o.ux.data(), o.uy.data(), n}, {o.vx.data(), o.vy.data(), n}, {ox.data(), oy.data(), n});
        std::size_t bad = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const std::complex<double> want =
                std::complex<double>(o.ux[i], o.uy[i]) * std::complex<double>(o.vx[i], o.vy[i]);
            bad += !same_bits(ox[i], want.real()) || !same_bits(oy[i], want.imag());
        }
        EXPECT_EQ(bad, 0u) << yaml;
        EXPECT_FALSE(ns->is_real()) << yaml;
    }
}

// Division, eq. (15) with A = -1, B = 0: (ac + bd)/(c^2 + d^2) + q (bc - ad)/(c^2 + d^2), the
// complex quotient. std::complex divides with scaling (Smith's method or __divdc3), a
// different sequence of roundings, so this agrees within a few ulps, not bitwise.
TEST(QSystemNumbers, ComplexDivisionIsComplexQuotient) {
    const Operands o = random_operands(1000, 2);
    auto ns = make<NumberSystem>("{type: complex}");
    for (std::size_t i = 0; i < o.ux.size(); ++i) {
        Vec2 q;
        ASSERT_TRUE(ns->divide({o.ux[i], o.uy[i]}, {o.vx[i], o.vy[i]}, q));
        const std::complex<double> want =
            std::complex<double>(o.ux[i], o.uy[i]) / std::complex<double>(o.vx[i], o.vy[i]);
        const double tol = 8 * std::abs(want) * std::numeric_limits<double>::epsilon();
        EXPECT_NEAR(q.x, want.real(), tol);
        EXPECT_NEAR(q.y, want.imag(), tol);
    }
}

// ------------------------------------------------------------------ multiplier

// Multiplying by a fixed a + qb is the matrix M = [[a, A b], [b, a + 2B b]] (eq. (14) read as
// a linear map of c + qd). multiply() evaluates exactly that product, so M v equals u * v
// bitwise, for every (A, B).
TEST(QSystemNumbers, MultiplierAgreesWithMultiply) {
    const Operands o = random_operands(1000, 3);
    for (auto [A, B] : systems) {
        auto ns = make<NumberSystem>(qsystem(A, B));
        for (std::size_t i = 0; i < o.ux.size(); ++i) {
            const Vec2 u{o.ux[i], o.uy[i]}, v{o.vx[i], o.vy[i]};
            const fp::Mat2 m = ns->multiplier(u);
            EXPECT_EQ(m.a, u.x);
            EXPECT_EQ(m.b, A * u.y);
            EXPECT_EQ(m.c, u.y);
            EXPECT_EQ(m.d, u.x + 2 * B * u.y);
            const Vec2 mv = m * v, uv = mul(*ns, u, v);
            ASSERT_TRUE(same_bits(mv.x, uv.x) && same_bits(mv.y, uv.y))
                << "A = " << A << ", B = " << B << ", i = " << i;
        }
    }
}

// The q-system numbers commute (paper 02 after eq. (15)); the products round differently
// (a c + (A b) d against c a + (A d) b), so within a few ulps of the operands' scale.
TEST(QSystemNumbers, MultiplicationCommutes) {
    const Operands o = random_operands(1000, 4);
    for (auto [A, B] : systems) {
        auto ns = make<NumberSystem>(qsystem(A, B));
        for (std::size_t i = 0; i < o.ux.size(); ++i) {
            const Vec2 u{o.ux[i], o.uy[i]}, v{o.vx[i], o.vy[i]};
            const Vec2 uv = mul(*ns, u, v), vu = mul(*ns, v, u);
            const double scale = (1 + std::fabs(A) + 2 * std::fabs(B)) * 9 * 4;
            EXPECT_NEAR(uv.x, vu.x, 8 * scale * std::numeric_limits<double>::epsilon());
            EXPECT_NEAR(uv.y, vu.y, 8 * scale * std::numeric_limits<double>::epsilon());
        }
    }
}

// ------------------------------------------------------------------ hand-computed, A = 2, B = 1

TEST(QSystemNumbers, HandComputedProductsA2B1) {
    auto ns = make<NumberSystem>("{type: q-system, A: 2, B: 1}");
    // q^2 = A + 2B q = 2 + 2q (eq. (11)): (0 + 1q)(0 + 1q) = (0 + 2*1*1) + q(0 + 0 + 2*1*1*1).
    EXPECT_EQ(mul(*ns, {0, 1}, {0, 1}), (Vec2{2, 2}));
    // (1 + 2q)(3 + 4q): eq. (14) real part 1*3 + 2*(2*4) = 19, q part 2*3 + 1*4 + 2*1*(2*4) = 26.
    // Expanded: 3 + 4q + 6q + 8q^2 = 3 + 10q + 8(2 + 2q) = 19 + 26q.
    EXPECT_EQ(mul(*ns, {1, 2}, {3, 4}), (Vec2{19, 26}));
    // (2 - q)(-1 + 0.5q): real 2*(-1) + 2*((-1)*0.5) = -3, q (-1)(-1) + 2*0.5 + 2*1*((-1)*0.5) = 1.
    // Expanded: -2 + q + q - 0.5q^2 = -2 + 2q - 0.5(2 + 2q) = -3 + q.
    EXPECT_EQ(mul(*ns, {2, -1}, {-1, 0.5}), (Vec2{-3, 1}));
    // The matrix of 1 + 2q: [[1, A*2], [2, 1 + 2B*2]] = [[1, 4], [2, 5]]; times (3, 4) = (19, 26).
    const fp::Mat2 m = ns->multiplier({1, 2});
    EXPECT_EQ(m.a, 1);
    EXPECT_EQ(m.b, 4);
    EXPECT_EQ(m.c, 2);
    EXPECT_EQ(m.d, 5);
    // Division, eq. (15): (19 + 26q) / (3 + 4q). Denominator 3^2 + 2*1*3*4 - 2*4^2 = 9 + 24 - 32
    // = 1; real 19*3 + 2*1*19*4 - 2*26*4 = 57 + 152 - 208 = 1; q 3*26 - 19*4 = 78 - 76 = 2.
    Vec2 q;
    ASSERT_TRUE(ns->divide({19, 26}, {3, 4}, q));
    EXPECT_EQ(q, (Vec2{1, 2}));
    // (-3 + q) / (-1 + 0.5q): denominator 1 + 2*(-1)(0.5) - 2*0.25 = 1 - 1 - 0.5 = -0.5;
    // real (-3)(-1) + 2*(-3)(0.5) - 2*1*0.5 = 3 - 3 - 1 = -1 -> 2; q (-1)(1) - (-3)(0.5) = 0.5 -> -1.
    ASSERT_TRUE(ns->divide({-3, 1}, {-1, 0.5}, q));
    EXPECT_EQ(q, (Vec2{2, -1}));
}

// ------------------------------------------------------------------ division

// (u v) / v = u and (u / v) v = u wherever the denominator D = c^2 + 2B cd - A d^2 of eq. (15)
// is not small: the quotient's rounding error grows like |v|^2 / |D|, so the test keeps the
// divisors with |D| >= |v|^2 / 4 (for A + B^2 > 0 the zero divisors D = 0 fill two lines
// through 0, and near them the quotient is ill-conditioned, not wrong) and allows a few ulps
// of the operands' scale.
TEST(QSystemNumbers, DivisionInvertsMultiplication) {
    const Operands o = random_operands(1000, 5);
    for (auto [A, B] : systems) {
        auto ns = make<NumberSystem>(qsystem(A, B));
        std::size_t tested = 0;
        for (std::size_t i = 0; i < o.ux.size(); ++i) {
            const Vec2 u{o.ux[i], o.uy[i]}, v{o.vx[i], o.vy[i]};
            const double c = v.x, d = v.y, den = c * c + 2 * B * c * d - A * d * d;
            if (std::fabs(den) < (c * c + d * d) / 4) continue;
            ++tested;
            const double k = 1 + std::fabs(A) + 2 * std::fabs(B);
            const double tol =
                64 * k * k * (1 + std::hypot(u.x, u.y)) * std::numeric_limits<double>::epsilon();
            Vec2 back;
            ASSERT_TRUE(ns->divide(mul(*ns, u, v), v, back));
            EXPECT_NEAR(back.x, u.x, tol) << "A = " << A << ", B = " << B;
            EXPECT_NEAR(back.y, u.y, tol) << "A = " << A << ", B = " << B;
            Vec2 quot;
            ASSERT_TRUE(ns->divide(u, v, quot));
            const Vec2 again = mul(*ns, quot, v);
            EXPECT_NEAR(again.x, u.x, tol) << "A = " << A << ", B = " << B;
            EXPECT_NEAR(again.y, u.y, tol) << "A = " << A << ", B = " << B;
        }
        EXPECT_GT(tested, 300u) << "A = " << A << ", B = " << B;
    }
}

// divide() returns false on a zero denominator and leaves `out` as it was.
TEST(QSystemNumbers, DivisionByZeroDenominatorRefused) {
    const Vec2 untouched{123, 456};
    // Zero itself, in every system: D = 0^2 + 2B*0*0 - A*0^2 = 0.
    for (auto [A, B] : systems) {
        auto ns = make<NumberSystem>(qsystem(A, B));
        Vec2 out = untouched;
        EXPECT_FALSE(ns->divide({1, 2}, {0, 0}, out)) << "A = " << A << ", B = " << B;
        EXPECT_EQ(out, untouched);
    }
    // A = 3, B = 1: q^2 = 3 + 2q. D = c^2 + 2cd - 3d^2 = (c - d)(c + 3d) vanishes at c + qd = 1 + q:
    // 1 + 2*1*1 - 3*1 = 0. Indeed 1 + q is a zero divisor: (1 + q)(-3 + q) by eq. (14) has
    // real part 1*(-3) + 3*(1*1) = 0 and q part 1*(-3) + 1*1 + 2*1*(1*1) = 0.
    {
        auto ns = make<NumberSystem>("{type: q-system, A: 3, B: 1}");
        Vec2 out = untouched;
        EXPECT_FALSE(ns->divide({2, 5}, {1, 1}, out));
        EXPECT_EQ(out, untouched);
        EXPECT_FALSE(ns->divide({2, 5}, {-3, 1}, out)); // 9 - 6 - 3 = 0
        EXPECT_EQ(mul(*ns, {1, 1}, {-3, 1}), (Vec2{0, 0}));
        EXPECT_TRUE(ns->divide({2, 5}, {1, 2}, out)); // 1 + 4 - 12 = -7
    }
    // A = 1, B = 0 (split-complex, q^2 = 1): D = c^2 - d^2, zero on c = +-d: 2 - 2q -> 4 - 4 = 0.
    {
        auto ns = make<NumberSystem>("{type: q-system, A: 1, B: 0}");
        Vec2 out = untouched;
        EXPECT_FALSE(ns->divide({1, 0}, {2, -2}, out));
        EXPECT_EQ(out, untouched);
    }
    // The complex numbers only refuse 0: D = c^2 + d^2.
    {
        auto ns = make<NumberSystem>("{type: complex}");
        Vec2 out;
        EXPECT_TRUE(ns->divide({1, 0}, {2, -2}, out));
        EXPECT_EQ(out, (Vec2{0.25, 0.25})); // 1/(2 - 2i) = (2 + 2i)/8
    }
}

TEST(QSystemNumbers, RealIsReal) {
    EXPECT_TRUE(make<NumberSystem>("{type: real}")->is_real());
    EXPECT_FALSE(make<NumberSystem>("{type: q-system, A: 0, B: 0}")->is_real());
}

} // namespace
