// The SIMD layer's promise (fixpoint/simd.hpp): the same recipe gives the same bytes on every
// instruction set the kernels dispatch to. Each recipe is rendered with dispatch pinned to
// each target this machine has (fp::simd::force_target), from the portable one-lane SCALAR
// up to the widest, and compared with the best target's image and counts.
#include "host.hpp"

#include <fixpoint/simd.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace fp::test;

namespace {

const std::string circles = "maps: [{type: inversion, shape: {type: circle, centre: [1, 0], radius: 0.65}}, "
                            "{type: inversion, shape: {type: circle, centre: [-0.5, 0.866], radius: 0.65}}, "
                            "{type: inversion, shape: {type: circle, centre: [-0.5, -0.866], radius: 0.65}}, "
                            "{type: inversion, shape: {type: circle, centre: [0, 0], radius: 0.4}}]";
const std::string frame = "type: chaos-game, width: 80, height: 80, view: [-1.2, 1.2, -1.2, 1.2], ";

// One recipe per kernel path: the fused circle step (hits only and with colour, float and
// double), the generic step (grouping, draw with rules, bookkeeping), the alias draw of an
// affine IFS with the flame colourer, Gumowski-Mira in double, inversions in polygons and
// stars, superformula and bezier sets about their centre and off it, a circle inverted about an
// off-centre point (ray exits), another iteration scheme.
const std::vector<std::string> recipes = {
    frame + "points: 200000, chains: 700, colourer: {type: density}, " + circles,
    frame + "points: 200000, chains: 300, colourer: {type: map-colour}, " + circles,
    frame + "points: 100000, precision: double, colourer: {type: density}, " + circles,
    frame + "points: 100000, precision: double, colourer: {type: flame}, " + circles,
    frame + "points: 100000, chains: 300, skip: 3, colourer: {type: flame, mode: set-colour}, " + circles,
    frame + "points: 150000, kernels: generic, colourer: {type: map-colour}, " + circles,
    frame + "points: 150000, kernels: generic, precision: double, colourer: {type: flame}, " + circles,
    "type: chaos-game, width: 64, height: 64, view: [0, 1, 0, 1], points: 200000, chains: 333, "
    "colourer: {type: flame}, maps: [{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}, "
    "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}, {type: affine, coefficients: [0.5, 0, 0, 0.5, "
    "0.25, 0.5]}]",
    "type: chaos-game, width: 64, height: 64, view: [-15, 15, -15, 15], points: 100000, chains: 1, skip: 0, "
    "start: [0, 0.5], precision: double, colourer: {type: density}, maps: [{type: gumowski-mira, alpha: 0, "
    "mu: -0.31}]",
    frame +
        "points: 100000, colourer: {type: map-colour}, maps: [{type: inversion, shape: {type: polygon, "
        "vertices: [[-0.3, -0.3], [0.4, -0.2], [0.1, 0.5]]}}, {type: inversion, shape: {type: star-polygon, "
        "points: 5, inner_radius: 0.2, outer_radius: 0.5, centre: [0.7, 0.1]}}, {type: inversion, shape: "
        "{type: circle, "
        "centre: [-0.6, 0.5], radius: 0.45}, centre: [-0.5, 0.45]}]",
    // superformula: the SDK's transcendentals, inversion about the centre (closed form) and
    // about another point of the kernel (the masked root finder), float and double.
    frame +
        "points: 60000, colourer: {type: map-colour}, maps: [{type: inversion, shape: {type: superformula, "
        "m: "
        "5, n1: 2, n2: 7, n3: 7, scale: 0.45, rotation: 0.3, centre: [0.55, 0.1]}}, {type: inversion, shape: "
        "{type: superformula, m: 3, n1: 0.8, n2: 1.5, n3: 1.5, b: 0.7, scale: 0.4, centre: [-0.5, 0.45]}, "
        "centre: [-0.47, 0.43]}, {type: inversion, shape: {type: circle, centre: [-0.2, -0.6], radius: "
        "0.4}}]",
    frame +
        "points: 40000, precision: double, colourer: {type: density}, maps: [{type: inversion, shape: {type: "
        "superformula, m: 6, n1: 3, n2: 4, n3: 9, scale: 0.45, centre: [0.4, 0.3]}, centre: [0.42, 0.27]}, "
        "{type: inversion, shape: {type: circle, centre: [-0.5, 0.4], radius: 0.4}}, {type: inversion, "
        "shape: "
        "{type: superformula, centre: [0, -0.5], scale: 0.45}}]",
    // bezier: the pieces' binary search by gathers and the root finders, about the centre and
    // about another point of the kernel, float and double.
    frame +
        "points: 60000, colourer: {type: map-colour}, maps: [{type: inversion, shape: {type: bezier, points: "
        "[[0.1, -0.1], [0.7, -0.2], [0.8, 0.2], [0.6, 0.5], [0.4, 0.8], [0.1, 0.3]]}}, {type: inversion, "
        "shape: "
        "{type: bezier, degree: 2, points: [[-0.9, 0], [-0.5, 0.9], [-0.1, 0], [-0.5, -0.9]]}, centre: "
        "[-0.45, "
        "0.1]}, {type: inversion, shape: {type: circle, centre: [0.2, -0.6], radius: 0.4}}]",
    frame +
        "points: 40000, precision: double, colourer: {type: density}, maps: [{type: inversion, shape: {type: "
        "bezier, degree: 2, points: [[-0.9, 0], [-0.5, 0.9], [-0.1, 0], [-0.5, -0.9]]}, centre: [-0.45, "
        "0.1]}, "
        "{type: inversion, shape: {type: circle, centre: [0.5, 0.4], radius: 0.4}}]",
    frame +
        "points: 100000, iteration: {type: s-iteration, alpha: 0.7, beta: 0.5}, colourer: {type: flame}, " +
        circles,
};

TEST(SimdTargets, EveryTargetGivesTheSameBytes) {
    const std::vector<std::string> targets = fp::simd::supported_targets();
    ASSERT_FALSE(targets.empty());
#if !defined(HWY_COMPILE_ONLY_STATIC) // (the sanitizer build compiles the baseline target only)
    // At least the portable one-lane target and a vector one on any machine fixpoint builds on.
    EXPECT_GE(targets.size(), 2u);
#endif
    for (const auto& r : recipes) {
        ASSERT_TRUE(fp::simd::force_target(""));
        const Render best = render("{" + r + "}", 2);
        EXPECT_GT(best.stats.drawn, 0u) << r;
        for (const auto& t : targets) {
            ASSERT_TRUE(fp::simd::force_target(t)) << t;
            EXPECT_EQ(fp::simd::active_target(), t);
            const Render other = render("{" + r + "}", t == targets.back() ? 1 : 3);
            EXPECT_TRUE(best.img.pixels == other.img.pixels) << t << ": " << r;
            EXPECT_EQ(best.stats.samples, other.stats.samples) << t << ": " << r;
            EXPECT_EQ(best.stats.drawn, other.stats.drawn) << t << ": " << r;
            EXPECT_EQ(best.stats.restarts, other.stats.restarts) << t << ": " << r;
        }
    }
    EXPECT_TRUE(fp::simd::force_target(""));
    EXPECT_EQ(fp::simd::active_target(), targets.front());
}

TEST(SimdTargets, UnknownTargetsAreRefused) {
    const std::string before = fp::simd::active_target();
    EXPECT_FALSE(fp::simd::force_target("avx9000"));
    EXPECT_EQ(fp::simd::active_target(), before);
    // Nor does a refusal undo a pin.
    const std::string last = fp::simd::supported_targets().back();
    ASSERT_TRUE(fp::simd::force_target(last));
    EXPECT_FALSE(fp::simd::force_target("avx9000"));
    EXPECT_EQ(fp::simd::active_target(), last);
    EXPECT_TRUE(fp::simd::force_target("best"));
    EXPECT_EQ(fp::simd::active_target(), fp::simd::supported_targets().front());
}

// The list is the CPU's whatever is pinned: loops that pin each target in turn, as the tests
// here do, cover every target on every pass, not the last pinned one alone.
TEST(SimdTargets, PinningKeepsTheListOfTargets) {
    const std::vector<std::string> all = fp::simd::supported_targets();
    for (const auto& t : all) {
        ASSERT_TRUE(fp::simd::force_target(t)) << t;
        EXPECT_EQ(fp::simd::active_target(), t);
        EXPECT_EQ(fp::simd::supported_targets(), all) << "pinned to " << t;
    }
    EXPECT_TRUE(fp::simd::force_target(""));
    EXPECT_EQ(fp::simd::active_target(), all.front());
}

} // namespace
