// Chaos game through the full plugin pipeline (YAML -> plugins -> renderer -> histogram ->
// colourer), on the reference kernel's work (bench/circles.yaml), beside an inline scalar
// loop of the same work as a second yardstick. Two colourers: density (hits only, the
// reference's work) and map-colour (a colour per point, accumulated in the histogram); float
// and double chains; 1 and 2 threads. The `iteration/...` lines run the density/float render
// with other iteration schemes in place of the Picard step (issue 3): Picard, the S-iteration in
// the reals and in a q-system, Mann. `density_float_generic` is the headline with the fused
// circle-inversion step turned off (`kernels: generic`): the generic plugin path.
//
//   fixpoint_bench [--benchmark_filter=...]    FIXPOINT_BENCH_POINTS overrides the 1e8 points
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/rng.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

std::uint64_t bench_points() {
    const char* env = std::getenv("FIXPOINT_BENCH_POINTS");
    return env ? std::uint64_t(std::atof(env)) : 100000000ull;
}

// The render of bench/circles.yaml with `precision`, `colourer` and, if given, `iteration` (a
// YAML flow mapping: the iteration scheme replacing the default Picard step).
void chaos_game_with(benchmark::State& state, const char* precision, const char* colourer,
                     const char* iteration, const char* kernels = "auto") {
    fp::host::Registry reg;
    for (const auto& d : fp::host::Registry::default_dirs()) reg.load_dir(d);
    const std::uint64_t n = bench_points();
    std::vector<std::string> sets = {"renderer.points=" + std::to_string(n),
                                     std::string("renderer.precision=") + precision,
                                     std::string("renderer.colourer={type: ") + colourer + "}"};
    if (iteration) sets.push_back(std::string("renderer.iteration=") + iteration);
    sets.push_back(std::string("renderer.kernels=") + kernels);
    const auto p = fp::host::load_pipeline(reg, FIXPOINT_BENCH_DIR "/circles.yaml", sets);
    const unsigned threads = unsigned(state.range(0));
    fp::host::Runtime rt(threads, nullptr);
    std::uint64_t restarts = 0;
    for (auto _ : state) {
        fp::RenderStats stats;
        auto img = p.renderer->render(rt, stats);
        benchmark::DoNotOptimize(img.pixels.data());
        restarts = stats.restarts;
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * n));
    state.counters["restarts"] = double(restarts);
}

void chaos_game(benchmark::State& state, const char* precision, const char* colourer) {
    chaos_game_with(state, precision, colourer, nullptr);
}

void chaos_game_generic(benchmark::State& state, const char* precision, const char* colourer) {
    chaos_game_with(state, precision, colourer, nullptr, "generic");
}

// Issue 3, section 9: the same six circles (density, float) with other iteration schemes in
// place of the Picard step p <- T(p). `picard` is the baseline (the default, named here);
// `s_real` the S-iteration in the reals (two applications of T per step); `s_qsystem` the
// S-iteration computing in the q-system Q_{-1.5, 0.2}; `mann_real` the Mann iteration (one
// application of T and one combination per step).
void iteration(benchmark::State& state, const char* scheme) {
    chaos_game_with(state, "float", "density", scheme);
}

// The same work as a plain scalar loop (double, one orbit, uniform choice among the other
// maps with redraw while the point is inside), histogram only: no plugins, no colour.
void inline_scalar(benchmark::State& state) {
    const std::uint64_t n = bench_points() / 4;
    double ox[6], oy[6], r2[6];
    for (int k = 0; k < 5; ++k)
        ox[k] = std::cos(2 * M_PI * k / 5), oy[k] = std::sin(2 * M_PI * k / 5), r2[k] = 0.65 * 0.65;
    ox[5] = oy[5] = 0, r2[5] = 0.16;
    std::vector<std::uint32_t> hist(1024 * 1024);
    for (auto _ : state) {
        fp::Rng rng = fp::chain_stream(1, 0);
        double x = 0.01, y = 0.02;
        int prev = 5;
        for (std::uint64_t i = 0; i < n; ++i) {
            int k;
            double dx, dy, d2;
            do {
                k = prev + 1 + int(fp::uniform_below(rng, 5));
                k -= k >= 6 ? 6 : 0;
                dx = x - ox[k], dy = y - oy[k], d2 = dx * dx + dy * dy;
            } while (d2 <= r2[k]);
            const double s = r2[k] / d2;
            x = ox[k] + s * dx, y = oy[k] + s * dy, prev = k;
            const double px = x * 640 + 512, py = y * 640 + 512;
            if (px >= 0 && px < 1024 && py >= 0 && py < 1024)
                ++hist[std::size_t(py) * 1024 + std::size_t(px)];
        }
        benchmark::DoNotOptimize(hist.data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * n));
}

// How every render here is timed: in milliseconds, with the process's CPU time beside the wall
// time (the threads' work, not only the caller's), over 3 iterations.
void timed(benchmark::internal::Benchmark* b) {
    b->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime()->Iterations(3);
}
void on_1_thread(benchmark::internal::Benchmark* b) { timed(b->Arg(1)); }
void on_1_and_2_threads(benchmark::internal::Benchmark* b) { timed(b->Arg(1)->Arg(2)); }

} // namespace

BENCHMARK_CAPTURE(chaos_game, density_float, "float", "density")->Apply(on_1_and_2_threads);
BENCHMARK_CAPTURE(chaos_game_generic, density_float_generic, "float", "density")->Apply(on_1_and_2_threads);
BENCHMARK_CAPTURE(chaos_game, density_double, "double", "density")->Apply(on_1_and_2_threads);
BENCHMARK_CAPTURE(chaos_game, map_colour_float, "float", "map-colour")->Apply(on_1_and_2_threads);
BENCHMARK_CAPTURE(chaos_game, map_colour_double, "double", "map-colour")->Apply(on_1_and_2_threads);
BENCHMARK_CAPTURE(iteration, picard, "{type: picard}")->Apply(on_1_and_2_threads);
BENCHMARK_CAPTURE(iteration, s_real, "{type: s-iteration, alpha: 0.7, beta: 0.5}")->Apply(on_1_thread);
BENCHMARK_CAPTURE(
    iteration, s_qsystem,
    "{type: s-iteration, numbers: {type: q-system, A: -1.5, B: 0.2}, alpha: 0.9+0.9q, beta: 0.2+0.2q}")
    ->Apply(on_1_and_2_threads);
BENCHMARK_CAPTURE(iteration, mann_real, "{type: mann, alpha: 0.7}")->Apply(on_1_thread);
BENCHMARK(inline_scalar)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

BENCHMARK_MAIN();
