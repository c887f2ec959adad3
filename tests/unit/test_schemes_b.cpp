// Unit tests of the three-step schemes (CR, Karakaya, Suantai), Schu, switching and the
// affine transform (paper 02, eqs. (5), (7), (8), (21)-(27), Sec. 6).
//
// The reductions between schemes (paper 02 Fig. 4 and what follows from the formulas) are
// checked on batches of points, under an affine map (not an involution) and under circle and
// polygon inversions, with real parameters and with q-system numbers (Q_{2,1}). Where the two
// sides do the same arithmetic in the same order they must agree to the bit; elsewhere to a
// few ulps (the sides group the same sums differently, e.g. alpha + beta against two
// separate weights).
#include "cli.hpp"
#include "configs.hpp"

#include "host.hpp"
#include <fixpoint/fixpoint.hpp>

#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::IterationScheme;
using fp::Transform;
using fp::Vec2;

/// A batch of points, structure of arrays.
struct Pts {
    std::vector<double> x, y;
    std::size_t size() const { return x.size(); }
};

/// One step of a process under map t at step index n: what the tests compare.
using Step = std::function<Pts(const Transform&, Pts, std::uint64_t)>;

Step step_of(const std::string& yaml) {
    std::shared_ptr<const IterationScheme> s = make<IterationScheme>(yaml);
    return [s, yaml](const Transform& t, Pts p, std::uint64_t n) {
        if (!s)
            ADD_FAILURE() << "no scheme " << yaml;
        else
            s->step(t, fp::Points<double>{p.x.data(), p.y.data(), p.size()}, nullptr, n);
        return p;
    };
}

Pts apply(const Transform& t, Pts p) {
    t.apply(fp::Points<double>{p.x.data(), p.y.data(), p.size()}, nullptr);
    return p;
}

const Step picard = [](const Transform& t, Pts p, std::uint64_t) { return apply(t, p); };
const Step identity = [](const Transform&, Pts p, std::uint64_t) { return p; };

/// b after a, both at the same step index.
Step then(Step a, Step b) {
    return [a, b](const Transform& t, Pts p, std::uint64_t n) { return b(t, a(t, std::move(p), n), n); };
}

struct Map {
    std::string yaml;
    Vec2 o;              ///< centre of inversion (points are drawn in a ring about it)
    double r_min, r_max; ///< the ring (r_min = 0: the square [-r_max, r_max]^2 instead)
};

const Map affine_map{"{type: affine, coefficients: [0.6, -0.3, 0.25, 0.5, 0.1, -0.2]}", {0, 0}, 0, 2};
const Map circle_map{
    "{type: inversion, shape: {type: circle, centre: [0.3, -0.2], radius: 0.9}}", {0.3, -0.2}, 0.4, 2.5};
const Map star_map{
    "{type: inversion, shape: {type: star-polygon, points: 5, outer_radius: 1, inner_radius: 0.5}}",
    {0, 0},
    0.4,
    2.5};
const Map maps[] = {affine_map, circle_map, star_map};

Pts sample(const Map& m, std::size_t count, std::uint64_t seed) {
    fp::Rng rng = fp::chain_stream(seed, 3);
    Pts p;
    for (std::size_t i = 0; i < count; ++i) {
        const double u = fp::uniform_double(rng), v = fp::uniform_double(rng);
        if (m.r_min == 0) {
            p.x.push_back(-m.r_max + 2 * m.r_max * u);
            p.y.push_back(-m.r_max + 2 * m.r_max * v);
        } else {
            const double r = m.r_min + (m.r_max - m.r_min) * u, a = 6.283185307179586 * v;
            p.x.push_back(m.o.x + r * std::cos(a));
            p.y.push_back(m.o.y + r * std::sin(a));
        }
    }
    return p;
}

bool same_bits(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

/// got == want to the bit (tol = 0) or within tol (1 + |want|) per coordinate.
void expect_points(const Pts& got, const Pts& want, double tol, const std::string& what) {
    ASSERT_EQ(got.size(), want.size());
    std::size_t bad = 0, first = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        const bool ok = tol == 0 ? same_bits(got.x[i], want.x[i]) && same_bits(got.y[i], want.y[i])
                                 : std::fabs(got.x[i] - want.x[i]) <= tol * (1 + std::fabs(want.x[i])) &&
                                       std::fabs(got.y[i] - want.y[i]) <= tol * (1 + std::fabs(want.y[i]));
        if (!ok && bad++ == 0) first = i;
    }
    EXPECT_EQ(bad, 0u) << what << ": " << bad << " of " << got.size() << " points differ; first: got ("
                       << got.x[first] << ", " << got.y[first] << "), want (" << want.x[first] << ", "
                       << want.y[first] << ")";
}

/// a and b agree on batches under every test map at steps 0..5.
void expect_same(const Step& a, const Step& b, double tol, const std::string& what) {
    for (const Map& m : maps) {
        auto t = make<Transform>(m.yaml);
        ASSERT_TRUE(t);
        const Pts p = sample(m, 600, 5);
        for (std::uint64_t n = 0; n < 6; ++n)
            expect_points(a(*t, p, n), b(*t, p, n), tol,
                          what + " under " + m.yaml + " at n = " + std::to_string(n));
    }
}

constexpr double ulps = 1e-13;
const std::string Q = ", numbers: {type: q-system, A: 2, B: 1}";

// ------------------------------------------------------------------ Suantai, eq. (5)

TEST(Suantai, BetaAndBZeroIsNoor) {
    // u = (1 - a) p + a T(v), p' = (1 - alpha) p + alpha T(u): Noor (alpha, a, gamma).
    expect_same(step_of("{type: suantai, alpha: 0.7, beta: 0, gamma: 0.4, a: 0.3, b: 0}"),
                step_of("{type: noor, alpha: 0.7, a: 0.3, gamma: 0.4}"), ulps, "real");
    expect_same(step_of("{type: suantai, alpha: [1.1, 0.6], beta: 0, gamma: -0.3, a: [0.2, 0.5, 0.9], b: 0}"),
                step_of("{type: noor, alpha: [1.1, 0.6], a: [0.2, 0.5, 0.9], gamma: -0.3}"), ulps,
                "sequences");
    expect_same(
        step_of("{type: suantai, alpha: 0.3+0.2q, beta: 0, gamma: 0.4-0.1q, a: [0.3, 0.6+0.1q], b: 0" + Q +
                "}"),
        step_of("{type: noor, alpha: 0.3+0.2q, a: [0.3, 0.6+0.1q], gamma: 0.4-0.1q" + Q + "}"), 1e-11,
        "q-system");
}

TEST(Suantai, AlphaZeroIsIshikawa) {
    // p' = (1 - beta) p + beta T(v), v = (1 - gamma) p + gamma T(p): Ishikawa (beta, gamma).
    expect_same(step_of("{type: suantai, alpha: 0, beta: 0.6, gamma: 0.3, a: 0.4, b: 0.2}"),
                step_of("{type: ishikawa, alpha: 0.6, a: 0.3}"), ulps, "real");
    expect_same(
        step_of("{type: suantai, alpha: 0, beta: 0.6-0.1q, gamma: 0.3+0.2q, a: 0.4, b: 0.2q" + Q + "}"),
        step_of("{type: ishikawa, alpha: 0.6-0.1q, a: 0.3+0.2q" + Q + "}"), 1e-11, "q-system");
}

TEST(Suantai, NoInnerStepsIsMannWithAlphaPlusBeta) {
    // a = b = gamma = 0: u = v = p, p' = (1 - alpha - beta) p + (alpha + beta) T(p).
    expect_same(step_of("{type: suantai, alpha: 0.5, beta: 0.25, gamma: 0, a: 0, b: 0}"),
                step_of("{type: mann, alpha: 0.75}"), ulps, "real");
    expect_same(step_of("{type: suantai, alpha: 0.5+0.25q, beta: 0.25-0.5q, gamma: 0, a: 0, b: 0" + Q + "}"),
                step_of("{type: mann, alpha: 0.75-0.25q" + Q + "}"), ulps, "q-system");
}

TEST(Suantai, AlphaAndBetaZeroIsTheIdentity) {
    expect_same(step_of("{type: suantai, alpha: 0, beta: 0, gamma: 0.3, a: 0.4, b: 0.2}"), identity, 0,
                "real");
    expect_same(step_of("{type: suantai, alpha: 0, beta: 0, gamma: 0.3q, a: 0.4, b: 0.2+0.1q" + Q + "}"),
                identity, 0, "q-system");
}

// ------------------------------------------------------------------ Karakaya, eq. (8)

TEST(Karakaya, BetaAndBZeroIsSp) {
    // u = (1 - a) v + a T(v), p' = (1 - alpha) u + alpha T(u): SP (alpha, a, gamma).
    expect_same(step_of("{type: karakaya, alpha: 0.7, beta: 0, gamma: 0.1, a: 0.4, b: 0}"),
                step_of("{type: sp, alpha: 0.7, a: 0.4, gamma: 0.1}"), ulps, "real");
    expect_same(
        step_of("{type: karakaya, alpha: 0.5+0.5q, beta: 0, gamma: 0.75-0.9q, a: 0.9+0.5q, b: 0" + Q + "}"),
        step_of("{type: sp, alpha: 0.5+0.5q, a: 0.9+0.5q, gamma: 0.75-0.9q" + Q + "}"), 1e-11, "q-system");
}

TEST(Karakaya, OnlyGammaIsMann) {
    // alpha = beta = a = b = 0: p' = u = v = (1 - gamma) p + gamma T(p).
    expect_same(step_of("{type: karakaya, alpha: 0, beta: 0, gamma: 0.35, a: 0, b: 0}"),
                step_of("{type: mann, alpha: 0.35}"), 0, "real");
    expect_same(step_of("{type: karakaya, alpha: 0, beta: 0, gamma: 0.35-0.2q, a: 0, b: 0" + Q + "}"),
                step_of("{type: mann, alpha: 0.35-0.2q" + Q + "}"), 0, "q-system");
}

TEST(Karakaya, ABZeroIsTwoMannSteps) {
    // a = b = 0: u = v, p' = (1 - alpha - beta) v + (alpha + beta) T(v): Mann(gamma) then
    // Mann(alpha + beta).
    expect_same(step_of("{type: karakaya, alpha: 0.5, beta: 0.25, gamma: 0.3, a: 0, b: 0}"),
                then(step_of("{type: mann, alpha: 0.3}"), step_of("{type: mann, alpha: 0.75}")), ulps,
                "real");
    expect_same(step_of("{type: karakaya, alpha: 0.5q, beta: 0.25, gamma: 0.3+0.1q, a: 0, b: 0" + Q + "}"),
                then(step_of("{type: mann, alpha: 0.3+0.1q" + Q + "}"),
                     step_of("{type: mann, alpha: 0.25+0.5q" + Q + "}")),
                ulps, "q-system");
}

// ------------------------------------------------------------------ CR, eq. (7)

TEST(Cr, AlphaZeroIsS) {
    // p' = u = (1 - beta) T(p) + beta T(v): the S-iteration (6) with (alpha, beta) = (beta, gamma).
    expect_same(step_of("{type: cr, alpha: 0, beta: 0.6, gamma: 0.2}"),
                step_of("{type: s-iteration, alpha: 0.6, beta: 0.2}"), ulps, "real");
    expect_same(step_of("{type: cr, alpha: 0, beta: 0.9+0.9q, gamma: 0.2+0.2q" + Q + "}"),
                step_of("{type: s-iteration, alpha: 0.9+0.9q, beta: 0.2+0.2q" + Q + "}"), 1e-11, "q-system");
}

TEST(Cr, AlphaOneIsPicardS) {
    // p' = T(u), u = (1 - beta) T(p) + beta T(v): Picard-S (beta, gamma).
    expect_same(step_of("{type: cr, alpha: 1, beta: 1.5, gamma: 0.8}"),
                step_of("{type: picard-s, beta: 1.5, gamma: 0.8}"), ulps, "real");
    expect_same(step_of("{type: cr, alpha: 1, beta: 0.6-0.1q, gamma: 0.8q" + Q + "}"),
                step_of("{type: picard-s, beta: 0.6-0.1q, gamma: 0.8q" + Q + "}"), 1e-11, "q-system");
}

TEST(Cr, BetaGammaZeroIsMannAfterT) {
    // v = p, u = T(p): p' = (1 - alpha) T(p) + alpha T(T(p)), Mann(alpha) applied to T(p).
    expect_same(step_of("{type: cr, alpha: 0.7, beta: 0, gamma: 0}"),
                then(picard, step_of("{type: mann, alpha: 0.7}")), 0, "real");
    expect_same(step_of("{type: cr, alpha: 0.7-0.3q, beta: 0, gamma: 0" + Q + "}"),
                then(picard, step_of("{type: mann, alpha: 0.7-0.3q" + Q + "}")), 0, "q-system");
    // beta = 0 alone: u = T(p) whatever gamma.
    expect_same(step_of("{type: cr, alpha: [0.7, 1.3], beta: 0, gamma: 0.45}"),
                then(picard, step_of("{type: mann, alpha: [0.7, 1.3]}")), 0, "beta = 0");
}

TEST(Cr, PicardLimits) {
    // alpha = beta = 0: p' = T(p); alpha = 1, beta = 0: p' = T(T(p)).
    expect_same(step_of("{type: cr, alpha: 0, beta: 0, gamma: 0.4}"), picard, 0, "alpha = beta = 0");
    expect_same(step_of("{type: cr, alpha: 1, beta: 0, gamma: 0.4}"), then(picard, picard), 0,
                "alpha = 1, beta = 0");
}

// ------------------------------------------------------------------ Schu, eqs. (21)-(25)

/// Step-by-step chain over changing maps (as in a chaos game): a and b to the bit at each n.
void expect_same_chain(const std::string& a_yaml, const std::string& b_yaml,
                       const std::vector<std::string>& chain_maps, std::uint64_t steps) {
    auto a = make<IterationScheme>(a_yaml), b = make<IterationScheme>(b_yaml);
    ASSERT_TRUE(a && b);
    std::vector<std::shared_ptr<const Transform>> ts;
    for (const auto& m : chain_maps) ts.push_back(make<Transform>(m));
    Pts p = sample(circle_map, 700, 9), q = p;
    std::vector<float> fx(p.x.begin(), p.x.end()), fy(p.y.begin(), p.y.end()), gx = fx, gy = fy;
    for (std::uint64_t n = 0; n < steps; ++n) {
        const Transform& t = *ts[n % ts.size()];
        a->step(t, fp::Points<double>{p.x.data(), p.y.data(), p.size()}, nullptr, n);
        b->step(t, fp::Points<double>{q.x.data(), q.y.data(), q.size()}, nullptr, n);
        expect_points(p, q, 0, a_yaml + " against " + b_yaml + " at n = " + std::to_string(n));
        a->step(t, fp::Points<float>{fx.data(), fy.data(), fx.size()}, nullptr, n);
        b->step(t, fp::Points<float>{gx.data(), gy.data(), gx.size()}, nullptr, n);
        std::size_t bad = 0;
        for (std::size_t i = 0; i < fx.size(); ++i) bad += !(fx[i] == gx[i] && fy[i] == gy[i]);
        EXPECT_EQ(bad, 0u) << "float, at n = " << n;
    }
}

const std::vector<std::string> three_circles = {
    "{type: inversion, shape: {type: circle, centre: [1, 0], radius: 0.9}}",
    "{type: inversion, shape: {type: circle, centre: [-0.5, 0.866], radius: 0.9}}",
    "{type: inversion, shape: {type: star-polygon, points: 5, outer_radius: 0.6, inner_radius: 0.35}}",
};

TEST(Schu, OnAnInvolutionIsMannWithEq24) {
    // Eq. (21) with T^2 = id: step n (from 0) is a Mann step with alpha_n when n + 1 is odd
    // (n even) and leaves p alone when n is odd. So Schu(alpha) = Mann(beta) with beta_n =
    // alpha_n at even n and 0 at odd n (eq. (24), parities as in the paper's p_1..p_5).
    // alpha of period 3 gives beta of period 6: [a0, 0, a2, 0, a1, 0].
    expect_same_chain("{type: schu, alpha: [0.3, 0.6, 0.9]}", "{type: mann, alpha: [0.3, 0, 0.9, 0, 0.6, 0]}",
                      three_circles, 8);
    expect_same_chain("{type: schu, alpha: 0.7}", "{type: mann, alpha: [0.7, 0]}", three_circles, 8);
    expect_same_chain("{type: schu, alpha: [1.4, -0.5, 0.8]}",
                      "{type: mann, alpha: [1.4, 0, 0.8, 0, -0.5, 0]}", {three_circles[0]}, 8);
}

TEST(Schu, OnAnInvolutionIsMannWithEq24InAQSystem) {
    expect_same_chain("{type: schu, alpha: [0.3+0.2q, 0.6, 0.9-0.1q]" + Q + "}",
                      "{type: mann, alpha: [0.3+0.2q, 0, 0.9-0.1q, 0, 0.6, 0]" + Q + "}", three_circles, 8);
}

TEST(Schu, GeneralDefinitionByHand) {
    // T(x, y) = (x / 2 + 1/4, y / 2): p = (1, 2), T(p) = (0.75, 1), T^2(p) = (0.625, 0.5),
    // T^3(p) = (0.5625, 0.25). At n = 2, alpha = 0.5: p' = (p + T^3(p)) / 2 = (0.78125, 1.125).
    auto t = make<Transform>("{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, 0]}");
    auto s = make<IterationScheme>("{type: schu, alpha: 0.5}");
    ASSERT_TRUE(t && s);
    ASSERT_FALSE(t->is_involution());
    double x = 1, y = 2;
    s->step(*t, fp::Points<double>{&x, &y, 1}, nullptr, 2);
    EXPECT_EQ(x, 0.78125);
    EXPECT_EQ(y, 1.125);
    // At n = 0 it is Mann: (p + T(p)) / 2 = (0.875, 1.5).
    x = 1, y = 2;
    s->step(*t, fp::Points<double>{&x, &y, 1}, nullptr, 0);
    EXPECT_EQ(x, 0.875);
    EXPECT_EQ(y, 1.5);
}

TEST(Schu, GeneralDefinitionOnBatches) {
    // n = 2: (1 - alpha) p + alpha T(T(T(p))), real and in Q_{2,1} (products by eq. (14)).
    auto t = make<Transform>(affine_map.yaml);
    ASSERT_TRUE(t);
    const Pts p = sample(affine_map, 500, 4);
    const Pts t3 = apply(*t, apply(*t, apply(*t, p)));
    Pts want = p;
    for (std::size_t i = 0; i < p.size(); ++i) {
        want.x[i] = 0.3 * p.x[i] + 0.7 * t3.x[i];
        want.y[i] = 0.3 * p.y[i] + 0.7 * t3.y[i];
    }
    expect_points(step_of("{type: schu, alpha: [0.1, 0.2, 0.7]}")(*t, p, 2), want, 1e-15, "real");
    // alpha = 0.3 + 0.2q, A = 2, B = 1: alpha (x + qy) = (0.3x + 0.2*2*y) + q(0.2x + 0.3y + 2*0.2*y).
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double dx = t3.x[i] - p.x[i], dy = t3.y[i] - p.y[i];
        want.x[i] = p.x[i] + (0.3 * dx + 0.4 * dy);
        want.y[i] = p.y[i] + (0.2 * dx + 0.7 * dy);
    }
    expect_points(step_of("{type: schu, alpha: 0.3+0.2q" + Q + "}")(*t, p, 2), want, 1e-14, "q-system");
    // n = 5 composes six times.
    const Pts t6 = apply(*t, apply(*t, apply(*t, t3)));
    for (std::size_t i = 0; i < p.size(); ++i) {
        want.x[i] = 0.5 * p.x[i] + 0.5 * t6.x[i];
        want.y[i] = 0.5 * p.y[i] + 0.5 * t6.y[i];
    }
    expect_points(step_of("{type: schu, alpha: 0.5}")(*t, p, 5), want, 1e-15, "n = 5");
}

TEST(Schu, RefusesTooManyCompositions) {
    auto t = make<Transform>(affine_map.yaml);
    auto s = make<IterationScheme>("{type: schu, alpha: 0.5}");
    ASSERT_TRUE(t && s);
    Pts p = sample(affine_map, 10, 1);
    auto run = [&](const IterationScheme& sc, std::uint64_t n) {
        sc.step(*t, fp::Points<double>{p.x.data(), p.y.data(), p.size()}, nullptr, n);
    };
    EXPECT_NO_THROW(run(*s, 999)); // 1000 compositions: the limit
    try {
        run(*s, 1000);
        ADD_FAILURE() << "step 1000 needs 1001 compositions and was not refused";
    } catch (const fp::InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("step n = 1000"), std::string::npos) << m;
        EXPECT_NE(m.find("1001"), std::string::npos) << m;
        EXPECT_NE(m.find("max_compositions = 1000"), std::string::npos) << m;
        EXPECT_NE(m.find("raise max_compositions"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    auto s3 = make<IterationScheme>("{type: schu, alpha: 0.5, max_compositions: 3}");
    EXPECT_NO_THROW(run(*s3, 2));
    EXPECT_THROW(run(*s3, 3), fp::InputError);
    // An involution never needs more than one application, whatever n.
    auto inv = make<Transform>(circle_map.yaml);
    Pts q = sample(circle_map, 10, 1), want = q;
    s3->step(*inv, fp::Points<double>{q.x.data(), q.y.data(), q.size()}, nullptr, 1000001);
    expect_points(q, want, 0, "odd n on an involution moves nothing");
    EXPECT_NO_THROW(s3->step(*inv, fp::Points<double>{q.x.data(), q.y.data(), q.size()}, nullptr, 1000000));
    // A point reflection written as an affine map is an involution too: the cheap form.
    auto refl = make<Transform>("{type: affine, matrix: [-1, 0, 0, -1], offset: [2, 4]}");
    ASSERT_TRUE(refl && refl->is_involution());
    EXPECT_NO_THROW(s3->step(*refl, fp::Points<double>{q.x.data(), q.y.data(), q.size()}, nullptr, 5000));
}

TEST(Schu, RefusalThroughTheCli) {
    const auto r = fp::test::run_cli({"eval", "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}",
                                      "--scheme", "{type: schu, max_compositions: 3}", "--steps", "5"},
                                     "1 2\n");
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("step n = 3 needs T composed 4 times, above max_compositions = 3"),
              std::string::npos)
        << r.err;
}

TEST(Schu, InTheInversionChaosGameIsMannWithEq24) {
    // The whole pipeline: the same pixels as Mann(alpha at even n, 0 at odd n).
    const std::string dir = fp::test::scratch_dir("schu-chaos-game");
    fp::test::write_file(dir + "/cfg.yaml",
                         chaos_game({"width: 96", "height: 96", "points: 200000", "chains: 256"},
                                    fp::test::three_circles("0.9")));
    auto render = [&](const std::string& iteration, const std::string& out) {
        const auto r = fp::test::run_cli({"render", "--quiet", dir + "/cfg.yaml", "-o", dir + "/" + out,
                                          "--set", "renderer.iteration=" + iteration});
        EXPECT_EQ(r.rc, 0) << r.err;
        return fp::host::read_image(dir + "/" + out).pixels;
    };
    const auto schu = render("{type: schu, alpha: [0.7, 0.4, 0.9]}", "schu.png");
    const auto mann = render("{type: mann, alpha: [0.7, 0, 0.9, 0, 0.4, 0]}", "mann.png");
    ASSERT_FALSE(schu.empty());
    EXPECT_TRUE(schu == mann);
}

// ------------------------------------------------------------------ switching, eqs. (26)-(27)

TEST(Switching, OneChildIsThatChild) {
    const std::string child =
        "{type: karakaya, alpha: [0.7, 0.9], beta: 0.7, gamma: 0.1, a: [0.1, 0.3, 0.5], b: 0.4}";
    expect_same(step_of("{type: switching, schemes: [" + child + "]}"), step_of(child), 0, "karakaya");
    const std::string qchild = "{type: cr, alpha: 0.7+0.1q, beta: [0.4, 0.2q], gamma: 0.1" + Q + "}";
    expect_same(step_of("{type: switching, schemes: [" + qchild + "]}"), step_of(qchild), 0, "cr in Q_{2,1}");
}

TEST(Switching, TwoChildrenAlternate) {
    const std::string a = "{type: cr, alpha: 0.7, beta: 0.4, gamma: 0.1}",
                      b = "{type: mann, alpha: [0.8, 0.3]}";
    const Step sw = step_of("{type: switching, schemes: [" + a + ", " + b + "]}");
    const Step sa = step_of(a), sb = step_of(b);
    for (const Map& m : maps) {
        auto t = make<Transform>(m.yaml);
        const Pts p = sample(m, 300, 2);
        for (std::uint64_t n = 0; n < 8; ++n)
            expect_points(sw(*t, p, n), (n % 2 == 0 ? sa : sb)(*t, p, n), 0, "n = " + std::to_string(n));
    }
}

TEST(Switching, PassesTheStepIndexThrough) {
    // Schu as the second of two children at n = 3 composes T four times (n + 1), not twice.
    auto t = make<Transform>(affine_map.yaml);
    const Pts p = sample(affine_map, 200, 8);
    const Step sw = step_of("{type: switching, schemes: [{type: picard}, {type: schu, alpha: 0.5}]}");
    expect_points(sw(*t, p, 3), step_of("{type: schu, alpha: 0.5}")(*t, p, 3), 0, "n = 3");
    expect_points(sw(*t, p, 2), apply(*t, p), 0, "n = 2");
}

TEST(Switching, OfQSystems) {
    // Eq. (27): one scheme, different numbers; step n uses Q_{A_{n mod m}, B_{n mod m}}.
    const std::string a = "{type: ishikawa, alpha: 1+0.1q, a: 0.1q, numbers: {type: q-system, A: -3, B: 0}}";
    const std::string b = "{type: ishikawa, alpha: 1+0.1q, a: 0.1q, numbers: {type: q-system, A: 3, B: 0}}";
    const Step sw = step_of("{type: switching, schemes: [" + a + ", " + b + "]}");
    const Step sa = step_of(a), sb = step_of(b);
    for (const Map& m : maps) {
        auto t = make<Transform>(m.yaml);
        const Pts p = sample(m, 300, 6);
        for (std::uint64_t n = 0; n < 6; ++n)
            expect_points(sw(*t, p, n), (n % 2 == 0 ? sa : sb)(*t, p, n), 0, "n = " + std::to_string(n));
    }
}

TEST(Switching, EmptyListIsRefused) {
    try {
        host().make<IterationScheme>("{type: switching, schemes: []}");
        ADD_FAILURE() << "an empty switching list was accepted";
    } catch (const fp::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("is empty"), std::string::npos) << e.what();
    }
}

// ------------------------------------------------------------------ affine

Vec2 map_point(const Transform& t, Vec2 p) {
    t.apply(fp::Points<double>{&p.x, &p.y, 1}, nullptr);
    return p;
}

TEST(Affine, HandComputedPoints) {
    // x' = a x + b y + e, y' = c x + d y + f.
    auto half = make<Transform>("{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, 0]}");
    EXPECT_EQ(map_point(*half, {1, 2}), (Vec2{0.75, 1}));
    EXPECT_EQ(map_point(*half, {-1, 0.5}), (Vec2{-0.25, 0.25}));
    auto m = make<Transform>("{type: affine, matrix: [1, 2, 3, 4], offset: [10, 20]}");
    EXPECT_EQ(map_point(*m, {1, 2}), (Vec2{15, 31}));   // (1 + 4 + 10, 3 + 8 + 20)
    EXPECT_EQ(map_point(*m, {-2, 0.5}), (Vec2{9, 16})); // (-2 + 1 + 10, -6 + 2 + 20)
    auto rot = make<Transform>("{type: affine, coefficients: [0, -1, 1, 0, 1, 0]}"); // quarter turn, then +x
    EXPECT_EQ(map_point(*rot, {2, 3}), (Vec2{-2, 2}));
    auto lin = make<Transform>("{type: affine, matrix: [2, 0, 0, -3]}"); // offset defaults to [0, 0]
    EXPECT_EQ(map_point(*lin, {1.5, 2}), (Vec2{3, -6}));
    // The float path.
    float x = 1, y = 2;
    m->apply(fp::Points<float>{&x, &y, 1}, nullptr);
    EXPECT_EQ(x, 15.f);
    EXPECT_EQ(y, 31.f);
}

TEST(Affine, MatrixWithOffsetIsTheCoefficients) {
    auto a = make<Transform>("{type: affine, matrix: [0.6, -0.3, 0.25, 0.5], offset: [0.1, -0.2]}");
    auto b = make<Transform>(affine_map.yaml);
    const Pts p = sample(affine_map, 500, 12);
    expect_points(apply(*a, p), apply(*b, p), 0, "matrix + offset against coefficients");
    // The mask: inactive points stay.
    Pts q = p;
    std::vector<unsigned char> mask(q.size());
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = i % 2;
    a->apply(fp::Points<double>{q.x.data(), q.y.data(), q.size()}, mask.data());
    const Pts all = apply(*a, p);
    for (std::size_t i = 0; i < q.size(); ++i) {
        EXPECT_EQ(q.x[i], mask[i] ? all.x[i] : p.x[i]);
        EXPECT_EQ(q.y[i], mask[i] ? all.y[i] : p.y[i]);
    }
}

TEST(Affine, Involutions) {
    EXPECT_TRUE(make<Transform>("{type: affine, matrix: [-1, 0, 0, -1], offset: [2, 4]}")->is_involution());
    EXPECT_TRUE(
        make<Transform>("{type: affine, coefficients: [1, 0, 0, -1, 0, 1]}")->is_involution()); // y -> 1 - y
    EXPECT_FALSE(make<Transform>("{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, 0]}")->is_involution());
    EXPECT_FALSE(
        make<Transform>("{type: affine, coefficients: [0, -1, 1, 0, 0, 0]}")->is_involution()); // A^2 = -I
    EXPECT_FALSE(
        make<Transform>("{type: affine, coefficients: [1, 0, 0, 1, 0.5, 0]}")->is_involution()); // a shift
    auto t = make<Transform>("{type: affine, coefficients: [1, 0, 0, -1, 0, 1]}");
    EXPECT_EQ(map_point(*t, map_point(*t, {0.3, 0.7})), (Vec2{0.3, 0.7}));
}

void expect_refused(const std::string& yaml, const std::string& message) {
    try {
        host().make<Transform>(yaml);
        ADD_FAILURE() << yaml << " was accepted";
    } catch (const fp::InputError& e) {
        EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
}

TEST(Affine, ExactlyOneForm) {
    expect_refused("{type: affine}", "give either matrix (with offset) or coefficients");
    expect_refused("{type: affine, matrix: [1, 0, 0, 1], coefficients: [1, 0, 0, 1, 0, 0]}",
                   "give either matrix (with offset) or coefficients, not both");
    expect_refused("{type: affine, coefficients: [1, 0, 0, 1, 0, 0], offset: [1, 1]}",
                   "offset goes with matrix");
    expect_refused("{type: affine, offset: [1, 1]}", "give either matrix (with offset) or coefficients");
    expect_refused("{type: affine, coefficients: [1, 0, 0, 1, 0]}", "coefficients");
    expect_refused("{type: affine, matrix: [1, 0, 0]}", "matrix");
}

TEST(Affine, SierpinskiChaosGameLandsOnTheTriangle) {
    // p -> (p + v) / 2 for the vertices v = (0, 0), (1, 0), (0.5, 1): the attractor is the
    // Sierpinski triangle. Nothing may land outside the big triangle or inside the middle
    // hole (the open triangle of the edge midpoints), and the triangle must be well covered.
    const std::string dir = fp::test::scratch_dir("sierpinski");
    fp::test::write_file(dir + "/cfg.yaml", R"(renderer:
  type: chaos-game
  width: 128
  height: 128
  view: [0, 1, 0, 1]
  points: 400000
  chains: 64
  colourer: {type: map-colour}
  maps:
    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0], colour: [1, 0, 0]}
    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0], colour: [0, 1, 0]}
    - {type: affine, matrix: [0.5, 0, 0, 0.5], offset: [0.25, 0.5], colour: [0, 0, 1]}
)");
    const auto r = fp::test::run_cli({"render", "--quiet", dir + "/cfg.yaml", "-o", dir + "/s.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const fp::Image img = fp::host::read_image(dir + "/s.png");
    ASSERT_EQ(img.width, 128);
    std::size_t lit_in = 0, in = 0, lit_out = 0, lit_hole = 0;
    const double px = 1.0 / 128, margin = 1.5 * px;
    for (int row = 0; row < img.height; ++row)
        for (int col = 0; col < img.width; ++col) {
            const double x = (col + 0.5) * px, y = 1 - (row + 0.5) * px; // pixel centre
            const std::size_t i =
                (std::size_t(row) * std::size_t(img.width) + std::size_t(col)) * std::size_t(img.channels);
            bool lit = false;
            for (int c = 0; c < 3; ++c) lit = lit || img.pixels[i + std::size_t(c)] > 0;
            // Signed distances to the big triangle's edges (positive inside) and the hole's.
            const double s5 = std::sqrt(5.0);
            const double big = std::min({y, (2 * x - y) / s5, (2 - 2 * x - y) / s5});
            const double hole = std::min({0.5 - y, (y - 2 * x + 1) / s5, (y + 2 * x - 1) / s5});
            if (big < -margin)
                lit_out += lit;
            else if (hole > margin)
                lit_hole += lit;
            else if (big > margin)
                in++, lit_in += lit;
        }
    EXPECT_EQ(lit_out, 0u) << "points outside the triangle";
    EXPECT_EQ(lit_hole, 0u) << "points in the middle hole";
    EXPECT_GT(double(lit_in), 0.3 * double(in)) << lit_in << " of " << in;
}

} // namespace
