// The finishing stage (fixpoint/finish.hpp) on tiny histograms, against values worked by hand
// from flam3's definitions (filters.c: flam3_create_spatial_filter, flam3_create_de_filters;
// rect.c: de_thread): the spatial taps, the density kernels and their choice, a flat region that
// stays flat, a single hit that spreads exactly as far as its kernel's radius, the energy kept
// where flam3 keeps it, the tone formulas, and the same bytes whole, in strips and on any number
// of workers.
#include "host.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

double g(double x) { return std::exp(-2 * x * x); } // flam3's gaussian, without its constant

fp::FinishSpec spec(int N, const std::string& filter = "", double R = 0, double m = 0, double curve = 0.4) {
    fp::FinishSpec s;
    s.supersample = N;
    if (!filter.empty()) s.filter = make<fp::Filter>(filter);
    s.estimator_radius = R, s.estimator_minimum = m, s.estimator_curve = curve;
    return s;
}

// A w x h histogram of hit counts.
fp::Histogram hits(int w, int h, const std::vector<std::uint64_t>& v) {
    fp::Histogram H;
    H.width = w, H.height = h;
    H.hits = v;
    return H;
}

// The image `width` x (rows / N) of the whole histogram H, finished serially.
std::vector<float> finish_whole(const fp::FinishSpec& s, const fp::Colourer& c, const fp::Histogram& H,
                                fp::RenderContext* ctx = nullptr) {
    const int N = s.supersample, w = H.width / N, h = H.height / N;
    std::vector<float> rgb(std::size_t(w) * std::size_t(h) * 3);
    fp::finish(s, c, H, 0, fp::HistogramSummary::of(H), w, 0, h, fp::Rgb{0, 0, 0}, rgb.data(), ctx);
    return rgb;
}

} // namespace

// flam3's default filter at supersample 2: fw = 2 * 1.5 * 2 * 0.5 = 3, 4 taps (the parity of 2),
// at x = ((2i + 1) / 4 - 1) * (1.5 * 4 / 3) = -1.5, -0.5, 0.5, 1.5.
TEST(SpatialTaps, GaussianIsFlam3sAtSupersampleTwo) {
    const auto f = make<fp::Filter>("{type: gaussian, radius: 0.5}");
    const std::vector<double> t = fp::spatial_taps(f.get(), 2);
    ASSERT_EQ(t.size(), 4u);
    const double sum = 2 * (g(1.5) + g(0.5));
    EXPECT_NEAR(t[0], g(1.5) / sum, 1e-15);
    EXPECT_NEAR(t[1], g(0.5) / sum, 1e-15);
    EXPECT_DOUBLE_EQ(t[0], t[3]);
    EXPECT_DOUBLE_EQ(t[1], t[2]);
}

// Radius 1 box at supersample 3: fw = 3, 5 taps (odd), x = (2i - 4) / 6: the outer two fall
// outside (-0.5, 0.5], the middle three are the pixel's own bins.
TEST(SpatialTaps, BoxOfRadiusOneIsThePixelsBins) {
    const auto f = make<fp::Filter>("{type: box, radius: 1}");
    const std::vector<double> t = fp::spatial_taps(f.get(), 3);
    ASSERT_EQ(t.size(), 5u);
    EXPECT_EQ(t[0], 0.0);
    EXPECT_EQ(t[4], 0.0);
    for (int i = 1; i <= 3; ++i) EXPECT_DOUBLE_EQ(t[std::size_t(i)], 1.0 / 3);
    // Without a filter: the same mean, N taps.
    EXPECT_EQ(fp::spatial_taps(nullptr, 3), (std::vector<double>{1.0 / 3, 1.0 / 3, 1.0 / 3}));
}

// Mitchell (B = C = 1/3) at radius 1, supersample 1: fw = 4, 5 taps at x = -2 .. 2 (adjust 2.5);
// k(0) = (6 - 2B) / 6 = 8/9, k(1) = B / 6 = 1/18 (the outer cubic at 1), k(2) = 0: they sum to 1.
TEST(SpatialTaps, MitchellByHand) {
    const auto f = make<fp::Filter>("{type: mitchell, radius: 1}");
    const std::vector<double> t = fp::spatial_taps(f.get(), 1);
    ASSERT_EQ(t.size(), 5u);
    EXPECT_EQ(t[0], 0.0);
    EXPECT_NEAR(t[1], 1.0 / 18, 1e-15);
    EXPECT_NEAR(t[2], 8.0 / 9, 1e-15);
    EXPECT_NEAR(t[3], 1.0 / 18, 1e-15);
}

// Lanczos-3 is the textbook window: 1 at 0, 0 at the integers, 0 beyond 3.
TEST(SpatialTaps, LanczosIsSincTimesSincOverThree) {
    const auto f = make<fp::Filter>("{type: lanczos}");
    EXPECT_EQ(f->value(0), 1.0);
    EXPECT_NEAR(f->value(1), 0.0, 1e-15);
    EXPECT_NEAR(f->value(2), 0.0, 1e-15);
    EXPECT_EQ(f->value(3.5), 0.0);
    const double pi = 3.14159265358979323846, x = 0.5;
    EXPECT_NEAR(f->value(x), std::sin(pi * x) / (pi * x) * std::sin(pi * x / 3) / (pi * x / 3), 1e-15);
}

// R = 2, m = 0, curve 0.4, N = 1: widths h_k = 3 / (k + 1)^0.4 down to 1 (k = 15: 3 / 16^0.4 <
// 1), so 16 kernels. Kernel 1 (h = 2.2736) keeps its energy: every bin within h lies in the
// square of reach 2. The last (h = 1, reach 0) is its centre alone, normalised over the
// centre and its four neighbours at distance 1 = h: flam3 loses the rest.
TEST(DensityKernels, WidthsAndCoefficientsByHand) {
    const fp::DensityKernels de = fp::DensityKernels::make(spec(1, "", 2, 0, 0.4));
    ASSERT_EQ(de.kernels.size(), 16u);
    EXPECT_DOUBLE_EQ(de.kernels[0].width, 3.0);
    EXPECT_NEAR(de.kernels[1].width, 3 / std::pow(2.0, 0.4), 1e-12);
    EXPECT_EQ(de.kernels[1].reach, 2);
    double sum = 0;
    for (float c : de.kernels[1].coefs) sum += c;
    EXPECT_NEAR(sum, 1.0, 1e-6);
    // The corner (2, 2) is at 2.83 > h: 0; (2, 1) at 2.236 <= h: g(1.5 * 2.236 / h) / norm.
    const auto& k1 = de.kernels[1].coefs;
    EXPECT_EQ(k1[0], 0.0f);
    EXPECT_GT(k1[1], 0.0f);
    const fp::DensityKernels::Kernel& last = de.kernels.back();
    EXPECT_EQ(last.reach, 0);
    EXPECT_DOUBLE_EQ(last.width, 1.0);
    EXPECT_NEAR(last.coefs[0], 1 / (1 + 4 * g(1.5)), 1e-7);
    // The choice: one hit the widest, 2.5 counted hits kernel 2, many hits the last.
    EXPECT_EQ(de.index(1), 0u);
    EXPECT_EQ(de.index(2.5), 2u);
    EXPECT_EQ(de.index(1e6), 15u);
}

TEST(DensityKernels, FlamsLimitsAreRefused) {
    EXPECT_NE(error_of([] {
                  (void)fp::DensityKernels::make(spec(1, "", 1, 2));
              }).find("must not exceed estimator_radius"),
              std::string::npos);
    EXPECT_NE(
        error_of([] { (void)fp::DensityKernels::make(spec(1, "", 64, 0, 0.01)); }).find("too many kernels"),
        std::string::npos);
}

// A region of equal bins stays equal under the estimate (away from the edges, where the
// kernels' spill beyond the histogram is lost).
TEST(Finish, FlatStaysFlatUnderTheEstimate) {
    const auto c = make<fp::Colourer>("{type: density, gamma: 1}");
    const fp::Histogram H = hits(16, 16, std::vector<std::uint64_t>(256, 5));
    const std::vector<float> rgb = finish_whole(spec(1, "", 2), *c, H);
    const float centre = rgb[3 * (8 * 16 + 8)];
    EXPECT_NEAR(centre, 1.0f, 1e-5f);
    for (int y = 3; y < 13; ++y)
        for (int x = 3; x < 13; ++x)
            EXPECT_NEAR(rgb[3 * std::size_t(y * 16 + x)], centre, 1e-6f) << x << "," << y;
}

// One hit at the centre of a 21 x 21 histogram, R = 3 (kernel 0: h = 4, reach 3): it lights
// exactly the bins within distance 4 inside the square of reach 3, and with gamma 1 (pixel = a)
// their sum is the bin's density, 1 (h = 4 is an integer, but the rim at 4 lies outside the
// square of the largest kernel, so flam3 keeps this one's energy).
TEST(Finish, OneHitSpreadsByItsKernelsRadius) {
    const auto c = make<fp::Colourer>("{type: density, gamma: 1}");
    std::vector<std::uint64_t> v(21 * 21, 0);
    v[10 * 21 + 10] = 1;
    const std::vector<float> rgb = finish_whole(spec(1, "", 3), *c, hits(21, 21, v));
    double sum = 0;
    for (int y = 0; y < 21; ++y)
        for (int x = 0; x < 21; ++x) {
            const int dx = x - 10, dy = y - 10;
            const bool inside = std::abs(dx) <= 3 && std::abs(dy) <= 3 && dx * dx + dy * dy <= 16;
            const float p = rgb[3 * std::size_t(y * 21 + x)];
            EXPECT_EQ(p > 0, inside) << dx << "," << dy;
            sum += p;
        }
    EXPECT_NEAR(sum, 1.0, 1e-5);
    // Its weights are flam3's: the centre g(0) over the disc's sum.
    double norm = 0;
    for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx)
            if (dx * dx + dy * dy <= 16) norm += g(1.5 * std::sqrt(double(dx * dx + dy * dy)) / 4);
    EXPECT_NEAR(rgb[3 * (10 * 21 + 10)], 1 / norm, 1e-6);
}

// estimator_quality Q: a bin's counted hits are scaled by Q (image pixels) / (the histogram's
// hits), so a histogram of k times the hits picks the same kernels. One bin of 1 hit and one of
// 16 (alone in a 21 x 21 histogram, so both are at the maximum density a = 1) spread over the
// same disc of radius 3 at Q = 1 / 441 (count_scale 1 / hits: counted 1), to the same bytes;
// without Q the 16 hits take kernel 15, h = 4 / 16^0.4 = 1.32, reach 1: 5 bins lit.
TEST(Finish, EstimatorQualityKeepsTheKernelsAsTheHitsGrow) {
    const auto c = make<fp::Colourer>("{type: density, gamma: 1}");
    std::vector<std::uint64_t> one(21 * 21, 0), sixteen(21 * 21, 0);
    one[10 * 21 + 10] = 1, sixteen[10 * 21 + 10] = 16;
    const fp::Histogram H1 = hits(21, 21, one), H16 = hits(21, 21, sixteen);
    fp::FinishSpec q = spec(1, "", 3);
    q.estimator_quality = 1.0 / 441.0;
    EXPECT_DOUBLE_EQ(fp::DensityKernels::count_scale(q, fp::HistogramSummary::of(H16)), 1.0 / 16.0);
    EXPECT_EQ(finish_whole(q, *c, H16), finish_whole(q, *c, H1));
    EXPECT_EQ(finish_whole(q, *c, H1), finish_whole(spec(1, "", 3), *c, H1));
    const std::vector<float> plain = finish_whole(spec(1, "", 3), *c, H16);
    int lit = 0;
    for (std::size_t i = 0; i < plain.size(); i += 3) lit += plain[i] > 0;
    EXPECT_EQ(lit, 5) << "reach 1: the centre and its 4 neighbours (the corners, at 1.41, lie outside h)";
    // By hand: Q 2 on 4 x 2 bins at supersample 2 (2 image pixels) with 8 hits: 2 * 2 / 8.
    fp::FinishSpec q2 = spec(2, "", 1);
    q2.estimator_quality = 2;
    EXPECT_DOUBLE_EQ(
        fp::DensityKernels::count_scale(q2, fp::HistogramSummary::of(hits(4, 2, {1, 1, 1, 1, 1, 1, 1, 1}))),
        0.5);
    EXPECT_EQ(fp::DensityKernels::count_scale(spec(2, "", 1),
                                              fp::HistogramSummary::of(hits(4, 2, {1, 1, 1, 1, 1, 1, 1, 1}))),
              1.0);
}

// Supersample 2 without a filter: each pixel is the mean of its 2 x 2 bins' densities, with
// their hits read as an image pixel's (4 h): a pixel half of whose bins are hit has coverage 1/2.
TEST(Finish, SupersampleAveragesEachPixelsBins) {
    const auto c = make<fp::Colourer>("{type: density, gamma: 1}");
    // 4 x 2 bins -> 2 x 1 pixels; the left pixel's bins all hit once, the right's two of four.
    const fp::Histogram H = hits(4, 2, {1, 1, 1, 0, 1, 1, 1, 0});
    const std::vector<float> rgb = finish_whole(spec(2), *c, H);
    EXPECT_FLOAT_EQ(rgb[0], 1.0f); // every bin at the maximum: a = 1
    EXPECT_FLOAT_EQ(rgb[3], 0.5f);
}

// The whole histogram, in strips of image rows with their halo, and on 1, 2 and 3 workers: the
// same bytes (flame colours, a filter and the estimate at supersample 2).
TEST(Finish, SameBytesInStripsAndOnAnyWorkers) {
    const auto c = make<fp::Colourer>("{type: flame, gamma: 2.2}");
    const int N = 2, w = 19, h = 13, W = w * N, Hs = h * N;
    fp::Histogram H;
    H.width = W, H.height = Hs;
    H.bins.resize(std::size_t(W) * std::size_t(Hs));
    std::uint64_t s = 12345;
    for (auto& b : H.bins) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        const std::uint64_t k = (s >> 33) % 7;
        b.hits = k < 3 ? 0 : k * k;
        b.r = b.hits * 40000, b.g = b.hits * 20000, b.b = b.hits * 65535;
    }
    const fp::FinishSpec sp = spec(N, "{type: gaussian, radius: 0.75}", 2.5);
    const fp::HistogramSummary whole = fp::HistogramSummary::of(H);
    const std::vector<float> one = finish_whole(sp, *c, H);
    for (unsigned threads : {1u, 2u, 3u}) {
        fp::host::Runtime rt(threads, nullptr);
        EXPECT_EQ(finish_whole(sp, *c, H, &rt), one) << threads << " threads";
    }
    const int halo = sp.halo();
    for (int rows : {1, 3, 5}) {
        std::vector<float> strips(one.size());
        for (int o0 = 0; o0 < h; o0 += rows) {
            const int on = std::min(rows, h - o0);
            const int p0 = std::max(0, o0 * N - halo), p1 = std::min(Hs, (o0 + on) * N + halo);
            fp::Histogram part;
            part.width = W, part.height = p1 - p0;
            part.bins.assign(H.bins.begin() + std::ptrdiff_t(p0) * W,
                             H.bins.begin() + std::ptrdiff_t(p1) * W);
            fp::finish(sp, *c, part, p0, whole, w, o0, on, fp::Rgb{0, 0, 0},
                       strips.data() + std::size_t(o0) * std::size_t(w) * 3, nullptr);
        }
        EXPECT_EQ(std::memcmp(strips.data(), one.data(), one.size() * sizeof(float)), 0)
            << rows << " rows a strip";
    }
    // A strip without its halo is refused, not finished wrongly.
    fp::Histogram part;
    part.width = W, part.height = 2 * N;
    part.bins.assign(H.bins.begin() + std::ptrdiff_t(4) * W, H.bins.begin() + std::ptrdiff_t(8) * W);
    std::vector<float> two(std::size_t(w) * 2 * 3);
    EXPECT_THROW(fp::finish(sp, *c, part, 4, whole, w, 2, 2, fp::Rgb{}, two.data(), nullptr),
                 fp::InternalError);
}

// flam3's tone (rect.c, palettes.c), on one pixel of density a and colour c, against the
// formulas written out here: alpha = a^(1/gamma) (with a linear blend below gamma_threshold),
// ls = vibrancy alpha / a, and (1 - vibrancy) c^(1/gamma) per channel.
TEST(Tone, Flam3sFormulas) {
    const auto plain = make<fp::Colourer>("{type: flame, gamma: 2}");
    const auto vib = make<fp::Colourer>("{type: flame, gamma: 2, vibrancy: 0.25}");
    const auto thr = make<fp::Colourer>("{type: flame, gamma: 2, gamma_threshold: 0.5}");
    const auto hp = make<fp::Colourer>("{type: flame, gamma: 2, brightness: 4, highlight_power: 1}");
    const float px[5] = {0.25f, 0.8f, 0.4f, 0.2f, 1.0f};
    float out[3];
    plain->display(px, 1, fp::Rgb{}, out);
    // alpha = sqrt(0.25) = 0.5: colour * 0.5.
    EXPECT_NEAR(out[0], 0.4, 1e-6);
    EXPECT_NEAR(out[2], 0.1, 1e-6);
    vib->display(px, 1, fp::Rgb{}, out);
    // 0.25 * colour * 0.5 + 0.75 * sqrt(colour * 0.25).
    EXPECT_NEAR(out[1], 0.25 * 0.4 * 0.5 + 0.75 * std::sqrt(0.4 * 0.25), 1e-6);
    thr->display(px, 1, fp::Rgb{}, out);
    // a = 0.25 < t = 0.5: alpha = (1 - 0.5) * 0.25 * (sqrt(0.5) / 0.5) + 0.5 * sqrt(0.25).
    const double alpha = 0.5 * 0.25 * (std::sqrt(0.5) / 0.5) + 0.5 * 0.5;
    EXPECT_NEAR(out[0], 0.8 * alpha, 1e-6);
    hp->display(px, 1, fp::Rgb{}, out);
    // ls * c = 4 * 0.5 * colour saturates red (1.6): scaled to red = 1 and the saturation times
    // ((1 / max c) / ls)^1 = (1 / 0.2) / 8 = 0.625, so each channel moves towards 1.
    EXPECT_NEAR(out[0], 1.0, 1e-6);
    EXPECT_NEAR(out[1], 1 - (1 - 0.5) * 0.625, 1e-6);
    EXPECT_NEAR(out[2], 1 - (1 - 0.25) * 0.625, 1e-6);
    // Coverage below 1 lets the background through.
    const float half[5] = {0.25f, 0.8f, 0.4f, 0.2f, 0.5f};
    plain->display(half, 1, fp::Rgb{1, 1, 1}, out);
    EXPECT_NEAR(out[2], 0.1 + 0.5, 1e-6);
}
