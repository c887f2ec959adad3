// The wallpaper transform alone (paper 04), through the plugin as the orbit-trap renderer calls
// it: apply(Points, mask) on one 256-point chunk, iterated in place (the points stay in the
// reduced domain, as in a render). Items = points mapped. One thread: the transform has no
// threads of its own. The forms of wallpaper_kernel.hpp: p4m (Fig. 8's coefficients: the sparse
// "cross" form, the map of ../shared/perf-reference/wallpaper.cpp), p4 (Fig. 9: the odd form), p1
// (random: dense) and p3m1 (Fig. 5: hexagonal); float and double; with and without a mask.
//
//   fixpoint_bench_wallpaper [--benchmark_filter=...]
#include <fixpoint/host/core/host.hpp>

#include <benchmark/benchmark.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace {

const char* const fig8 = "{type: wallpaper, group: p4m, P03: [0, -0.234602], P04: [0, -0.231376], "
                         "P13: [0, -0.931333], P14: [0, -0.982975], P23: [0, 0.429163], P24: [0, 0.363704], "
                         "P30: [-0.234602, 0], P31: [-0.931333, 0], P32: [0.429163, 0], P40: [-0.231376, 0], "
                         "P41: [-0.982975, 0], P42: [0.363704, 0]}";
const char* const fig9 =
    "{type: wallpaper, group: p4, P03: [0.215989, -0.150289], P04: [0.0748772, 0.670663], P13: [0.741719, "
    "0.543639], P14: [0.709028, -0.822211], P23: [0.708072, -0.814562], P24: [0.100835, 0.40511], P30: "
    "[-0.150289, -0.215989], P31: [0.543639, -0.741719], P32: [-0.814562, -0.708072], P40: [0.670663, "
    "-0.0748772], P41: [-0.822211, -0.709028], P42: [0.40511, -0.100835]}";
const char* const dense = "{type: wallpaper, group: p1, seed: 1}";
const char* const fig5 = "{type: wallpaper, group: p3m1, G: [[0.343244, 0.711418], [-0.671499, -0.289951], "
                         "[-0.959405, -0.868905]], H: [[-0.224996, 0.0844803], [-0.0571376, 0.0250126], "
                         "[0.0250892, 0.553883]]}";

const fp::host::Host& host() {
    static const fp::host::Host h;
    return h;
}

template <class T>
void wallpaper(benchmark::State& state, const char* yaml, bool masked) {
    const auto t = host().make<fp::Transform>(yaml);
    constexpr std::size_t n = 256;
    std::vector<T> x(n), y(n);
    std::vector<unsigned char> mask(n, 1);
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = T(-6.2 + 12.4 * double(i) / n);
        y[i] = T(6.1 - 11.9 * double((i * 37) % n) / n);
        mask[i] = i % 7 != 3; // a few retired lanes, as in a render
    }
    for (auto _ : state) {
        t->apply(fp::Points<T>{x.data(), y.data(), n}, masked ? mask.data() : nullptr);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * n));
}

void wallpaper_float(benchmark::State& state, const char* yaml, bool masked) {
    wallpaper<float>(state, yaml, masked);
}
void wallpaper_double(benchmark::State& state, const char* yaml, bool masked) {
    wallpaper<double>(state, yaml, masked);
}

} // namespace

BENCHMARK_CAPTURE(wallpaper_float, p4m_fig8_float, fig8, false);
BENCHMARK_CAPTURE(wallpaper_float, p4m_fig8_float_masked, fig8, true);
BENCHMARK_CAPTURE(wallpaper_double, p4m_fig8_double, fig8, false);
BENCHMARK_CAPTURE(wallpaper_float, p4_fig9_float, fig9, false);
BENCHMARK_CAPTURE(wallpaper_double, p4_fig9_double, fig9, false);
BENCHMARK_CAPTURE(wallpaper_float, p1_dense_float, dense, false);
BENCHMARK_CAPTURE(wallpaper_double, p1_dense_double, dense, false);
BENCHMARK_CAPTURE(wallpaper_float, p3m1_fig5_float, fig5, false);
BENCHMARK_CAPTURE(wallpaper_double, p3m1_fig5_double, fig5, false);

BENCHMARK_MAIN();
