// chaos-game's fused step for circle inversions (plugins/renderers/chaos-game/kernels-inl.hpp):
// the known-kernel contract of `inversion` in a `circle`, is_picard, the fused step on every
// instruction set this machine has against the generic step's arithmetic written out per
// chain, and whole renders with `kernels: auto` and `kernels: generic` giving the same bytes.
#include "host.hpp"

#include <fixpoint/simd.hpp>

// The renderer's kernels, compiled here for every target too (the plugin keeps its own
// copies hidden), so that the test can call them directly.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "renderers/chaos-game/kernels-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "renderers/chaos-game/histogram.hpp"
#include "renderers/chaos-game/kernels-inl.hpp"

namespace fp_chaos {
HWY_EXPORT(fused_f);
HWY_EXPORT(draw_rules);
} // namespace fp_chaos

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

template <class T>
bool same_bits(T a, T b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// n circles of radius 0.35 on the unit circle, map j with weight j + 1 (above 16 maps, the
// draw reads the later maps' parameters by broadcast, not from LaneTables' repeated copies).
std::string ring_maps(int n) {
    std::string m = "maps: [";
    for (int j = 0; j < n; ++j) {
        const double a = 2 * M_PI * j / n;
        m += std::string(j ? ", " : "") + "{type: inversion, shape: {type: circle, centre: [" +
             std::to_string(std::cos(a)) + ", " + std::to_string(std::sin(a)) +
             "], radius: 0.35}, weight: " + std::to_string(j + 1) + "}";
    }
    return m + "]";
}

// The six circles of bench/circles.yaml (and ../shared/perf-reference/circles.cpp).
std::string circles_maps(const std::string& extra = "") {
    std::string m = "maps: [";
    for (int j = 0; j < 5; ++j) {
        const double a = 2 * M_PI * j / 5;
        m += "{type: inversion, shape: {type: circle, centre: [" + std::to_string(std::cos(a)) + ", " +
             std::to_string(std::sin(a)) + "], radius: 0.65}" + (j == 2 ? extra : "") + "}, ";
    }
    return m + "{type: inversion, shape: {type: circle, centre: [0, 0], radius: 0.4}}]";
}

TEST(ChaosKernel, InversionInACircleAboutItsCentreIsAKnownKernel) {
    const auto t = host().make<fp::Transform>("{type: inversion, shape: {type: circle, centre: [0.3, -0.2], "
                                              "radius: 0.65}}");
    const fp::KnownKernel k = t->kernel();
    ASSERT_EQ(k.kind, fp::KnownKernel::Kind::circle_inversion);
    EXPECT_EQ(k.cx, 0.3);
    EXPECT_EQ(k.cy, -0.2);
    EXPECT_EQ(k.r2, 0.65 * 0.65);
    // The contract: apply() and contains() give the bits of the formula, in float and double.
    const std::vector<double> px = {0.1, 2.0, -1.5, 0.31, 0.3, 1e-3, 7.25};
    const std::vector<double> py = {0.1, -0.5, 0.4, -0.19, 0.45, -0.2, -3.0};
    auto check = [&](auto zero) {
        using T = decltype(zero);
        std::vector<T> x(px.begin(), px.end()), y(py.begin(), py.end());
        std::vector<unsigned char> in(x.size());
        t->contains(fp::Points<const T>{x.data(), y.data(), x.size()}, in.data());
        const std::vector<T> x0 = x, y0 = y;
        t->apply(fp::Points<T>{x.data(), y.data(), x.size()}, nullptr);
        const T cx = T(k.cx), cy = T(k.cy), r2 = T(k.r2);
        for (std::size_t i = 0; i < x.size(); ++i) {
            const T dx = x0[i] - cx, dy = y0[i] - cy, d2 = dx * dx + dy * dy, s = r2 / d2;
            EXPECT_TRUE(same_bits(x[i], T(cx + s * dx))) << i;
            EXPECT_TRUE(same_bits(y[i], T(cy + s * dy))) << i;
            EXPECT_EQ(in[i], d2 < r2 ? 1 : 0) << i;
        }
    };
    check(0.0f);
    check(0.0);
}

TEST(ChaosKernel, OtherMapsAreOtherKernels) {
    // A centre moved inside the circle (paper 01 Fig. 4) and a square: the general formula.
    EXPECT_EQ(host()
                  .make<fp::Transform>("{type: inversion, shape: {type: circle, centre: [0, 0], radius: 1}, "
                                       "centre: [0.2, 0]}")
                  ->kernel()
                  .kind,
              fp::KnownKernel::Kind::none);
    EXPECT_EQ(
        host()
            .make<fp::Transform>("{type: inversion, shape: {type: polygon, vertices: [[-1, -1], [1, -1], "
                                 "[1, 1], [-1, 1]]}}")
            ->kernel()
            .kind,
        fp::KnownKernel::Kind::none);
    // Affine and Gumowski-Mira maps are kernels of their own kinds, with their coefficients.
    const fp::KnownKernel a =
        host().make<fp::Transform>("{type: affine, coefficients: [0.5, 0.1, 0.2, 0.5, 0.25, -1]}")->kernel();
    EXPECT_EQ(a.kind, fp::KnownKernel::Kind::affine);
    EXPECT_EQ(std::vector<double>(a.c, a.c + 6), (std::vector<double>{0.5, 0.1, 0.2, 0.5, 0.25, -1}));
    const fp::KnownKernel g =
        host().make<fp::Transform>("{type: gumowski-mira, alpha: 0.008, mu: -0.7}")->kernel();
    EXPECT_EQ(g.kind, fp::KnownKernel::Kind::gumowski_mira);
    EXPECT_EQ(std::vector<double>(g.c, g.c + 3), (std::vector<double>{0.008, -0.7, 2 * (1 - -0.7)}));
}

TEST(ChaosKernel, OnlyPicardIsPicard) {
    EXPECT_TRUE(host().make<fp::IterationScheme>("{type: picard}")->is_picard());
    // Mann with alpha = 1 is Picard for finite points but not bit for bit (0 * inf).
    EXPECT_FALSE(host().make<fp::IterationScheme>("{type: mann, alpha: 1}")->is_picard());
    EXPECT_FALSE(host().make<fp::IterationScheme>("{type: s-iteration, alpha: 0.7, beta: 0.5}")->is_picard());
}

// The generic step written out for one chain: Circle::inside, choose_rules' draw, Inversion.
uint32_t pcg_next(uint64_t& state, uint64_t inc) {
    const uint64_t old = state;
    state = old * 6364136223846793005ull + inc;
    const auto x = uint32_t(((old >> 18) ^ old) >> 27);
    const auto rot = uint32_t(old >> 59);
    return (x >> rot) | (x << ((32u - rot) & 31u));
}

// One draw of paper 01's loop (kernels-inl.hpp's draw_other): with equal weights a map other
// than the previous one p, uniformly; else Walker's alias table over all k maps.
uint32_t draw_other(uint32_t r, uint32_t p, uint32_t k, bool uniform, const uint32_t* thr,
                    const uint32_t* alias) {
    if (!uniform) {
        const uint64_t m = uint64_t(r) * k;
        const auto col = uint32_t(m >> 32);
        return uint32_t(m) < thr[col] ? col : alias[col];
    }
    if (p == k) return uint32_t((uint64_t(r) * k) >> 32);
    const uint32_t c = p + 1 + uint32_t((uint64_t(r) * (k - 1)) >> 32);
    return c >= k ? c - k : c;
}

/// The kernel tests' image: 64 x 64 bins over [-1.5, 1.5]^2, skip 1, `none` the maps' count.
void window64(fp_chaos::BookArgs<float>& b, uint32_t none) {
    b.xmin = -1.5f, b.xmax = 1.5f, b.ymin = -1.5f, b.ymax = 1.5f;
    b.scx = b.scy = 64.0f / 3.0f;
    b.W = b.H = 64, b.dummy = 64 * 64, b.skip = 1, b.none = none;
}

TEST(ChaosKernel, FusedStepIsTheGenericStep) {
    const std::vector<double> cx = {1, 0.309, -0.809, -0.809, 0.309, 0},
                              cy = {0, 0.951, 0.588, -0.588, -0.951, 0};
    const std::vector<double> r2 = {0.4225, 0.4225, 0.4225, 0.4225, 0.4225, 0.16};
    const std::vector<uint32_t> q = {100, 300, 50, 700, 1u << 30, 9};
    fp_chaos::LaneTables<float> t;
    for (std::size_t j = 0; j < cx.size(); ++j)
        t.p[0][j] = float(cx[j]), t.p[1][j] = float(cy[j]), t.p[2][j] = float(r2[j]), t.q[j] = q[j];
    t.k = uint32_t(cx.size());
    t.repeat_wide();
    t.kind = fp_chaos::LaneKind::circle;
    t.colour = fp_chaos::LaneColour::none;
    t.rules = true;
    const std::size_t k = cx.size();

    // Walker's table for the weights' draw (its values only matter as lookups here).
    for (std::size_t j = 0; j < k; ++j)
        t.thr[j] = 0x40000000u * uint32_t(j % 4), t.alias[j] = uint32_t(4 - j % 4);

    for (const bool uniform : {true, false})
        for (const std::string& target : fp::simd::supported_targets())
            for (std::size_t nb : {std::size_t(1), std::size_t(37), std::size_t(512)}) {
                SCOPED_TRACE(target);
                SCOPED_TRACE(uniform ? "equal weights" : "weights");
                t.uniform = uniform;
                ASSERT_TRUE(fp::simd::force_target(target));
                // The kernels work on whole vectors: arrays of a block's size (512).
                std::vector<float> x(512), y(512);
                std::vector<uint64_t> rs(512), ri(512);
                std::vector<uint32_t> prev(512), active(512), chosen(512, 99), restart(512, 99);
                // The bookkeeping's arrays: every chain past its skip (1), points to spare.
                std::vector<uint32_t> age(512, 5), idle(512, 3), plotf(512), idx(512), hits(64 * 64 + 1);
                std::vector<uint64_t> left(512, 1000), dep(512);
                std::vector<float> cr(512), cg(512), cb(512);
                fp::Rng g = fp::chain_stream(7, nb);
                for (std::size_t i = 0; i < nb; ++i) {
                    // Points over [-1.5, 1.5]^2: some inside one or two circles; a few NaN and exact
                    // centres (an infinite factor).
                    x[i] = float(-1.5 + 3 * fp::uniform_double(g));
                    y[i] = float(-1.5 + 3 * fp::uniform_double(g));
                    if (i % 50 == 7) x[i] = std::numeric_limits<float>::quiet_NaN();
                    if (i % 50 == 11) x[i] = 0, y[i] = 0;
                    prev[i] = uint32_t(fp::uniform_below(g, uint32_t(k + 1)));
                    active[i] = i % 13 == 5 ? 0u : 1u;
                    rs[i] = uint64_t(g()) << 32 | g();
                    ri[i] = (uint64_t(i) << 1) | 1u;
                }
                std::vector<float> ex = x, ey = y;
                std::vector<uint64_t> ers = rs;
                std::vector<uint32_t> echosen(nb), erestart(nb);
                std::size_t again = 0, direct = 0; // chains that drew again, that took the direct draw
                for (std::size_t i = 0; i < nb; ++i) {
                    std::vector<bool> ok(k);
                    uint32_t tot = 0;
                    for (std::size_t j = 0; j < k; ++j) {
                        const float dx = x[i] - float(cx[j]), dy = y[i] - float(cy[j]);
                        ok[j] = !(dx * dx + dy * dy < float(r2[j])) && prev[i] != j;
                        tot += ok[j] ? q[j] : 0u;
                    }
                    // Paper 01's loop: draw while the map is not allowed, at most rejection_draws
                    // times (an inactive chain draws once), then the direct draw among the allowed.
                    const auto draw = [&] {
                        return draw_other(pcg_next(ers[i], ri[i]), prev[i], uint32_t(k), uniform, t.thr,
                                          t.alias);
                    };
                    uint32_t c = draw();
                    again += active[i] && !ok[c];
                    for (int d = 1; active[i] && !ok[c] && d < fp_chaos::rejection_draws; ++d) c = draw();
                    bool some = true;
                    if (active[i] && !ok[c]) {
                        ++direct;
                        const uint32_t u = uint32_t((uint64_t(pcg_next(ers[i], ri[i])) * tot) >> 32);
                        uint32_t cum = 0;
                        c = 0;
                        for (std::size_t j = 0; j < k; ++j) {
                            cum += ok[j] ? q[j] : 0u;
                            c += cum <= u ? 1u : 0u;
                        }
                        some = tot != 0;
                    }
                    const bool mv = active[i] && some;
                    echosen[i] = mv ? c : uint32_t(k);
                    erestart[i] = active[i] && !some ? 1u : 0u;
                    if (mv) {
                        const float ox = float(cx[c]), oy = float(cy[c]);
                        const float dx = x[i] - ox, dy = y[i] - oy, s = float(r2[c]) / (dx * dx + dy * dy);
                        ex[i] = ox + s * dx;
                        ey[i] = oy + s * dy;
                    }
                }
                const std::vector<uint32_t> prev0 = prev, active0 = active;
                fp_chaos::FusedArgs<float> f{};
                f.tables = &t;
                f.draw = fp_chaos::DrawArgs{
                    rs.data(),      ri.data(), prev.data(), active.data(), nullptr, 0,      chosen.data(),
                    restart.data(), nb,        uint32_t(k), nullptr,       nullptr, nullptr};
                f.book = fp_chaos::BookArgs<float>{x.data(),   y.data(),    chosen.data(),  prev.data(),
                                                   age.data(), idle.data(), restart.data(), plotf.data(),
                                                   idx.data(), left.data(), active.data(),  cr.data(),
                                                   cg.data(),  cb.data(),   dep.data(),     nb};
                window64(f.book, uint32_t(k));
                f.hits = hits.data();
                fp_chaos::Counts counts;
                {
                    using namespace fp_chaos; // (static dispatch names N_<target>::fused_f)
                    counts = HWY_DYNAMIC_DISPATCH(fused_f)(f);
                }
                uint64_t plotted = 0;
                for (std::size_t i = 0; i < nb; ++i) {
                    const bool mv = echosen[i] < k;
                    // The chosen map becomes the previous one; the bad values (NaN, the centres'
                    // infinities) restart their chains (bit 1); the rest plot.
                    EXPECT_EQ(prev[i], mv ? echosen[i] : prev0[i]) << nb << " " << i;
                    const bool fin = std::isfinite(ex[i]) && std::isfinite(ey[i]);
                    EXPECT_EQ(restart[i], erestart[i] | (mv && !fin ? 2u : 0u)) << nb << " " << i;
                    EXPECT_EQ(left[i], mv && fin ? 999u : 1000u) << nb << " " << i;
                    EXPECT_EQ(active[i], active0[i]) << nb << " " << i;
                    plotted += mv && fin;
                    EXPECT_EQ(rs[i], ers[i]) << nb << " " << i;
                    EXPECT_TRUE(same_bits(x[i], ex[i])) << nb << " " << i << " " << x[i] << " " << ex[i];
                    EXPECT_TRUE(same_bits(y[i], ey[i])) << nb << " " << i << " " << y[i] << " " << ey[i];
                }
                EXPECT_EQ(counts.plotted, plotted);
                // The block of 512 takes both branches of the loop: draws again, and the direct
                // draw after rejection_draws rejections.
                if (nb == 512) {
                    EXPECT_GT(again, direct) << uniform;
                    EXPECT_GT(direct, 0u) << uniform;
                }
            }
    fp::simd::force_target("");
}

// The fused step's packing of the running colour (flame's rule, c = (c + c_j) / 2) into the
// deposit's 16-bit fields: fp::quantise_colour of the new colours, clamp included, on every
// target. The clamp is skipped only where FusedArgs::colours_in_range promises colours in
// [0, 1]: with colours in range the promise changes no bit; without it, colours outside
// [0, 1] (and NaN) are clamped.
TEST(ChaosKernel, FusedPackingClampsUnlessColoursAreInRange) {
    fp_chaos::LaneTables<float> t;
    const float cm[3][3] = {{1, 0, 0.25f}, {0, 1, 0.5f}, {0.75f, 0.125f, 1}};
    for (std::size_t j = 0; j < 3; ++j) {
        const float c[6] = {0.5f, 0, 0, 0.5f, 0.25f * float(j), 0.1f * float(j)};
        for (int i = 0; i < 6; ++i) t.p[i][j] = c[i];
        t.cr[j] = cm[j][0], t.cg[j] = cm[j][1], t.cb[j] = cm[j][2];
        // Walker's table of three equal weights: each column its own map.
        t.thr[j] = 0xffffffffu, t.alias[j] = uint32_t(j);
    }
    t.k = 3;
    t.repeat_wide();
    t.kind = fp_chaos::LaneKind::affine;
    t.colour = fp_chaos::LaneColour::average;
    t.rules = false;
    t.colours_in_range = true;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float wild[] = {1.5f, -0.25f, nan, 1e30f, -1e30f, 1.0f, 0.0f};
    for (const std::string& target : fp::simd::supported_targets())
        for (const bool in_range : {true, false}) {
            SCOPED_TRACE(target);
            SCOPED_TRACE(in_range ? "colours in [0, 1]" : "colours outside [0, 1]");
            ASSERT_TRUE(fp::simd::force_target(target));
            const std::size_t nb = 37;
            std::vector<float> x(512), y(512), cr(512), cg(512), cb(512);
            std::vector<uint64_t> rs(512), ri(512), left(512, 1000), dep(512);
            std::vector<uint32_t> prev(512, 3), active(512), chosen(512), restart(512);
            std::vector<uint32_t> age(512, 5), idle(512), plotf(512), idx(512), hits(64 * 64 + 1);
            fp::Rng g = fp::chain_stream(11, nb);
            for (std::size_t i = 0; i < nb; ++i) {
                x[i] = float(fp::uniform_double(g)), y[i] = float(fp::uniform_double(g));
                active[i] = 1;
                rs[i] = uint64_t(g()) << 32 | g();
                ri[i] = (uint64_t(i) << 1) | 1u;
                cr[i] = float(fp::uniform_double(g)), cg[i] = float(i) / float(nb), cb[i] = 1.0f;
                if (!in_range) cr[i] = wild[i % 7], cb[i] = wild[(i + 3) % 7];
            }
            const std::vector<float> cr0 = cr, cg0 = cg, cb0 = cb;
            // The packed deposits of one step from these states, with and without the promise.
            const auto step = [&](bool promise, std::vector<uint32_t>& map) {
                std::vector<float> sx = x, sy = y, sr = cr0, sg = cg0, sb = cb0;
                std::vector<uint64_t> srs = rs, sleft = left, sdep(512);
                std::vector<uint32_t> sprev = prev, sactive = active, sage = age, sidle = idle;
                fp_chaos::FusedArgs<float> f{};
                f.tables = &t;
                f.draw = fp_chaos::DrawArgs{
                    srs.data(),     ri.data(), sprev.data(), sactive.data(), nullptr, 0,      chosen.data(),
                    restart.data(), nb,        3u,           nullptr,        nullptr, nullptr};
                f.book = fp_chaos::BookArgs<float>{sx.data(),   sy.data(),    chosen.data(),  sprev.data(),
                                                   sage.data(), sidle.data(), restart.data(), plotf.data(),
                                                   idx.data(),  sleft.data(), sactive.data(), sr.data(),
                                                   sg.data(),   sb.data(),    sdep.data(),    nb};
                window64(f.book, 3);
                f.hits = hits.data();
                f.colours_in_range = promise;
                {
                    using namespace fp_chaos; // (static dispatch names N_<target>::fused_f)
                    HWY_DYNAMIC_DISPATCH(fused_f)(f);
                }
                map = sprev;
                return sdep;
            };
            std::vector<uint32_t> map, map2;
            const std::vector<uint64_t> dep_plain = step(false, map);
            for (std::size_t i = 0; i < nb; ++i) {
                ASSERT_LT(map[i], 3u) << i;
                const float* c = cm[map[i]];
                const uint64_t want = 1u | uint64_t(fp::quantise_colour((cr0[i] + c[0]) * 0.5f)) << 16 |
                                      uint64_t(fp::quantise_colour((cg0[i] + c[1]) * 0.5f)) << 32 |
                                      uint64_t(fp::quantise_colour((cb0[i] + c[2]) * 0.5f)) << 48;
                EXPECT_EQ(dep_plain[i], want) << i << " " << cr0[i] << " " << cb0[i];
            }
            if (in_range) {
                // The promise kept: the clamp skipped, the same bits.
                const std::vector<uint64_t> dep_fast = step(true, map2);
                EXPECT_EQ(map2, map);
                for (std::size_t i = 0; i < nb; ++i) EXPECT_EQ(dep_fast[i], dep_plain[i]) << i;
            }
        }
    fp::simd::force_target("");
}

// Paper 01's loop gives each allowed map its share: 4 maps of weights 1, 2, 3, 4 (or all
// equal), every chain's previous map 0 and its point inside map 2's set, so maps 1 and 3 are
// allowed, with probabilities 2/6 and 4/6 (1/2 and 1/2). 400 draws of 512 chains (the generic
// step's draw_rules, on every target): each share within 4 standard deviations (0.0042 at
// p = 1/3), never a map not allowed; and with every map but the previous one holding the point,
// every chain restarts.
TEST(ChaosKernel, RulesDrawGivesEachAllowedMapItsShare) {
    constexpr std::size_t B = 512, k = 4;
    for (const bool uniform : {false, true}) {
        const std::vector<double> w =
            uniform ? std::vector<double>{1, 1, 1, 1} : std::vector<double>{1, 2, 3, 4};
        // Integer weights and Walker's table, as the renderer makes them.
        std::vector<uint32_t> q(k), thr, alias;
        for (std::size_t j = 0; j < k; ++j) q[j] = uint32_t(w[j] / 10 * double(1u << 31));
        fp_chaos::walker_table(w, thr, alias);
        for (const std::string& target : fp::simd::supported_targets()) {
            SCOPED_TRACE(target);
            SCOPED_TRACE(uniform ? "equal weights" : "weights 1, 2, 3, 4");
            ASSERT_TRUE(fp::simd::force_target(target));
            std::vector<uint64_t> rs(B), ri(B);
            for (std::size_t i = 0; i < B; ++i) rs[i] = fp::mix64(i + 1), ri[i] = (uint64_t(i) << 1) | 1u;
            std::vector<uint32_t> prev(B, 0), active(B, 1), chosen(B), restart(B);
            std::vector<unsigned char> inside(k * B, 0);
            std::fill(inside.begin() + 2 * B, inside.begin() + 3 * B, 1);
            fp_chaos::DrawArgs a{
                rs.data(),     ri.data(),      prev.data(), active.data(), inside.data(), B,
                chosen.data(), restart.data(), B,           uint32_t(k),   q.data(),      thr.data(),
                alias.data(),  uniform};
            std::vector<std::size_t> count(k + 1, 0);
            constexpr int rounds = 400;
            for (int r = 0; r < rounds; ++r) {
                {
                    using namespace fp_chaos;
                    HWY_DYNAMIC_DISPATCH(draw_rules)(a);
                }
                for (std::size_t i = 0; i < B; ++i) {
                    ++count[chosen[i]];
                    EXPECT_EQ(restart[i], 0u);
                }
            }
            const double n = double(rounds * B), p1 = uniform ? 0.5 : 1.0 / 3;
            EXPECT_EQ(count[0] + count[2] + count[k], 0u);
            EXPECT_NEAR(double(count[1]) / n, p1, 4 * std::sqrt(p1 * (1 - p1) / n));
            EXPECT_NEAR(double(count[3]) / n, 1 - p1, 4 * std::sqrt(p1 * (1 - p1) / n));
            // No allowed map: maps 1 and 3 hold the point too.
            std::fill(inside.begin() + B, inside.end(), 1);
            {
                using namespace fp_chaos;
                HWY_DYNAMIC_DISPATCH(draw_rules)(a);
            }
            EXPECT_EQ(std::count(chosen.begin(), chosen.end(), uint32_t(k)), std::ptrdiff_t(B));
            EXPECT_EQ(std::count(restart.begin(), restart.end(), 1u), std::ptrdiff_t(B));
        }
    }
    fp::simd::force_target("");
}

// Each recipe rendered with the fused path allowed (auto) and forbidden (generic), on 1, 2 and
// 3 threads (other splits of the chains into blocks): the same pixels and the same counts.
void expect_fused_is_generic(const std::vector<std::string>& recipes) {
    for (const auto& r : recipes) {
        const Render a = render("{" + r + "}", 1);
        const Render b = render("{" + r + ", kernels: generic}", 1);
        const Render c = render("{" + r + "}", 2);
        const Render d = render("{" + r + "}", 3);
        ASSERT_EQ(a.img.pixels.size(), b.img.pixels.size());
        EXPECT_TRUE(a.img.pixels == b.img.pixels) << r;
        EXPECT_TRUE(a.img.pixels == c.img.pixels) << r;
        EXPECT_TRUE(a.img.pixels == d.img.pixels) << r;
        EXPECT_EQ(a.stats.samples, b.stats.samples) << r;
        EXPECT_EQ(a.stats.samples, d.stats.samples) << r;
        EXPECT_EQ(a.stats.drawn, b.stats.drawn) << r;
        EXPECT_EQ(a.stats.restarts, b.stats.restarts) << r;
        EXPECT_EQ(a.stats.bad_values, b.stats.bad_values) << r;
        EXPECT_GT(a.stats.drawn, 0u) << r;
    }
}

// Recipes of every fused path: the same as the generic step.
TEST(ChaosKernel, FusedAndGenericRendersAreIdentical) {
    const std::string bench = "type: chaos-game, width: 96, height: 96, view: [-0.8, 0.8, -0.8, 0.8], ";
    const std::vector<std::string> recipes = {
        // bench/circles.yaml, small: hits only, the default 4096 chains.
        bench + "points: 300000, colourer: {type: density}, " + circles_maps(),
        // Weights and colours per map, a colour per point; 100 chains (a partial vector).
        bench + "points: 200000, chains: 100, seed: 9, colourer: {type: map-colour}, " +
            circles_maps(", weight: 3, colour: [1, 0, 0]"),
        // The flame colourer (running colour), skip 0, a fixed start point.
        bench + "points: 200000, chains: 300, skip: 0, start: [0.05, 0.02], colourer: {type: flame}, " +
            circles_maps(),
        // Two circles that overlap widely: chains restart often (no allowed map); skip 1.
        "type: chaos-game, width: 64, height: 64, view: [-1.5, 2, -1.5, 1.5], points: 200000, chains: 500, "
        "skip: 1, colourer: {type: density}, maps: [{type: inversion, shape: {type: circle, centre: [0, 0], "
        "radius: 1}}, {type: inversion, shape: {type: circle, centre: [0.5, 0], radius: 1}}]",
        // Hits only with few points per chain (50 or 51) and a skip of 3: the fused path's steady
        // runs end one step before the first chain would run out, then single steps finish.
        bench + "points: 5003, chains: 100, skip: 3, colourer: {type: density}, " + circles_maps(),
        // 20 circles with unequal weights: the draw beyond 16 maps, in float and in double.
        "type: chaos-game, width: 64, height: 64, view: [-1.4, 1.4, -1.4, 1.4], points: 100000, chains: 300, "
        "colourer: {type: map-colour}, " +
            ring_maps(20),
        "type: chaos-game, width: 64, height: 64, view: [-1.4, 1.4, -1.4, 1.4], points: 100000, chains: 300, "
        "precision: double, colourer: {type: density}, " +
            ring_maps(20),
        // The same with colour (steady runs carry the colours too), and with the flame colourer
        // on an expanding map beside a contracting one: steady runs ended by restarts.
        bench + "points: 5003, chains: 100, skip: 3, colourer: {type: map-colour}, " + circles_maps(),
        "type: chaos-game, width: 64, height: 64, view: [-2, 2, -2, 2], points: 100000, chains: 100, skip: "
        "2, colourer: {type: flame}, maps: [{type: affine, coefficients: [1.5, 0.2, -0.1, 1.4, 0.01, 0]}, "
        "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.3, 0.1], weight: 4}]",
        // Hits only, skip 0, 700 chains (a block of 512 and a partial one; on 2 threads blocks of
        // 128 at the end).
        bench + "points: 200000, chains: 700, skip: 0, seed: 4, colourer: {type: density}, " + circles_maps(),
        // Double chains, hits only and with colour: the same either way.
        bench + "points: 100000, precision: double, colourer: {type: density}, " + circles_maps(),
        bench + "points: 100000, chains: 300, precision: double, colourer: {type: map-colour}, " +
            circles_maps(),
        // Few chains (the lean path): three, and two with many restarts (overlapping circles).
        bench + "points: 60000, chains: 3, skip: 2, colourer: {type: density}, " + circles_maps(),
        "type: chaos-game, width: 64, height: 64, view: [-1.5, 2, -1.5, 1.5], points: 30000, chains: 2, "
        "skip: 1, colourer: {type: density}, maps: [{type: inversion, shape: {type: circle, centre: [0, 0], "
        "radius: 1}}, {type: inversion, shape: {type: circle, centre: [0.5, 0], radius: 1}}]",
        // Four bins of 75000 points each with colour: the workers' 32-bit bins spill into
        // 64 bits (the fused step lists them during its pass, the generic one at once).
        "type: chaos-game, width: 2, height: 2, view: [0, 1, 0, 1], points: 300000, chains: 600, "
        "colourer: {type: map-colour}, maps: [{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}, "
        "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}, {type: affine, coefficients: [0.5, 0, 0, "
        "0.5, 0.25, 0.5]}]",
        // Two bins, about 100000 points of each map in each: the tallies' 16-bit counters of
        // map-colour spill (listed by the fused step, and at once in the deposits at a block's
        // end).
        "type: chaos-game, width: 2, height: 1, view: [0, 1, 0, 1], points: 600000, chains: 600, "
        "colourer: {type: map-colour}, maps: [{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}, "
        "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}, {type: affine, coefficients: [0.5, 0, 0, "
        "0.5, 0.25, 0.5]}]",
        // Affine maps (Walker's alias table) with both colour rules, and a single orbit of a
        // Gumowski-Mira map in double and float (the narrow lean path), one with few points.
        "type: chaos-game, width: 64, height: 64, view: [0, 1, 0, 1], points: 100000, chains: 333, "
        "colourer: {type: flame}, maps: [{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}, "
        "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0], weight: 2}, {type: affine, coefficients: "
        "[0.5, 0, 0, 0.5, 0.25, 0.5]}]",
        "type: chaos-game, width: 64, height: 64, view: [0, 1, 0, 1], points: 100000, chains: 40, "
        "colourer: {type: map-colour}, maps: [{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}, "
        "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}, {type: affine, coefficients: [0.5, 0, 0, "
        "0.5, 0.25, 0.5]}]",
        "type: chaos-game, width: 64, height: 64, view: [-15, 15, -15, 15], points: 200000, chains: 1, skip: "
        "0, "
        "start: [0, 0.5], precision: double, colourer: {type: density}, maps: [{type: gumowski-mira, mu: "
        "-0.31}]",
        "type: chaos-game, width: 64, height: 64, view: [-15, 15, -15, 15], points: 200000, chains: 1, skip: "
        "0, "
        "start: [0, 0.5], colourer: {type: density}, maps: [{type: gumowski-mira, mu: -0.31}]",
        // The single orbit of one map (orbit_run_t): Gumowski-Mira without damping (alpha = 0,
        // the step that skips the zero term) in double and float, and an expanding affine map
        // whose orbit overflows and restarts again and again.
        "type: chaos-game, width: 64, height: 64, view: [-15, 15, -15, 15], points: 300000, chains: 1, skip: "
        "4, start: [0.1, 0.5], precision: double, colourer: {type: density}, maps: [{type: gumowski-mira, "
        "alpha: 0, mu: -0.31}]",
        "type: chaos-game, width: 64, height: 64, view: [-15, 15, -15, 15], points: 300000, chains: 1, skip: "
        "0, start: [0.1, 0.5], colourer: {type: density}, maps: [{type: gumowski-mira, alpha: 0, mu: -0.31}]",
        "type: chaos-game, width: 64, height: 64, view: [-2, 2, -2, 2], points: 100000, chains: 1, skip: 2, "
        "colourer: {type: density}, maps: [{type: affine, coefficients: [1.5, 0.2, -0.1, 1.4, 0.01, 0]}]",
        // The same map on 100 chains (the whole fused step, steady runs ended by restarts: the
        // streams, left alone during a run of one map, jump ahead at its end) and on 3.
        "type: chaos-game, width: 64, height: 64, view: [-2, 2, -2, 2], points: 100000, chains: 100, skip: "
        "2, colourer: {type: density}, maps: [{type: affine, coefficients: [1.5, 0.2, -0.1, 1.4, 0.01, 0]}]",
        "type: chaos-game, width: 64, height: 64, view: [-2, 2, -2, 2], points: 100000, chains: 3, skip: 0, "
        "precision: double, colourer: {type: density}, maps: [{type: affine, coefficients: [1.5, 0.2, -0.1, "
        "1.4, 0.01, 0]}]",
        "type: chaos-game, width: 64, height: 64, view: [-15, 15, -15, 15], points: 1000, chains: 2, skip: "
        "5, "
        "colourer: {type: centroid-distance}, maps: [{type: gumowski-mira, mu: -0.31}, {type: gumowski-mira, "
        "alpha: 0.008, mu: -0.7}]",
    };
    expect_fused_is_generic(recipes);
    // The overflowing orbit restarts (bad values), in the orbit path as in the generic one.
    for (size_t i = 4; i >= 2; --i)
        EXPECT_GT(render("{" + recipes[recipes.size() - i] + "}", 1).stats.bad_values, 40u);
    // The restarting recipe does restart (so the comparison covers restarts).
    EXPECT_GT(render("{" + recipes[3] + "}", 1).stats.restarts, 0u);
    // Every point of the few-points recipe is plotted, exactly.
    EXPECT_EQ(render("{" + recipes[4] + "}", 1).stats.samples, 5003u);
}

// Paper 01's colouring by set (flame's set-colour: the pixel rule last, the map rule) on the
// fused step, the renderer writing each bin's last colour after every step: the same pixels
// and counts as the generic step, which writes them from its own deposits. Circles with the
// rules (6 maps: the bins are tallies), with skip 3 and few points a chain (the chains' colours
// during their skip, which the generic path keeps and the fused one sets, and the ends of
// steady runs must not show); 20 circles (no tallies); affine maps in double (the alias draw);
// the S-iteration's program.
TEST(ChaosKernel, FusedSetColourIsGeneric) {
    const std::string bench = "type: chaos-game, width: 96, height: 96, view: [-0.8, 0.8, -0.8, 0.8], ";
    const std::string small = "type: chaos-game, width: 64, height: 64, ";
    const std::string set_colour = "colourer: {type: flame, mode: set-colour}, ";
    const std::string affine = "maps: [{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}, "
                               "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0], weight: 2}, "
                               "{type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, 0.5]}]";
    expect_fused_is_generic({
        bench + "points: 120000, chains: 300, skip: 3, seed: 5, " + set_colour +
            circles_maps(", colour: [0.2, 0.7, 0.9]"),
        bench + "points: 5003, chains: 100, skip: 3, " + set_colour + circles_maps(),
        small + "view: [-1.4, 1.4, -1.4, 1.4], points: 100000, chains: 300, " + set_colour + ring_maps(20),
        small + "view: [0, 1, 0, 1], points: 100000, chains: 333, precision: double, " + set_colour + affine,
        // Another scheme's program in the fused step.
        bench + "points: 100000, iteration: {type: s-iteration, alpha: 0.7, beta: 0.5}, " + set_colour +
            circles_maps(),
    });
}

// Schemes other than Picard in the fused step (IterationScheme::program, run by
// kernels-inl.hpp's program_lanes): the same pixels and counts as the generic step, on 1, 2
// and 3 threads. Two-, three- and four-instruction programs (lin2 and lin3), coefficients that
// change with n, q-system numbers, float and double, hits only and colour, affine and
// Gumowski-Mira maps, few chains; and Schu on a reflection beside a contraction, whose two
// programs agree at even n only: the render changes path at every step (a steady run ended
// early, the lagged deposits made), and on the contraction from n = 15 has no program at all.
TEST(ChaosKernel, FusedSchemesAreTheGenericStep) {
    const std::string bench = "type: chaos-game, width: 96, height: 96, view: [-0.8, 0.8, -0.8, 0.8], ";
    const std::string Q = ", numbers: {type: q-system, A: 2, B: 1}";
    const std::vector<std::string> recipes = {
        bench + "points: 300000, iteration: {type: mann, alpha: 0.7}, colourer: {type: density}, " +
            circles_maps(),
        bench +
            "points: 200000, chains: 100, iteration: {type: s-iteration, alpha: 0.6, beta: [0.3, 0.5]}, "
            "colourer: {type: map-colour}, " +
            circles_maps(", weight: 3, colour: [1, 0, 0]"),
        bench +
            "points: 100000, chains: 300, precision: double, iteration: {type: karakaya, alpha: 0.3, beta: "
            "0.2, a: 0.25, b: 0.15, gamma: 0.5}, colourer: {type: flame}, " +
            circles_maps(),
        bench +
            "points: 100000, skip: 3, iteration: {type: noor, alpha: [0.7, 0.9, 1.1], a: 0.4, gamma: 0.2}, "
            "colourer: {type: density}, " +
            circles_maps(),
        bench + "points: 100000, precision: double, iteration: {type: mann, alpha: 0.3+0.2q" + Q +
            "}, colourer: {type: density}, " + circles_maps(),
        bench +
            "points: 100000, iteration: {type: switching, schemes: [{type: ishikawa, alpha: 1+0.1q, a: "
            "0.1q, numbers: {type: q-system, A: -3, B: 0}}, {type: ishikawa, alpha: 1+0.1q, a: 0.1q, "
            "numbers: {type: q-system, A: 3, B: 0}}]}, colourer: {type: map-colour}, " +
            circles_maps(),
        bench + "points: 60000, chains: 3, skip: 2, iteration: {type: cr}, colourer: {type: density}, " +
            circles_maps(),
        "type: chaos-game, width: 64, height: 64, view: [0, 1, 0, 1], points: 100000, chains: 333, "
        "iteration: {type: sp, alpha: 0.8}, colourer: {type: flame}, maps: [{type: affine, coefficients: "
        "[0.5, "
        "0, 0, 0.5, 0, 0]}, {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0], weight: 2}, {type: "
        "affine, "
        "coefficients: [0.5, 0, 0, 0.5, 0.25, 0.5]}]",
        "type: chaos-game, width: 64, height: 64, view: [-15, 15, -15, 15], points: 100000, chains: 1, skip: "
        "0, start: [0, 0.5], precision: double, iteration: {type: mann, alpha: 0.9}, colourer: {type: "
        "density}, maps: [{type: gumowski-mira, mu: -0.31}]",
        "type: chaos-game, width: 64, height: 64, view: [-1, 2, -1, 2], points: 60000, chains: 200, skip: 2, "
        "iteration: {type: schu, alpha: 0.6, max_compositions: 1000}, colourer: {type: map-colour}, maps: "
        "[{type: affine, coefficients: [1, 0, 0, -1, 0, 1]}, {type: affine, coefficients: [0.5, -0.2, 0.1, "
        "0.6, 0.25, 0]}]",
        // The same in one bin, with about 150000 points of each map: the tallies' counters spill
        // in the generic steps' deposits too.
        "type: chaos-game, width: 1, height: 1, view: [-1, 2, -1, 2], points: 400000, chains: 500, skip: 2, "
        "iteration: {type: schu, alpha: 0.6, max_compositions: 1000}, colourer: {type: map-colour}, maps: "
        "[{type: affine, coefficients: [1, 0, 0, -1, 0, 1]}, {type: affine, coefficients: [0.5, -0.2, 0.1, "
        "0.6, 0.25, 0]}]",
    };
    expect_fused_is_generic(recipes);
}

// The single undamped orbit's shortcut (y + 0 = y: the damping term skipped) holds while the
// term alpha (1 - 0.05 y^2) y is finite; beyond |y| = 6e154, 0.05 y^2 overflows and 0 times
// infinity makes the point NaN. Mostly f(x') overflows there too, but with mu = 100 and
// x = -y / 100, f(x) = mu x + ... cancels y: x' = y + f(x) is finite; only the term makes it NaN.
// Started there, every step must be a bad value, in the orbit path as in the generic step.
TEST(ChaosKernel, SingleOrbitKeepsTheDampingTermsOverflow) {
    const std::string r = "{type: chaos-game, width: 32, height: 32, view: [-15, 15, -15, 15], points: 2000, "
                          "chains: 1, skip: 0, start: [7e152, -7e154], precision: double, colourer: "
                          "{type: density}, maps: [{type: gumowski-mira, alpha: 0, mu: 100}]";
    const Render fused = render(r + "}", 1), generic = render(r + ", kernels: generic}", 1);
    EXPECT_EQ(generic.stats.drawn, 0u);
    EXPECT_EQ(generic.stats.samples, 0u);
    EXPECT_GT(generic.stats.bad_values, 100u);
    EXPECT_EQ(fused.stats.bad_values, generic.stats.bad_values);
    EXPECT_EQ(fused.stats.restarts, generic.stats.restarts);
    EXPECT_EQ(fused.stats.samples, generic.stats.samples);
}

// The histograms' buffers come zeroed without a memset (HugeBuf: a fresh mapping on Linux;
// assign_huge: value-initialised), 2 MiB aligned and writable to their last element; a
// round's writes never show in the buffer the next alloc gives. (Whether memory freed by
// the allocator would come back dirty depends on the allocator: this checks the contract,
// not that a missing memset would show.)
TEST(ChaosKernel, HistogramBuffersComeZeroed) {
    const auto poll = [] {};
    fp_chaos::HugeBuf<fp_chaos::Cnt4> bins;
    const size_t sizes[] = {1,        (size_t(2) << 20) / sizeof(fp_chaos::Cnt4) + 3,
                            1u << 18, 1u << 18,
                            1u << 18, 1u << 18,
                            1u << 18, 1u << 18};
    for (size_t n : sizes) {
        bins.alloc(n, poll);
        ASSERT_NE(bins.get(), nullptr);
        EXPECT_EQ(reinterpret_cast<uintptr_t>(bins.get()) % (size_t(2) << 20), 0u) << n;
        size_t nonzero = 0;
        for (size_t i = 0; i < n; ++i)
            nonzero += (bins.get()[i][0] | bins.get()[i][1] | bins.get()[i][2] | bins.get()[i][3]) != 0;
        EXPECT_EQ(nonzero, 0u) << n;
        for (size_t i = 0; i < n; ++i) bins.get()[i] = fp_chaos::Cnt4{1, 2, 3, 4};
    }
    std::vector<fp::HistBin> total(7, fp::HistBin{1, 2, 3, 4});
    fp_chaos::assign_huge(total, 100000, poll);
    ASSERT_EQ(total.size(), 100000u);
    size_t nonzero = 0;
    for (const fp::HistBin& b : total) nonzero += (b.hits | b.r | b.g | b.b) != 0;
    EXPECT_EQ(nonzero, 0u);
}

} // namespace
