// The SDK's transcendental functions on double lanes (fixpoint/simd-math-inl.hpp): against
// libm within a few ulps over the ranges kernels use them in, C's special values, and the
// same bits on every SIMD target this machine has.
#include <fixpoint/simd.hpp>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "unit/test_simd_math.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include <fixpoint/simd-math-inl.hpp>

#include <cstddef>
#include <vector>

#ifndef FIXPOINT_TEST_SIMD_MATH_ONCE
#define FIXPOINT_TEST_SIMD_MATH_ONCE
namespace fp_test_math {
enum Fn { Sin, Cos, Atan2, Log, Exp, Pow };
} // namespace fp_test_math
#endif

// Per target: out = f(a, b) lane by lane over the whole arrays (n a multiple of no vector
// length needed: the tail runs through a padded buffer).
HWY_BEFORE_NAMESPACE();
namespace fp_test_math::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace fs = fp::simd::HWY_NAMESPACE;

void apply(int fn, const double* a, const double* b, double* out, std::size_t n) {
    const hn::ScalableTag<double> d;
    const std::size_t N = hn::Lanes(d);
    for (std::size_t i = 0; i < n; i += N) {
        alignas(HWY_MAX_BYTES) double ba[HWY_MAX_BYTES / 8] = {}, bb[HWY_MAX_BYTES / 8] = {},
                                                         bo[HWY_MAX_BYTES / 8];
        const std::size_t m = n - i < N ? n - i : N;
        for (std::size_t k = 0; k < m; ++k) ba[k] = a[i + k], bb[k] = b[i + k];
        const auto x = hn::Load(d, ba), y = hn::Load(d, bb);
        hn::Vec<decltype(d)> r;
        switch (fn) {
        case Sin:
        case Cos: {
            hn::Vec<decltype(d)> s, c;
            fs::sin_cos(d, x, s, c);
            r = fn == Sin ? s : c;
            break;
        }
        case Atan2: r = fs::atan2(d, x, y); break;
        case Log: r = fs::log(d, x); break;
        case Exp: r = fs::exp(d, x); break;
        default: r = fs::pow_abs(d, x, y); break;
        }
        hn::Store(r, d, bo);
        for (std::size_t k = 0; k < m; ++k) out[i + k] = bo[k];
    }
}

} // namespace fp_test_math::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp_test_math {
HWY_EXPORT(apply);
} // namespace fp_test_math

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>

namespace {

using namespace fp_test_math;

std::vector<double> run(int fn, const std::vector<double>& a, const std::vector<double>& b) {
    std::vector<double> out(a.size());
    HWY_DYNAMIC_DISPATCH(apply)(fn, a.data(), b.data(), out.data(), a.size());
    return out;
}

/// Distance in units in the last place between two finite doubles (by their ordered bits).
double ulps(double a, double b) {
    if (a == b) return 0;
    auto key = [](double v) {
        std::int64_t i;
        std::memcpy(&i, &v, 8);
        return i < 0 ? std::numeric_limits<std::int64_t>::min() - i : i;
    };
    const std::int64_t ka = key(a), kb = key(b);
    return double(ka > kb ? std::uint64_t(ka) - std::uint64_t(kb) : std::uint64_t(kb) - std::uint64_t(ka));
}

struct Case {
    const char* name;
    int fn;
    double a0, a1, b0, b1; // uniform ranges of the arguments
    double max_ulps;
    double (*ref)(double, double);
};

// The ranges are those the kernels use (superformula: angles of a few turns, |cos| and |sin|
// in [0, 1] to exponents of either sign, sums of such powers), and more.
const Case cases[] = {
    {"sin", Sin, -40, 40, 0, 0, 2, [](double a, double) { return std::sin(a); }},
    {"cos", Cos, -40, 40, 0, 0, 2, [](double a, double) { return std::cos(a); }},
    {"atan2", Atan2, -3, 3, -3, 3, 2, [](double a, double b) { return std::atan2(a, b); }},
    {"log", Log, 1e-6, 1e6, 0, 0, 2, [](double a, double) { return std::log(a); }},
    {"log near 1", Log, 0.5, 2, 0, 0, 2, [](double a, double) { return std::log(a); }},
    {"exp", Exp, -700, 700, 0, 0, 2, [](double a, double) { return std::exp(a); }},
    {"exp small", Exp, -2, 2, 0, 0, 2, [](double a, double) { return std::exp(a); }},
    // exp(y log x) carries log's absolute error times y: relative, about |y log x| ulps.
    {"pow", Pow, 1e-3, 1, -8, 8, 64, [](double a, double b) { return std::pow(a, b); }},
};

TEST(SimdMath, CloseToLibmOnEveryTarget) {
    std::mt19937_64 rng(7);
    for (const Case& c : cases) {
        std::uniform_real_distribution<double> ua(c.a0, c.a1), ub(c.b0, c.b1);
        std::vector<double> a(100003), b(a.size());
        for (std::size_t i = 0; i < a.size(); ++i) a[i] = ua(rng), b[i] = c.b1 > c.b0 ? ub(rng) : 0;
        std::vector<double> first;
        for (const std::string& target : fp::simd::supported_targets()) {
            SCOPED_TRACE(std::string(c.name) + " on " + target);
            ASSERT_TRUE(fp::simd::force_target(target));
            const auto r = run(c.fn, a, b);
            double worst = 0;
            std::size_t at = 0;
            for (std::size_t i = 0; i < a.size(); ++i) {
                const double e = ulps(r[i], c.ref(a[i], b[i]));
                if (e > worst) worst = e, at = i;
            }
            EXPECT_LE(worst, c.max_ulps)
                << "at " << a[at] << ", " << b[at] << ": " << r[at] << " against " << c.ref(a[at], b[at]);
            if (first.empty())
                first = r;
            else
                EXPECT_EQ(0, std::memcmp(first.data(), r.data(), r.size() * sizeof(double)))
                    << "bits differ from " << fp::simd::supported_targets().front();
        }
    }
    fp::simd::force_target("");
}

TEST(SimdMath, SpecialValues) {
    const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
    auto one = [](int fn, double a, double b = 0) { return run(fn, {a}, {b})[0]; };
    EXPECT_EQ(one(Log, 0), -inf);
    EXPECT_EQ(one(Log, inf), inf);
    EXPECT_TRUE(std::isnan(one(Log, -1)));
    EXPECT_TRUE(std::isnan(one(Log, nan)));
    EXPECT_EQ(one(Log, 1), 0);
    EXPECT_NEAR(one(Log, 4.9406564584124654e-324), std::log(4.9406564584124654e-324), 1e-13); // subnormal
    EXPECT_EQ(one(Exp, 0), 1);
    EXPECT_EQ(one(Exp, 710), inf);
    EXPECT_EQ(one(Exp, -inf), 0);
    EXPECT_EQ(one(Exp, -746), 0);
    EXPECT_EQ(one(Exp, -740), std::exp(-740)); // subnormal result
    EXPECT_TRUE(std::isnan(one(Exp, nan)));
    EXPECT_EQ(one(Pow, 0, 2), 0);
    EXPECT_EQ(one(Pow, 0, -2), inf);
    EXPECT_EQ(one(Pow, 0, 0), 1);
    EXPECT_EQ(one(Pow, inf, -0.5), 0);
    EXPECT_EQ(one(Pow, 1, 7), 1);
    EXPECT_EQ(one(Pow, 2, 10), 1024);
    const double pi = 3.14159265358979323846;
    EXPECT_EQ(one(Atan2, 0.0, 1), 0);
    EXPECT_TRUE(std::signbit(one(Atan2, -0.0, 1)));
    EXPECT_EQ(one(Atan2, 0.0, -1), pi);
    EXPECT_EQ(one(Atan2, -0.0, -1), -pi);
    EXPECT_EQ(one(Atan2, 0.0, -0.0), pi);
    EXPECT_EQ(one(Atan2, 0.0, 0.0), 0);
    EXPECT_EQ(one(Atan2, 1, 0), pi / 2);
    EXPECT_EQ(one(Atan2, -1, 0), -pi / 2);
    EXPECT_EQ(one(Atan2, 1, 1), pi / 4);
    EXPECT_EQ(one(Sin, 0), 0);
    EXPECT_EQ(one(Cos, 0), 1);
    EXPECT_TRUE(std::isnan(one(Sin, nan)));
}

} // namespace
#endif // HWY_ONCE
