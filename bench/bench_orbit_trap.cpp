// The orbit-trap renderer (paper 04, Algorithm 3) through the plugin pipeline, on the work of the
// reference kernel ../shared/perf-reference/wallpaper.cpp: its p4m-like map (the 12 non-zero
// coefficients of the reference, P32 = 0.422963 included, so the map is given as `group: p1`,
// which checks no conditions), the four traps of Fig. 3b ((+-4, 0), (0, +-4), r = 2 sqrt 2), 1024^2
// pixels at the reference's pixel centres over [-pi, pi)^2 (area [-pi + pi/1024, pi - pi/1024]^2),
// one sample per pixel, M = 100, the centred reduction into [-pi, pi) (map and renderer), float.
//
// The rate is the reference's unit, useful pixel-iterations per second: the sum over samples of
// the step that caught the orbit, or M. It is counted by one untimed render whose colourer (built
// here, not a plugin) adds up the iterations colour_hits() is given; the timed renders use the
// real colour-map colourer, so their time includes the colouring.
//
// fig8d: the time of a 1920 x 1080, 8-sample, M = 100 render of Fig. 8(d) (p4m, S-iteration
// alpha = 2, beta = -1.1, traps of Fig. 3b, colour map of Fig. 4a), the area [-2 pi, 2 pi] high
// and 16/9 as wide (square pixels).
//
//   fixpoint_bench_orbit_trap [--benchmark_filter=...]
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/registry.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/simd.hpp>

#include <benchmark/benchmark.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace {

constexpr double pi = std::numbers::pi;

const fp::host::Host& host() {
    static const fp::host::Host h;
    return h;
}

// The reference's map (wallpaper.cpp, struct Wall): P[i][j] = (x, y) for u_i(x) v_j(y).
const std::string reference_map =
    "{type: wallpaper, group: p1, reduction: centred, P03: [0, -0.234602], P04: [0, -0.231376], "
    "P13: [0, -0.931333], P14: [0, -0.982975], P23: [0, 0.429163], P24: [0, 0.363704], "
    "P30: [-0.234602, 0], P31: [-0.931333, 0], P32: [0.422963, 0], P40: [-0.231376, 0], "
    "P41: [-0.982975, 0], P42: [0.363704, 0]}";

// Paper 04's p4m example (Fig. 8), P32 fixed to 0.429163 (the p4m condition P32.x = P23.y).
const std::string fig8_map =
    "{type: wallpaper, group: p4m, P03: [0, -0.234602], P04: [0, -0.231376], P13: [0, -0.931333], "
    "P14: [0, -0.982975], P23: [0, 0.429163], P24: [0, 0.363704], P30: [-0.234602, 0], P31: [-0.931333, 0], "
    "P32: [0.429163, 0], P40: [-0.231376, 0], P41: [-0.982975, 0], P42: [0.363704, 0]}";

/// A colourer that only counts: the sum of the iterations of all samples.
class CountingColourer final : public fp::Colourer {
public:
    void update(const std::uint32_t*, fp::ColourState, const fp::Rgb*, const unsigned char*) const override {}
    void resolve(const fp::Histogram&, fp::Rgb, float*) const override {}
    bool colours_trap_hits() const override { return true; }
    void colour_hits(const std::int32_t*, const float*, const std::uint32_t* iteration, std::size_t n,
                     const fp::Rgb*, float* rgb) const override {
        std::uint64_t s = 0;
        for (std::size_t i = 0; i < n; ++i) s += iteration[i];
        for (std::size_t i = 0; i < 3 * n; ++i) rgb[i] = 0;
        total += s;
    }
    mutable std::atomic<std::uint64_t> total{0};
};

struct Setup {
    int width, height, samples;
    std::vector<double> area;
    std::string mapping, iteration, reduction;
};

Setup reference_setup() {
    const double h = pi - pi / 1024;
    return {1024, 1024, 1, {-h, h, -h, h}, reference_map, "{type: picard}", "centred"};
}

Setup fig8d_setup() {
    const double h = 2 * pi, w = h * 16 / 9;
    return {1920, 1080, 8, {-w, w, -h, h}, fig8_map, "{type: s-iteration, alpha: 2, beta: -1.1}", "fmod"};
}

// The orbit-trap renderer for `s`, with `colourer` (null: colour-map fig-4a), built from a
// parameter bag (so that an in-process colourer can take the colourer's slot).
std::shared_ptr<const fp::Renderer> make_renderer(const Setup& s,
                                                  std::shared_ptr<const fp::Object> colourer) {
    const fp::host::PluginEntry* e = host().registry().find("orbit-trap");
    if (!e) throw std::runtime_error("the orbit-trap plugin is not built");
    fp::ParamBag bag(e->desc->params, e->desc->n_params, "orbit-trap");
    bag.set("width", std::int64_t(s.width));
    bag.set("height", std::int64_t(s.height));
    bag.set("area", s.area);
    bag.set("max_iterations", std::int64_t(100));
    bag.set("samples", std::int64_t(s.samples));
    bag.set("mapping", std::shared_ptr<const fp::Object>(host().make<fp::Transform>(s.mapping)));
    bag.set("iteration", std::shared_ptr<const fp::Object>(host().make<fp::IterationScheme>(s.iteration)));
    bag.set("traps",
            std::shared_ptr<const fp::Object>(host().make<fp::Trap>("{type: circles, preset: fig-3b}")));
    if (!colourer) colourer = host().make<fp::Colourer>("{type: colour-map, preset: fig-4a}");
    bag.set("colourer", colourer);
    bag.set("reduction", s.reduction);
    bag.set("precision", std::string("float"));
    // (A bag built by hand has no defaults: every parameter the renderer reads is set.)
    bag.set("tile", false);
    return std::shared_ptr<const fp::Renderer>(dynamic_cast<const fp::Renderer*>(e->desc->create(bag)));
}

std::uint64_t useful_iterations(const Setup& s) {
    auto counter = std::make_shared<CountingColourer>();
    auto r = make_renderer(s, counter);
    fp::host::Runtime rt(2, nullptr);
    fp::RenderStats st;
    r->render(rt, st);
    return counter->total.load();
}

void run(benchmark::State& state, const Setup& s, bool per_iteration) {
    static std::uint64_t iters_ref = 0, iters_fig8d = 0;
    std::uint64_t& iters = s.samples == 1 ? iters_ref : iters_fig8d;
    if (per_iteration && iters == 0) iters = useful_iterations(s);
    auto r = make_renderer(s, nullptr);
    fp::host::Runtime rt(unsigned(state.range(0)), nullptr);
    std::uint64_t drawn = 0;
    for (auto _ : state) {
        fp::RenderStats st;
        auto img = r->render(rt, st);
        benchmark::DoNotOptimize(img.pixels.data());
        drawn = st.drawn;
    }
    if (per_iteration) {
        state.SetItemsProcessed(std::int64_t(state.iterations() * iters));
        state.counters["pixel_iterations"] = double(iters);
    }
    state.counters["trapped"] = double(drawn);
}

void reference_work(benchmark::State& state) { run(state, reference_setup(), true); }
void fig8d(benchmark::State& state) { run(state, fig8d_setup(), true); }

} // namespace

BENCHMARK(reference_work)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(fig8d)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// FIXPOINT_SIMD pins the kernels' instruction set, as for the CLI (bench/targets.sh).
int main(int argc, char** argv) {
    if (const char* t = std::getenv("FIXPOINT_SIMD"); t && *t && !fp::simd::force_target(t)) {
        std::fprintf(stderr, "FIXPOINT_SIMD=%s: not an instruction set of this CPU\n", t);
        return 2;
    }
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
