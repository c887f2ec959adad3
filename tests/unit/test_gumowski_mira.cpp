// Unit tests of the Gumowski-Mira map (paper 03, eq. (1)) and of the centroid-distance
// colourer (paper 03, Fig. 6):
//     f(x) = mu x + 2 (1 - mu) x^2 / (1 + x^2),
//     x' = y + alpha (1 - 0.05 y^2) y + f(x),   y' = -x + f(x').
// Orbits computed by hand (exact fractions where they stay short), the alpha term, the float
// path, the mask; the colourer's centroid and its colours at the centre and the rim.
#include "host.hpp"

#include <fixpoint/host/core/host.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

using fp::Colourer;
using fp::Transform;
using fp::Vec2;

std::shared_ptr<const Transform> gm(const std::string& params) {
    const std::string yaml = "{type: gumowski-mira, " + params + "}";
    return make<Transform>(yaml);
}

// This file's tolerance where a test names none.
using fp::test::expect_point;
void expect_point(Vec2 got, Vec2 want) { expect_point(got, want, 1e-15); }

// ------------------------------------------------------------------ the map

TEST(GumowskiMira, Defaults) {
    // alpha = 0, mu = -0.31: f(1) = -0.31 + 2.62 / 2 = 1, so from (1, 0):
    //   x1 = 0 + f(1) = 1,   y1 = -1 + f(1) = 0: (1, 0) is a fixed point of GM(0, -0.31)
    //   (f(x) = x  <=>  mu + 2 (1 - mu) x / (1 + x^2) = 1  <=>  x = 1, for any mu != 1).
    auto t = host().make<Transform>("{type: gumowski-mira}");
    ASSERT_TRUE(t);
    expect_point(apply(*t, {1, 0}), {1, 0});
    expect_point(apply(*gm("alpha: 0, mu: -0.31"), {1, 0}, 10), {1, 0});
}

TEST(GumowskiMira, Fig1OrbitByHand) {
    // GM(0, -0.15) from the paper's start (0, 0.5). 2 (1 - mu) = 2.3 = 23/10.
    auto t = gm("alpha: 0, mu: -0.15");
    // Step 1: f(0) = 0, so x1 = y0 + f(x0) = 1/2.
    //   f(1/2) = -0.15 * 0.5 + 2.3 * (1/4) / (5/4) = -3/40 + 23/50 = 77/200 = 0.385,
    //   y1 = -x0 + f(x1) = 0.385.
    expect_point(apply(*t, {0, 0.5}), {0.5, 0.385});
    // Step 2: x2 = y1 + f(x1) = 0.385 + 0.385 = 0.77 = 77/100.
    //   f(0.77) = -0.1155 + 2.3 * 0.5929 / 1.5929 = -231/2000 + 136367/159290,
    //   y2 = -1/2 + f(0.77) = 7664801/31858000 = 0.24059266118400402...
    expect_point(apply(*t, {0, 0.5}, 2), {0.77, 7664801.0 / 31858000.0});
    // Step 3: y2 = -x1 + f(x2) gives f(x2) = y2 + 1/2, so x3 = y2 + f(x2) = 2 y2 + 1/2
    //   = 7664801/15929000 + 7964500/15929000 = 15629301/15929000 = 0.98118532236800803...;
    //   y3 = -0.77 + f(x3) = 0.21098181362467824... (exact rational arithmetic, rounded).
    expect_point(apply(*t, {0, 0.5}, 3), {15629301.0 / 15929000.0, 0.21098181362467824}, 1e-14);
}

TEST(GumowskiMira, AlphaTerm) {
    // GM(0.1, -0.31) from (0, 0.5): the term alpha (1 - 0.05 y^2) y = 0.1 * (1 - 0.0125) * 0.5
    //   = 0.1 * 0.9875 * 0.5 = 0.049375, f(0) = 0, so x1 = 0.5 + 0.049375 = 0.549375 = 879/1600.
    //   x1^2 = 0.301812890625, f(x1) = -0.31 * 0.549375 + 2.62 * 0.301812890625 / 1.301812890625
    //   = -0.17030625 + 0.60741... = 233079972591/533222560000 = y1 (x0 = 0).
    auto t = gm("alpha: 0.1, mu: -0.31");
    expect_point(apply(*t, {0, 0.5}), {0.549375, 233079972591.0 / 533222560000.0});
    // Two and three steps, from exact rational arithmetic (Python fractions):
    expect_point(apply(*t, {0, 0.5}, 2), {0.9175254499612415, 0.36371156008969846}, 1e-14);
    expect_point(apply(*t, {0, 0.5}, 3), {1.3129287062712434, 0.33356874437460843}, 1e-14);
    // y = 0 kills the alpha term: the same image as with alpha = 0.
    expect_point(apply(*t, {0.7, 0}), apply(*gm("alpha: 0, mu: -0.31"), {0.7, 0}));
    // sigma = 0.05: at y^2 = 20 the alpha term vanishes whatever alpha is.
    const double y = std::sqrt(20.0);
    expect_point(apply(*gm("alpha: 0.3, mu: -0.5"), {0.2, y}), apply(*gm("alpha: 0, mu: -0.5"), {0.2, y}),
                 1e-13);
}

TEST(GumowskiMira, FloatCloseToDouble) {
    auto t = gm("alpha: 0.008, mu: -0.7509");
    std::vector<double> xd, yd;
    std::vector<float> xf, yf;
    for (int i = 0; i < 400; ++i) {
        const double x = -10 + 0.05 * i, y = 7 - 0.035 * i;
        xd.push_back(x), yd.push_back(y), xf.push_back(float(x)), yf.push_back(float(y));
    }
    t->apply(fp::Points<double>{xd.data(), yd.data(), xd.size()}, nullptr);
    t->apply(fp::Points<float>{xf.data(), yf.data(), xf.size()}, nullptr);
    for (std::size_t i = 0; i < xd.size(); ++i) {
        const double sc = 1 + std::fabs(xd[i]) + std::fabs(yd[i]);
        EXPECT_NEAR(xf[i], xd[i], 1e-5 * sc) << i;
        EXPECT_NEAR(yf[i], yd[i], 1e-5 * sc) << i;
    }
}

TEST(GumowskiMira, MaskAndBatch) {
    auto t = gm("alpha: 0, mu: -0.15");
    std::vector<double> x = {0, 1, 2, 3}, y = {0.5, 0.5, 0.5, 0.5};
    const unsigned char mask[] = {1, 0, 1, 0};
    t->apply(fp::Points<double>{x.data(), y.data(), x.size()}, mask);
    expect_point({x[0], y[0]}, {0.5, 0.385});
    expect_point({x[1], y[1]}, {1, 0.5});
    expect_point({x[2], y[2]}, apply(*t, {2, 0.5}));
    expect_point({x[3], y[3]}, {3, 0.5});
}

// ------------------------------------------------------------------ centroid-distance

std::shared_ptr<const Colourer> colourer(const std::string& params) {
    const std::string yaml = "{type: centroid-distance, " + params + "}";
    auto c = host().make<Colourer>(yaml);
    EXPECT_TRUE(c) << yaml;
    return c;
}

std::vector<float> resolve(const Colourer& c, const fp::Histogram& h, fp::Rgb bg = {0.1f, 0.2f, 0.3f}) {
    std::vector<float> px(3 * h.bins.size());
    c.resolve(h, bg, px.data());
    return px;
}

void expect_pixel(const std::vector<float>& px, std::size_t i, fp::Rgb want, double tol = 1e-6) {
    EXPECT_NEAR(px[3 * i], want.r, tol) << "pixel " << i;
    EXPECT_NEAR(px[3 * i + 1], want.g, tol) << "pixel " << i;
    EXPECT_NEAR(px[3 * i + 2], want.b, tol) << "pixel " << i;
}

TEST(CentroidDistance, SymmetricRow) {
    // A 5 x 3 histogram, hits in the middle row only: columns 0..4 with 1, 1, 2, 1, 1 hits.
    //   sum H = 6, sum H col = 0 + 1 + 4 + 3 + 4 = 12, centroid column 12/6 + 1/2 = 2.5, row
    //   1.5: the centre of pixel (2, 1). Distances 2, 1, 0, 1, 2 pixels, max 2: t = 1, 1/2,
    //   0, 1/2, 1. Flat: inner at the centre, middle at t = 1/2, outer at the rim.
    fp::Histogram h;
    h.resize(5, 3);
    const std::uint64_t hits[5] = {1, 1, 2, 1, 1};
    for (int c = 0; c < 5; ++c) h.bins[5 + c].hits = hits[c];
    auto c = colourer("inner: [1, 1, 0], middle: [0, 1, 0], outer: [0, 0, 1], density: flat");
    EXPECT_FALSE(c->needs_colour());
    const auto px = resolve(*c, h);
    expect_pixel(px, 7, {1, 1, 0});
    expect_pixel(px, 6, {0, 1, 0});
    expect_pixel(px, 8, {0, 1, 0});
    expect_pixel(px, 5, {0, 0, 1});
    expect_pixel(px, 9, {0, 0, 1});
    for (std::size_t i : {0u, 4u, 10u, 14u}) expect_pixel(px, i, {0.1f, 0.2f, 0.3f}, 0);
    // Without middle: t = 1/2 is the mean of inner and outer.
    const auto px2 = resolve(*colourer("inner: [1, 1, 0], outer: [0, 0, 1], density: flat"), h);
    expect_pixel(px2, 6, {0.5f, 0.5f, 0.5f});
    // Log density: the centre holds max H = 2 (factor 1); the others have H = 1, factor
    //   (log2(2) / log2(3))^(1/2.2).
    const auto px3 = resolve(*colourer("inner: [1, 1, 0], outer: [0, 0, 1], gamma: 2.2"), h);
    const double k = std::pow(1 / std::log2(3.0), 1 / 2.2);
    expect_pixel(px3, 7, {1, 1, 0});
    expect_pixel(px3, 9, {0, 0, float(k)});
    expect_pixel(px3, 6, {float(0.5 * k), float(0.5 * k), float(0.5 * k)});
}

TEST(CentroidDistance, HitWeightedCentroid) {
    // 4 x 1: 3 hits in column 0, 1 in column 3. Centroid column (3 * 0 + 1 * 3) / 4 + 1/2 =
    //   1.25 (not the midpoint 2 of the two pixels); distances 0.75 and 2.25, t = 1/3 and 1.
    //   inner blue, outer red: column 0 = (1/3, 0, 2/3), column 3 = red.
    fp::Histogram h;
    h.resize(4, 1);
    h.bins[0].hits = 3;
    h.bins[3].hits = 1;
    const auto px = resolve(*colourer("inner: [0, 0, 1], outer: [1, 0, 0], density: flat"), h);
    expect_pixel(px, 0, {1.0f / 3, 0, 2.0f / 3});
    expect_pixel(px, 3, {1, 0, 0});
    expect_pixel(px, 1, {0.1f, 0.2f, 0.3f}, 0);
    // Brightness scales and clamps.
    const auto pxb =
        resolve(*colourer("inner: [0, 0, 1], outer: [1, 0, 0], density: flat, brightness: 1.5"), h);
    expect_pixel(pxb, 0, {0.5f, 0, 1});
}

TEST(CentroidDistance, OneBinAndEmpty) {
    // All hits in one bin: t = 0, the inner colour. An empty histogram: background only.
    fp::Histogram h;
    h.resize(3, 3);
    h.bins[4].hits = 7;
    auto c = colourer("inner: \"#ff0000\", outer: \"#0000ff\"");
    expect_pixel(resolve(*c, h), 4, {1, 0, 0});
    h.bins[4].hits = 0;
    const auto px = resolve(*c, h);
    for (std::size_t i = 0; i < 9; ++i) expect_pixel(px, i, {0.1f, 0.2f, 0.3f}, 0);
}

} // namespace

#include <fixpoint/host/core/runtime.hpp>

namespace {

// Paper 03 Sec. III with a single map of probability 1 is the plain orbit: the chaos game with
// one GM map, one chain and no skip lights exactly the pixels of the orbit computed here by
// hand from the same start point.
TEST(GumowskiMira, SuperfractalWithOneMapIsThePlainOrbit) {
    auto t = gm("alpha: 0, mu: -0.31");
    constexpr int n = 20000, w = 96, h = 80;
    std::vector<Vec2> orbit;
    Vec2 p{0, 0.5};
    for (int i = 0; i < n; ++i) orbit.push_back(p = apply(*t, p));
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (Vec2 q : orbit)
        x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
    // A view a little larger than the orbit, so that every point lands in the image.
    const double mx = 0.05 * (x1 - x0), my = 0.05 * (y1 - y0);
    const double v[4] = {x0 - mx, x1 + mx, y0 - my, y1 + my};
    char yaml[1024];
    std::snprintf(
        yaml, sizeof yaml,
        "{type: chaos-game, width: %d, height: %d, view: [%.17g, %.17g, %.17g, %.17g], points: %d, chains: "
        "1, "
        "skip: 0, start: [0, 0.5], precision: double, background: [0, 0, 0], colourer: {type: map-colour, "
        "density: flat}, maps: [{type: gumowski-mira, alpha: 0, mu: -0.31, colour: [1, 1, 1]}]}",
        w, h, v[0], v[1], v[2], v[3], n);
    auto r = host().make<fp::Renderer>(yaml);
    ASSERT_TRUE(r);
    fp::host::Runtime rt(2, nullptr);
    fp::RenderStats stats;
    const fp::Image img = r->render(rt, stats);
    EXPECT_EQ(stats.restarts, 0u);
    std::vector<int> lit(std::size_t(w) * h, 0);
    for (Vec2 q : orbit) {
        const int col = std::min(w - 1, int(std::floor((q.x - v[0]) * (w / (v[1] - v[0])))));
        const int row = std::min(h - 1, int(std::floor((v[3] - q.y) * (h / (v[3] - v[2])))));
        lit[std::size_t(row) * w + std::size_t(col)] = 1;
    }
    std::size_t differ = 0, on = 0;
    for (std::size_t i = 0; i < lit.size(); ++i) {
        const bool shown = img.pixels[3 * i] > 0;
        differ += shown != bool(lit[i]);
        on += lit[i];
    }
    EXPECT_GT(on, 500u);
    EXPECT_EQ(differ, 0u);
}

} // namespace

namespace {

// fit_view: a pre-run fits the view to the orbits, so (almost) every point lands in the image
// and the pattern fills it; the fit is part of the recipe, hence deterministic.
TEST(GumowskiMira, FitViewHoldsTheOrbits) {
    const std::string yaml =
        "{type: chaos-game, width: 120, height: 90, points: 400000, chains: 64, skip: 100, fit_view: true, "
        "start_box: [-0.1, 0.1, 0.4, 0.6], precision: double, colourer: {type: density}, "
        "maps: [{type: gumowski-mira, alpha: 0, mu: -0.31}]}";
    auto r = host().make<fp::Renderer>(yaml);
    fp::host::Runtime rt(2, nullptr);
    fp::RenderStats st;
    const fp::Image a = r->render(rt, st);
    EXPECT_GT(double(st.drawn), 0.995 * double(st.samples));
    std::size_t lit = 0;
    for (std::size_t i = 0; i < a.pixels.size(); i += 3) lit += a.pixels[i] > 0;
    EXPECT_GT(double(lit), 0.15 * 120 * 90); // the pattern fills the frame, not a corner of it
    fp::host::Runtime rt1(1, nullptr);
    fp::RenderStats st1;
    EXPECT_EQ(host().make<fp::Renderer>(yaml)->render(rt1, st1).pixels, a.pixels);
}

// A single chain choosing between two maps (paper 03's superfractal child, fig4.yaml): the
// view fits the render's own orbit (the pre-run's streams would give another child, and its
// 4000 steps a quarter of this one). Seeds 1 to 3: at most 0.2% of the points outside the view,
// the child spanning at least 85% of the image along its tighter side (5% margins), nothing
// on the border; the same pixels on 1 and 2 threads.
TEST(GumowskiMira, FitViewHoldsASingleChildWhole) {
    for (const char* seed : {"1", "2", "3"}) {
        const std::string yaml =
            std::string("{type: chaos-game, width: 320, height: 240, points: 30000, chains: 1, skip: 0, ") +
            "start: [0, 0.5], precision: double, fit_view: true, seed: " + seed +
            ", colourer: {type: density}, maps: [{type: gumowski-mira, alpha: 0, mu: -0.7501, weight: 0.5}, "
            "{type: gumowski-mira, alpha: 0, mu: -0.7509, weight: 0.5}]}";
        fp::host::Runtime rt(2, nullptr);
        fp::RenderStats st;
        const fp::Image a = host().make<fp::Renderer>(yaml)->render(rt, st);
        EXPECT_GE(double(st.drawn), 0.998 * double(st.samples)) << seed;
        int x0 = 320, x1 = -1, y0 = 240, y1 = -1;
        for (int y = 0; y < 240; ++y)
            for (int x = 0; x < 320; ++x)
                if (a.pixels[3 * (size_t(y) * 320 + size_t(x))] > 0)
                    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        EXPECT_GT(x0, 0) << seed;
        EXPECT_LT(x1, 319) << seed;
        EXPECT_GT(y0, 0) << seed;
        EXPECT_LT(y1, 239) << seed;
        EXPECT_GE(std::max((x1 - x0 + 1) / 320.0, (y1 - y0 + 1) / 240.0), 0.85) << seed;
        fp::host::Runtime rt1(1, nullptr);
        fp::RenderStats st1;
        EXPECT_EQ(host().make<fp::Renderer>(yaml)->render(rt1, st1).pixels, a.pixels) << seed;
    }
}

TEST(GumowskiMira, BadStartBox) {
    try {
        host().make<fp::Renderer>(
            "{type: chaos-game, start_box: [1, 0, 0, 1], maps: [{type: gumowski-mira}]}");
        FAIL() << "accepted";
    } catch (const fp::InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "<string>:1:31: renderer.start_box: the start box must be [xmin, xmax, ymin, "
                  "ymax] with xmin < xmax and ymin < ymax");
    }
}

} // namespace
