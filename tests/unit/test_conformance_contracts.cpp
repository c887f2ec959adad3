// The conformance suite holds plugins to the fast-path promises renderers rely on: a
// Transform's KnownKernel, IterationScheme::is_picard, a Trap's TrapKernel, a Metric's kind,
// Colourer::resolve_parallel and Colourer::reads_hits_only are checked to the bit. Objects
// that lie about them must be reported (so the checks can fail); the project's own plugins
// must pass.
#include "host.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/conformance/conformance.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

bool mentions(const std::vector<std::string>& findings, const std::string& what) {
    return std::any_of(findings.begin(), findings.end(),
                       [&](const std::string& s) { return s.find(what) != std::string::npos; });
}

// Inversion in the unit circle computed as d / |d|^2: mathematically eq. (2), but not the
// kernel's arithmetic ((r2 / |d|^2) * d), so the bits differ for many points.
class ReorderedInversion final : public fp::TransformBase<ReorderedInversion> {
public:
    template <class T>
    void map_pt(T& x, T& y) const {
        const T q = x * x + y * y;
        x = x / q;
        y = y / q;
    }
    fp::KnownKernel kernel() const override {
        return {fp::KnownKernel::Kind::circle_inversion, 0.0, 0.0, 1.0};
    }
    bool has_region() const override { return true; }
};

// Mann with alpha = 1/2 claiming to be Picard.
class FalsePicard final : public fp::IterationScheme {
public:
    void step(const fp::Transform& t, fp::Points<float> p, fp::Mask m, std::uint64_t) const override {
        run(t, p, m);
    }
    void step(const fp::Transform& t, fp::Points<double> p, fp::Mask m, std::uint64_t) const override {
        run(t, p, m);
    }
    bool is_picard() const override { return true; }

private:
    template <class T>
    static void run(const fp::Transform& t, fp::Points<T> p, fp::Mask m) {
        std::vector<T> x(p.x, p.x + p.n), y(p.y, p.y + p.n);
        t.apply(p, m);
        for (std::size_t i = 0; i < p.n; ++i) p.x[i] = (p.x[i] + x[i]) / 2, p.y[i] = (p.y[i] + y[i]) / 2;
    }
};

// One circle of radius 1 at the origin whose test() uses <= and a sloppy ratio.
class SloppyCircle final : public fp::Trap {
public:
    std::size_t count() const override { return 1; }
    void test(fp::Points<const float> p, std::int32_t* t, float* r) const override { run(p, t, r); }
    void test(fp::Points<const double> p, std::int32_t* t, double* r) const override { run(p, t, r); }
    fp::TrapKernel kernel() const override {
        return {fp::TrapKernel::Kind::euclidean_circles, 1, &zero_, &zero_, &one_, &one_f_, &one_};
    }

private:
    template <class T>
    static void run(fp::Points<const T> p, std::int32_t* t, T* r) {
        for (std::size_t i = 0; i < p.n; ++i) {
            const T d = std::hypot(p.x[i], p.y[i]);
            t[i] = d < T(1.0001) ? 0 : -1;
            r[i] = std::min(d, T(0.999));
        }
    }
    double zero_ = 0, one_ = 1;
    float one_f_ = 1;
};

// The Euclidean distance that says its key is the distance squared but returns the distance.
class KeylessEuclid final : public fp::Metric {
public:
    void distance(fp::Points<const float> p, fp::Vec2 c, float* o) const override { run(p, c, o); }
    void distance(fp::Points<const double> p, fp::Vec2 c, double* o) const override { run(p, c, o); }
    Kind kind() const override { return Kind::euclidean; }

private:
    template <class T>
    static void run(fp::Points<const T> p, fp::Vec2 c, T* o) {
        for (std::size_t i = 0; i < p.n; ++i) o[i] = std::hypot(p.x[i] - T(c.x), p.y[i] - T(c.y));
    }
};

// A flat colourer whose parallel resolve forgets the background of empty bins.
class PatchyParallel final : public fp::Colourer {
public:
    void update(const std::uint32_t*, fp::ColourState, const fp::Rgb*, const unsigned char*) const override {}
    void resolve(const fp::Histogram& h, fp::Rgb bg, float* rgb) const override { fill(h, bg, rgb, true); }
    void resolve_parallel(const fp::Histogram& h, fp::Rgb bg, float* rgb, fp::RenderContext&) const override {
        fill(h, bg, rgb, false);
    }

private:
    static void fill(const fp::Histogram& h, fp::Rgb bg, float* rgb, bool with_background) {
        for (std::size_t i = 0; i < h.bins.size(); ++i) {
            const bool empty = h.bins[i].hits == 0 && with_background;
            rgb[3 * i] = empty ? bg.r : 1, rgb[3 * i + 1] = empty ? bg.g : 1,
                    rgb[3 * i + 2] = empty ? bg.b : 1;
        }
    }
};

// A colourer that says it reads hit counts alone, but shades a histogram of hit counts
// alone (Histogram::hits) darker than the same bins: it reads the form, not only the counts.
class FormDependent final : public fp::Colourer {
public:
    void update(const std::uint32_t*, fp::ColourState, const fp::Rgb*, const unsigned char*) const override {}
    bool needs_colour() const override { return false; }
    bool reads_hits_only() const override { return true; }
    void resolve(const fp::Histogram& h, fp::Rgb bg, float* rgb) const override {
        const float v = h.hits.empty() ? 1.0f : 0.5f;
        for (std::size_t i = 0; i < h.size(); ++i) {
            const bool empty = h.hits_at(i) == 0;
            rgb[3 * i] = empty ? bg.r : v, rgb[3 * i + 1] = empty ? bg.g : v,
                    rgb[3 * i + 2] = empty ? bg.b : v;
        }
    }
};

} // namespace

TEST(ConformanceContracts, AColourerThatReadsTheHistogramsFormIsReported) {
    const auto f = fp::host::check_object(FormDependent{}, fp::Kind::Colourer);
    EXPECT_TRUE(mentions(f, "colourer: resolve() of hit counts alone differs from resolve() of the bins"))
        << testing::PrintToString(f);
}

TEST(ConformanceContracts, AParallelResolveThatDiffersIsReported) {
    const auto f = fp::host::check_object(PatchyParallel{}, fp::Kind::Colourer);
    EXPECT_TRUE(mentions(f, "resolve_parallel() with 1 worker differs from resolve()"))
        << testing::PrintToString(f);
}

TEST(ConformanceContracts, ALyingKnownKernelIsReported) {
    const auto f = fp::host::check_object(ReorderedInversion{}, fp::Kind::Transform);
    EXPECT_TRUE(mentions(f, "kernel() promises inversion in a circle")) << testing::PrintToString(f);
}

TEST(ConformanceContracts, AFalsePicardIsReported) {
    const auto f = fp::host::check_object(FalsePicard{}, fp::Kind::IterationScheme);
    EXPECT_TRUE(mentions(f, "is_picard() is true, but step() is not exactly T(p)"))
        << testing::PrintToString(f);
}

TEST(ConformanceContracts, ALyingTrapKernelIsReported) {
    const auto f = fp::host::check_object(SloppyCircle{}, fp::Kind::Trap);
    EXPECT_TRUE(mentions(f, "kernel() promises Euclidean circles")) << testing::PrintToString(f);
}

TEST(ConformanceContracts, ALyingMetricKindIsReported) {
    const auto f = fp::host::check_object(KeylessEuclid{}, fp::Kind::Metric);
    EXPECT_TRUE(mentions(f, "kind() is euclidean, but distance_key()")) << testing::PrintToString(f);
}

TEST(ConformanceContracts, TheProjectsFastPathsKeepTheirPromises) {
    const auto inv = host().make<fp::Transform>(
        "{type: inversion, shape: {type: circle, centre: [0.3, -0.2], radius: 0.7}}");
    ASSERT_EQ(inv->kernel().kind, fp::KnownKernel::Kind::circle_inversion);
    EXPECT_EQ(fp::host::check_object(*inv, fp::Kind::Transform), std::vector<std::string>{});
    const auto picard = host().make<fp::IterationScheme>("{type: picard}");
    ASSERT_TRUE(picard->is_picard());
    EXPECT_EQ(fp::host::check_object(*picard, fp::Kind::IterationScheme), std::vector<std::string>{});
    const auto trap = host().make<fp::Trap>("{type: circles, preset: fig-1d}");
    ASSERT_EQ(trap->kernel().kind, fp::TrapKernel::Kind::euclidean_circles);
    EXPECT_EQ(fp::host::check_object(*trap, fp::Kind::Trap), std::vector<std::string>{});
    const auto lp = host().make<fp::Metric>("{type: lp, p: 2}");
    ASSERT_EQ(lp->kind(), fp::Metric::Kind::euclidean);
    EXPECT_EQ(fp::host::check_object(*lp, fp::Kind::Metric), std::vector<std::string>{});
}
