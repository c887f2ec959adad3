// IterationScheme::program (sdk/include/fixpoint/scheme_program.hpp): the programs fp::SchemeBase
// records from a scheme's kernel, written out by hand for Mann and the S-iteration; run_program
// of them equal to step() to the bit, special values included; Schu's program changing with n
// and with the map (and none where it would need more than a program holds); Picard's, and a
// switching process's (its children's in turn).
#include "host.hpp"
#include <fixpoint/fixpoint.hpp>

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::SchemeProgram;
using Op = fp::SchemeProgram::Op;

std::shared_ptr<const fp::IterationScheme> scheme(const std::string& yaml) {
    return host().make<fp::IterationScheme>(yaml);
}
std::shared_ptr<const fp::Transform> transform(const std::string& yaml) {
    return host().make<fp::Transform>(yaml);
}

const std::string circle = "{type: inversion, shape: {type: circle, centre: [0.5, 0.2], radius: 0.7}}";
const std::string contraction = "{type: affine, coefficients: [0.5, -0.2, 0.1, 0.6, 0.25, 0]}";
const std::string reflection = "{type: affine, coefficients: [1, 0, 0, -1, 0, 1]}"; // y -> 1 - y

void expect_instr(const SchemeProgram& p, std::size_t i, Op op, int dst, int u, int v = -1) {
    ASSERT_LT(i, p.size);
    const SchemeProgram::Instr& in = p.code[i];
    EXPECT_EQ(in.op, op) << "instruction " << i;
    EXPECT_EQ(in.dst, dst) << "instruction " << i;
    EXPECT_EQ(in.u, u) << "instruction " << i;
    if (v >= 0) {
        EXPECT_EQ(in.v, v) << "instruction " << i;
    }
}

// The coefficients a lin2 instruction holds: (1 - w) I and w I over the reals.
void expect_weights(const SchemeProgram::Instr& in, double w) {
    const double want[8] = {1 - w, 0, 0, 1 - w, w, 0, 0, w};
    for (int j = 0; j < 8; ++j) EXPECT_EQ(in.k[j], want[j]) << "k[" << j << "]";
}

TEST(SchemeProgram, MannByHand) {
    // p' = (1 - alpha) p + alpha T(p): T(p) into register 1, then the combination into 0.
    const auto mann = scheme("{type: mann, alpha: 0.7}");
    const auto t = transform(circle);
    SchemeProgram p;
    ASSERT_TRUE(mann->program(*t, 0, true, p));
    ASSERT_EQ(p.size, 2u);
    EXPECT_EQ(p.regs, 2u);
    expect_instr(p, 0, Op::map, 1, 0);
    expect_instr(p, 1, Op::lin2, 0, 0, 1);
    expect_weights(p.code[1], 0.7);
    // A periodic alpha: the coefficients of step n are alpha_{n mod 2}.
    const auto periodic = scheme("{type: mann, alpha: [0.7, 0.2]}");
    ASSERT_TRUE(periodic->program(*t, 5, false, p));
    expect_weights(p.code[1], 0.2);
    ASSERT_TRUE(periodic->program(*t, 6, false, p));
    expect_weights(p.code[1], 0.7);
}

TEST(SchemeProgram, SIterationByHand) {
    // Paper 02 eq. (6): T(p) -> r1; u = (1 - beta) p + beta T(p) -> r2; T(u) -> r2;
    // p' = (1 - alpha) T(p) + alpha T(u) -> r0.
    const auto s = scheme("{type: s-iteration, alpha: 0.6, beta: 0.3}");
    SchemeProgram p;
    ASSERT_TRUE(s->program(*transform(circle), 3, true, p));
    ASSERT_EQ(p.size, 4u);
    EXPECT_EQ(p.regs, 3u);
    expect_instr(p, 0, Op::map, 1, 0);
    expect_instr(p, 1, Op::lin2, 2, 0, 1);
    expect_weights(p.code[1], 0.3);
    expect_instr(p, 2, Op::map, 2, 2);
    expect_instr(p, 3, Op::lin2, 0, 1, 2);
    expect_weights(p.code[3], 0.6);
}

// run_program of the recorded program against step(), both precisions, points with an
// infinity and a NaN among them.
template <class T>
void expect_program_is_step(const fp::IterationScheme& s, const fp::Transform& t, std::uint64_t n,
                            const std::string& what) {
    const std::size_t N = 37;
    std::vector<T> x(N), y(N);
    for (std::size_t i = 0; i < N; ++i) x[i] = T(-1.3 + 0.07 * double(i)), y[i] = T(0.9 - 0.05 * double(i));
    x[3] = std::numeric_limits<T>::infinity();
    y[7] = std::numeric_limits<T>::quiet_NaN();
    SchemeProgram p;
    ASSERT_TRUE(s.program(t, n, sizeof(T) == 8, p)) << what;
    std::vector<T> sx = x, sy = y;
    s.step(t, fp::Points<T>{sx.data(), sy.data(), N}, nullptr, n);
    fp::run_program(p, t, fp::Points<T>{x.data(), y.data(), N});
    EXPECT_EQ(std::memcmp(x.data(), sx.data(), N * sizeof(T)), 0) << what << " at n = " << n;
    EXPECT_EQ(std::memcmp(y.data(), sy.data(), N * sizeof(T)), 0) << what << " at n = " << n;
}

TEST(SchemeProgram, EveryBuiltInSchemeOnSchemeBaseIsItsProgram) {
    const std::string Q = ", numbers: {type: q-system, A: 2, B: 1}";
    const std::vector<std::string> schemes = {
        "{type: mann, alpha: [0.7, 0.2]}",
        "{type: mann, alpha: 0.3+0.2q" + Q + "}",
        "{type: ishikawa}",
        "{type: khan}",
        "{type: noor, alpha: [0.7, 0.9], a: 0.4, gamma: 0.2}",
        "{type: sp}",
        "{type: s-iteration, alpha: 0.6-0.1q, beta: 0.3" + Q + "}",
        "{type: picard-s}",
        "{type: cr}",
        "{type: karakaya, alpha: 0.3, beta: 0.2, a: 0.25, b: 0.15, gamma: 0.5}",
        "{type: suantai}",
        "{type: schu, alpha: 0.6}",
    };
    for (const auto& yaml : schemes) {
        const auto s = scheme(yaml);
        for (const auto& map : {circle, contraction})
            for (std::uint64_t n : {0, 1, 2, 5}) {
                expect_program_is_step<double>(*s, *transform(map), n, yaml + " on " + map);
                expect_program_is_step<float>(*s, *transform(map), n, yaml + " on " + map);
            }
    }
}

TEST(SchemeProgram, SchuChangesWithTheStepAndTheMap) {
    const auto schu = scheme("{type: schu, alpha: 0.6}");
    const auto inv = transform(reflection), con = transform(contraction);
    SchemeProgram p;
    // An involution: a Mann step at even n, nothing at odd n (T^{n+1} = id).
    ASSERT_TRUE(schu->program(*inv, 4, true, p));
    EXPECT_EQ(p.size, 2u);
    ASSERT_TRUE(schu->program(*inv, 5, true, p));
    EXPECT_EQ(p.size, 0u);
    // Another map: n + 1 applications of T, then the combination.
    ASSERT_TRUE(schu->program(*con, 3, true, p));
    ASSERT_EQ(p.size, 5u);
    for (std::size_t i = 0; i < 4; ++i) expect_instr(p, i, Op::map, 1, i == 0 ? 0 : 1);
    expect_instr(p, 4, Op::lin2, 0, 0, 1);
    // 15 applications and the combination fill a program; 16 do not fit.
    EXPECT_TRUE(schu->program(*con, 14, true, p));
    EXPECT_EQ(p.size, SchemeProgram::max_instrs);
    EXPECT_FALSE(schu->program(*con, 15, true, p));
    // So at n = 1 the two maps' programs differ (a renderer then takes its generic step).
    SchemeProgram a, b;
    ASSERT_TRUE(schu->program(*inv, 1, false, a));
    ASSERT_TRUE(schu->program(*con, 1, false, b));
    EXPECT_FALSE(a.same_as(b));
    ASSERT_TRUE(schu->program(*inv, 0, false, a));
    ASSERT_TRUE(schu->program(*con, 0, false, b));
    EXPECT_TRUE(a.same_as(b));
}

TEST(SchemeProgram, PicardAndSwitching) {
    SchemeProgram p;
    const auto t = transform(circle);
    ASSERT_TRUE(scheme("{type: picard}")->program(*t, 7, true, p));
    ASSERT_EQ(p.size, 1u);
    expect_instr(p, 0, Op::map, 0, 0);
    // Step n is the program of schemes[n mod m].
    const auto sw = scheme("{type: switching, schemes: [{type: mann, alpha: 0.25}, {type: picard}]}");
    ASSERT_TRUE(sw->program(*t, 4, true, p));
    ASSERT_EQ(p.size, 2u);
    expect_weights(p.code[1], 0.25);
    ASSERT_TRUE(sw->program(*t, 5, true, p));
    EXPECT_EQ(p.size, 1u);
    for (std::uint64_t n : {0, 1, 2, 3}) {
        expect_program_is_step<double>(*sw, *t, n, "switching");
        expect_program_is_step<float>(*sw, *t, n, "switching");
    }
}

} // namespace
