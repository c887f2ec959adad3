// Reductions between the iteration schemes of paper 02 (its Fig. 4 and the formulas of Sec. 3):
// each scheme at its degenerate parameter values is checked against the simpler scheme on a
// batch of 1000 random points, with a star-shaped set inversion (paper 01) and with an affine
// map, in double and float lanes, over the real numbers, the complex numbers and q-systems.
//
// Exact or within ulps: most reductions run the very same floating-point operations on both
// sides, because the schemes build every combination with Chunk::lin from the matrices of their
// parameters: a parameter 0 gives the zero matrix and 1 - 0 the identity, so u = 1 p + 0 T(p)
// is p to the bit, and the following T(u) is T(p) to the bit. Those are compared bitwise. Where
// the reduction needs (1 - c) x + c x = x (S with beta = 0, Picard-S with gamma = 0), the sum
// rounds, and the comparison allows a few ulps of the point's scale (times the local expansion
// of the map, for Picard-S, where T is applied after the rounding).
#include "host.hpp"

#include <fixpoint/host/core/host.hpp>
#include <fixpoint/transform_base.hpp>

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::IterationScheme;
using fp::Transform;

// A plain affine map (a contraction with a rotation), written here so that these tests depend on
// no other transform plugin than the inversion.
class Affine final : public fp::TransformBase<Affine> {
public:
    template <class T>
    void map_pt(T& x, T& y) const {
        const T nx = T(0.6) * x - T(0.35) * y + T(0.2);
        const T ny = T(0.25) * x + T(0.55) * y - T(0.1);
        x = nx;
        y = ny;
    }
};

// A concave star-shaped polygon (an arrow head) inverted about a kernel point off its centroid.
const std::string inversion_yaml =
    "{type: inversion, shape: {type: polygon, vertices: [[-1, -0.8], [0, -0.3], "
    "[1, -0.8], [0, 1]]}, centre: [0, 0.05]}";

struct Map {
    const char* name;
    std::shared_ptr<const Transform> t;
};

const std::vector<Map>& maps() {
    static const std::vector<Map> m = {
        {"inversion", host().make<Transform>(inversion_yaml)},
        {"affine", std::make_shared<Affine>()},
    };
    return m;
}

// 1000 points in [-2, 2]^2, none within 0.05 of the centre of inversion (whose image is far
// away and ill-conditioned).
template <class T>
struct Batch {
    std::vector<T> x, y;
};

template <class T>
Batch<T> random_points() {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> d(-2, 2);
    Batch<T> b;
    while (b.x.size() < 1000) {
        const double x = d(rng), y = d(rng);
        if (std::hypot(x, y - 0.05) < 0.05) continue;
        b.x.push_back(T(x));
        b.y.push_back(T(y));
    }
    return b;
}

/// Runs `steps` one after another on a copy of the batch at step index n. A step "T" is the
/// map itself (the Picard step, through the transform directly).
template <class T>
Batch<T> run(const Transform& t, const std::vector<std::string>& steps, std::uint64_t n) {
    Batch<T> b = random_points<T>();
    const fp::Points<T> p{b.x.data(), b.y.data(), b.x.size()};
    for (const std::string& s : steps) {
        if (s == "T")
            t.apply(p, nullptr);
        else
            make<IterationScheme>(s)->step(t, p, nullptr, n);
    }
    return b;
}

template <class T>
bool same_bits(T a, T b) {
    if constexpr (sizeof(T) == 8)
        return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
    else
        return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

/// The number systems the reductions run in, with the "free" parameter values of each: real
/// values for the reals, q-numbers a + qb otherwise. The reduction values (0, 1) are the same
/// numbers 0 + 0q and 1 + 0q in every system.
struct System {
    const char* name;
    std::string numbers; ///< ", numbers: {...}" or empty
    std::string v1, v2, v3;
};

const std::vector<System> systems = {
    {"real", "", "0.7", "0.3", "1.5"},
    {"complex", ", numbers: {type: complex}", "0.7+0.3q", "0.3-0.2q", "1.5+0.1q"},
    {"q(-1.5,0.2)", ", numbers: {type: q-system, A: -1.5, B: 0.2}", "0.5+0.5q", "0.9+0.5q", "0.75-0.9q"},
    {"q(2,1)", ", numbers: {type: q-system, A: 2, B: 1}", "1.1-0.2q", "0.1-0.2q", "0.3+0.5q"},
};

struct Reduction {
    const char* name;
    std::vector<std::string> lhs, rhs;
    bool exact;
    /// Tolerance in units of epsilon times the point's scale (inexact reductions only).
    double ulps = 0;
};

std::string sub(std::string s, const System& sys) {
    auto rep = [&](const std::string& key, const std::string& val) {
        for (std::size_t i; (i = s.find(key)) != std::string::npos;) s.replace(i, key.size(), val);
    };
    rep("$N", sys.numbers);
    rep("$1", sys.v1);
    rep("$2", sys.v2);
    rep("$3", sys.v3);
    return s;
}

// $1, $2, $3 are the system's free values; $N its `numbers:`.
const std::vector<Reduction> reductions = {
    {"Mann(alpha=1) = Picard", {"{type: mann, alpha: 1$N}"}, {"T"}, true},
    {"Ishikawa(a=0) = Mann", {"{type: ishikawa, alpha: $1, a: 0$N}"}, {"{type: mann, alpha: $1$N}"}, true},
    {"Ishikawa(alpha=1, a=0) = Picard", {"{type: ishikawa, alpha: 1, a: 0$N}"}, {"T"}, true},
    {"Noor(gamma=0) = Ishikawa",
     {"{type: noor, alpha: $1, a: $2, gamma: 0$N}"},
     {"{type: ishikawa, alpha: $1, a: $2$N}"},
     true},
    {"Noor(a=gamma=0) = Mann",
     {"{type: noor, alpha: $1, a: 0, gamma: 0$N}"},
     {"{type: mann, alpha: $1$N}"},
     true},
    {"SP(a=gamma=0) = Mann",
     {"{type: sp, alpha: $1, a: 0, gamma: 0$N}"},
     {"{type: mann, alpha: $1$N}"},
     true},
    // SP is three Mann steps in a row (gamma, then a, then alpha).
    {"SP = Mann(gamma) Mann(a) Mann(alpha)",
     {"{type: sp, alpha: $1, a: $2, gamma: $3$N}"},
     {"{type: mann, alpha: $3$N}", "{type: mann, alpha: $2$N}", "{type: mann, alpha: $1$N}"},
     true},
    {"Khan = Mann then Picard", {"{type: khan, a: $2$N}"}, {"{type: mann, alpha: $2$N}", "T"}, true},
    {"Khan(a=0) = Picard", {"{type: khan, a: 0$N}"}, {"T"}, true},
    {"Khan(a=1) = Picard twice", {"{type: khan, a: 1$N}"}, {"T", "T"}, true},
    {"S(alpha=1, beta=x) = Khan(alpha=x)",
     {"{type: s-iteration, alpha: 1, beta: $2$N}"},
     {"{type: khan, a: $2$N}"},
     true},
    // (1 - alpha) T(p) + alpha T(p) rounds: under an ulp of the point's scale measured (the
    // coefficient matrices are small); 8 leaves room.
    {"S(beta=0) = Picard", {"{type: s-iteration, alpha: $1, beta: 0$N}"}, {"T"}, false, 8},
    {"Picard-S(beta, gamma) = T o S(alpha=beta, beta=gamma)",
     {"{type: picard-s, beta: $3, gamma: $2$N}"},
     {"{type: s-iteration, alpha: $3, beta: $2$N}", "T"},
     true},
    // u = (1 - beta) T(p) + beta T(p) rounds, then T is applied to it, so the error is an ulp or
    // so times the local expansion of T at T(p): about 5 eps-scales measured for the inversion,
    // 1 for the affine map; 64 leaves room.
    {"Picard-S(gamma=0) = Picard twice", {"{type: picard-s, beta: $3, gamma: 0$N}"}, {"T", "T"}, false, 64},
};

template <class T>
void check(const Reduction& r, const System& sys, const Map& m) {
    std::vector<std::string> lhs, rhs;
    for (const auto& s : r.lhs) lhs.push_back(sub(s, sys));
    for (const auto& s : r.rhs) rhs.push_back(sub(s, sys));
    const std::uint64_t n = 5;
    const Batch<T> a = run<T>(*m.t, lhs, n), b = run<T>(*m.t, rhs, n);
    const double eps = std::numeric_limits<T>::epsilon();
    std::size_t bad = 0, first = 0;
    double worst = 0;
    for (std::size_t i = 0; i < a.x.size(); ++i) {
        bool ok;
        if (r.exact) {
            ok = same_bits(a.x[i], b.x[i]) && same_bits(a.y[i], b.y[i]);
        } else {
            const double scale = 1 + std::fmax(std::fabs(double(b.x[i])), std::fabs(double(b.y[i])));
            const double err =
                std::fmax(std::fabs(double(a.x[i]) - b.x[i]), std::fabs(double(a.y[i]) - b.y[i]));
            worst = std::fmax(worst, err / (scale * eps));
            ok = err <= r.ulps * scale * eps;
        }
        if (!ok && bad++ == 0) first = i;
    }
    EXPECT_EQ(bad, 0u) << r.name << " [" << sys.name << ", " << m.name << ", "
                       << (sizeof(T) == 8 ? "double" : "float") << "]: first at " << first << ": ("
                       << a.x[first] << ", " << a.y[first] << ") vs (" << b.x[first] << ", " << b.y[first]
                       << "); worst " << worst << " eps-scales\n  " << lhs[0] << "\n  " << rhs[0];
}

TEST(SchemeReductions, AllSchemesAllSystems) {
    for (const auto& r : reductions)
        for (const auto& sys : systems)
            for (const auto& m : maps()) {
                check<double>(r, sys, m);
                check<float>(r, sys, m);
            }
}

// ------------------------------------------------------------------ sequences

// Mann with alpha [0.7, 0.9] uses 0.7 at even steps and 0.9 at odd ones (paper 02 eq. (29)).
TEST(SchemeReductions, PeriodicSequenceAlternates) {
    for (const auto& m : maps())
        for (std::uint64_t n : {0, 1, 2, 3}) {
            const auto a = run<double>(*m.t, {"{type: mann, alpha: [0.7, 0.9]}"}, n);
            const auto b =
                run<double>(*m.t, {n % 2 == 0 ? "{type: mann, alpha: 0.7}" : "{type: mann, alpha: 0.9}"}, n);
            EXPECT_EQ(a.x, b.x) << m.name << " n = " << n;
            EXPECT_EQ(a.y, b.y) << m.name << " n = " << n;
        }
}

// A longer list cycles with period 3; a list of q-numbers likewise.
TEST(SchemeReductions, PeriodicSequenceOfThreeAndOfQNumbers) {
    const char* real_vals[] = {"0.7", "0.9", "0.5"};
    const char* q_vals[] = {"0.5+0.5q", "0.1+2q"};
    for (const auto& m : maps())
        for (std::uint64_t n = 0; n < 6; ++n) {
            auto a = run<double>(*m.t, {"{type: ishikawa, alpha: [0.7, 0.9, 0.5], a: 0.2}"}, n);
            auto b = run<double>(
                *m.t, {std::string("{type: ishikawa, alpha: ") + real_vals[n % 3] + ", a: 0.2}"}, n);
            EXPECT_EQ(a.x, b.x) << m.name << " n = " << n;
            EXPECT_EQ(a.y, b.y) << m.name << " n = " << n;
            a = run<double>(*m.t, {"{type: khan, a: [0.5+0.5q, [0.1, 2]], numbers: {type: complex}}"}, n);
            b = run<double>(
                *m.t, {std::string("{type: khan, a: ") + q_vals[n % 2] + ", numbers: {type: complex}}"}, n);
            EXPECT_EQ(a.x, b.x) << m.name << " n = " << n;
            EXPECT_EQ(a.y, b.y) << m.name << " n = " << n;
        }
}

// Two plain numbers [x, y] are a periodic list over the reals but the single q-number x + qy
// in a q-system (fp::Sequence::bare_pair): the same at every step.
TEST(SchemeReductions, BarePairIsOneQNumberInAQSystem) {
    const std::string ns = ", numbers: {type: q-system, A: -1.5, B: 0.2}}";
    for (const auto& m : maps())
        for (std::uint64_t n : {0, 1}) {
            const auto a = run<double>(*m.t, {"{type: mann, alpha: [0.7, 0.9]" + ns}, n);
            const auto b = run<double>(*m.t, {"{type: mann, alpha: 0.7+0.9q" + ns}, n);
            EXPECT_EQ(a.x, b.x) << m.name << " n = " << n;
            EXPECT_EQ(a.y, b.y) << m.name << " n = " << n;
        }
}

// The step honours the mask: inactive points are left as they were.
TEST(SchemeReductions, MaskLeavesInactivePoints) {
    const Transform& t = *maps()[0].t;
    for (const char* yaml :
         {"{type: ishikawa, alpha: 0.7, a: 0.3}", "{type: noor}", "{type: sp}", "{type: khan}",
          "{type: s-iteration}", "{type: picard-s, beta: 1.5, gamma: 0.8}"}) {
        auto s = make<IterationScheme>(yaml);
        Batch<double> b = random_points<double>(), full = b;
        std::vector<unsigned char> mask(b.x.size());
        for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = i % 3 != 0;
        s->step(t, {b.x.data(), b.y.data(), b.x.size()}, mask.data(), 2);
        s->step(t, {full.x.data(), full.y.data(), full.x.size()}, nullptr, 2);
        const Batch<double> orig = random_points<double>();
        for (std::size_t i = 0; i < mask.size(); ++i) {
            const Batch<double>& want = mask[i] ? full : orig;
            ASSERT_EQ(b.x[i], want.x[i]) << yaml << " i = " << i;
            ASSERT_EQ(b.y[i], want.y[i]) << yaml << " i = " << i;
        }
    }
}

TEST(SchemeReductions, ApplicationsPerStep) {
    EXPECT_EQ(make<IterationScheme>("{type: mann}")->applications(), 1u);
    EXPECT_EQ(make<IterationScheme>("{type: ishikawa}")->applications(), 2u);
    EXPECT_EQ(make<IterationScheme>("{type: noor}")->applications(), 3u);
    EXPECT_EQ(make<IterationScheme>("{type: sp}")->applications(), 3u);
    EXPECT_EQ(make<IterationScheme>("{type: khan}")->applications(), 2u);
    EXPECT_EQ(make<IterationScheme>("{type: s-iteration}")->applications(), 2u);
    EXPECT_EQ(make<IterationScheme>("{type: picard-s}")->applications(), 3u);
}

// ------------------------------------------------------------------ bad input

std::string error_of(const std::string& yaml) {
    try {
        host().make<IterationScheme>(yaml);
    } catch (const fp::InputError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(SchemeReductions, QNumberInARealSchemeRefused) {
    const std::string e = error_of("{type: s-iteration, alpha: 0.9+0.9q, beta: 0.2}");
    EXPECT_NE(e.find("alpha"), std::string::npos) << e;
    EXPECT_NE(e.find("0.9+0.9q is a q-system number, but the scheme computes in the real numbers"),
              std::string::npos)
        << e;
    // Inside a periodic list too.
    const std::string e2 = error_of("{type: picard-s, beta: 0.6, gamma: [0.8, 0.1-0.2q]}");
    EXPECT_NE(e2.find("gamma"), std::string::npos) << e2;
    EXPECT_NE(e2.find("0.1-0.2q is a q-system number"), std::string::npos) << e2;
    // The same values are fine in a q-system.
    EXPECT_EQ(error_of("{type: s-iteration, alpha: 0.9+0.9q, beta: 0.2, numbers: {type: complex}}"),
              "(no error)");
}

TEST(SchemeReductions, UnreadableQNumberRefused) {
    for (const char* bad : {"0.5+0.5z", "0.5q+1", "q0.5", "0.5++0.5q", "--1"}) {
        const std::string e = error_of(std::string("{type: noor, alpha: '") + bad +
                                       "', numbers: {type: q-system, A: -1, B: 0}}");
        EXPECT_NE(e.find("alpha"), std::string::npos) << e;
        EXPECT_NE(e.find("as a number or q-system number (write 0.7, 0.5+0.5q or [0.5, 0.5])"),
                  std::string::npos)
            << bad << ": " << e;
    }
    // An empty periodic list.
    const std::string e = error_of("{type: khan, a: []}");
    EXPECT_NE(e.find("a periodic list must not be empty"), std::string::npos) << e;
}

} // namespace
