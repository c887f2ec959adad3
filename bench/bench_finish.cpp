// The finishing stage (fixpoint/finish.hpp, issue 42) on the fern's histogram, beside a whole
// render of the same size: what the filter, flam3's density estimation and the tone cost.
//
//   finish/*_1024     a 1024 x 1024 image from the histogram of bench/fern.yaml's 1e8 points:
//                     ss1_gauss (flam3's default filter), ss1_de9 (and flam3's default estimate,
//                     radius 9), ss2_gauss and ss2_de9 (a 2048 x 2048 histogram)
//   finish/de9_4096   the estimate and filter on a 4096 x 4096 histogram (1.6e9 points)
//   render/fern_4096  bench/fern.yaml rendered at 4096 x 4096 with those points, unfinished: a
//                     typical render of that size (issue 42 wants the estimate under a tenth)
//
// The histograms come from a plain loop of the fern's maps (the same maps and weights, a
// colour per map), made once per size before the timings.
//
//   fixpoint_bench_finish [--benchmark_filter=...]   FIXPOINT_BENCH_SCALE=0.01 for fewer points
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

double scale() {
    const char* env = std::getenv("FIXPOINT_BENCH_SCALE");
    return env ? std::atof(env) : 1.0;
}

const fp::host::Host& host() {
    static const fp::host::Host h;
    return h;
}

// The fern's histogram, W x W bins over bench/fern.yaml's view, `points` points.
const fp::Histogram& fern(int W, std::uint64_t points) {
    static std::map<std::pair<int, std::uint64_t>, fp::Histogram> made;
    auto it = made.find({W, points});
    if (it != made.end()) return it->second;
    fp::Histogram h;
    h.resize(W, W);
    struct Map {
        double a, b, c, d, e, f, w;
        std::uint64_t r, g, bl;
    };
    const Map maps[4] = {{0, 0, 0, 0.16, 0, 0, 0.01, 65535, 20000, 20000},
                         {0.85, -0.04, 0.04, 0.85, 0, -1.6, 0.85, 20000, 65535, 20000},
                         {0.20, 0.26, -0.23, 0.22, 0, -1.6, 0.07, 20000, 20000, 65535},
                         {-0.15, -0.28, -0.26, 0.24, 0, -0.44, 0.07, 65535, 65535, 20000}};
    const double xmin = -5.0113, xmax = 5.4913, ymin = -10.2513, ymax = 0.2513;
    const double sx = W / (xmax - xmin), sy = W / (ymax - ymin);
    std::uint64_t s = 0x9e3779b97f4a7c15ull;
    double x = 0, y = 0;
    for (std::uint64_t i = 0; i < points + 20; ++i) {
        s ^= s >> 12, s ^= s << 25, s ^= s >> 27;
        const double u = double((s * 0x2545f4914f6cdd1dull) >> 11) * 0x1.0p-53;
        const Map& m = u < 0.01 ? maps[0] : u < 0.86 ? maps[1] : u < 0.93 ? maps[2] : maps[3];
        const double nx = m.a * x + m.b * y + m.e, ny = m.c * x + m.d * y + m.f;
        x = nx, y = ny;
        if (i < 20 || x < xmin || x >= xmax || y <= ymin || y > ymax) continue;
        const auto ix = std::min(W - 1, int((x - xmin) * sx)), iy = std::min(W - 1, int((ymax - y) * sy));
        fp::HistBin& b = h.bins[std::size_t(iy) * std::size_t(W) + std::size_t(ix)];
        ++b.hits, b.r += m.r, b.g += m.g, b.b += m.bl;
    }
    return made.emplace(std::make_pair(W, points), std::move(h)).first->second;
}

void finish(benchmark::State& state, int image, int N, double estimator, std::uint64_t points) {
    const fp::Histogram& h = fern(image * N, std::uint64_t(double(points) * scale()));
    const auto colourer = host().make<fp::Colourer>("{type: flame}");
    fp::FinishSpec spec;
    spec.supersample = N;
    spec.filter = host().make<fp::Filter>("{type: gaussian, radius: 0.5}");
    spec.estimator_radius = estimator;
    fp::host::Runtime rt(unsigned(state.range(0)), nullptr);
    std::vector<float> rgb(std::size_t(image) * std::size_t(image) * 3);
    for (auto _ : state) {
        const fp::HistogramSummary whole = fp::HistogramSummary::of(h, &rt);
        fp::finish(spec, *colourer, h, 0, whole, image, 0, image, fp::Rgb{}, rgb.data(), &rt);
        benchmark::DoNotOptimize(rgb.data());
    }
    state.counters["bins"] = double(h.bins.size());
}

void render(benchmark::State& state, int image, std::uint64_t points) {
    fp::host::Registry reg;
    for (const auto& d : fp::host::Registry::default_dirs()) reg.load_dir(d);
    const std::uint64_t n = std::uint64_t(double(points) * scale());
    const auto p = fp::host::load_pipeline(reg, FIXPOINT_BENCH_DIR "/fern.yaml",
                                           {"renderer.points=" + std::to_string(n),
                                            "renderer.width=" + std::to_string(image),
                                            "renderer.height=" + std::to_string(image)});
    fp::host::Runtime rt(unsigned(state.range(0)), nullptr);
    for (auto _ : state) {
        fp::RenderStats stats;
        auto img = p.renderer->render(rt, stats);
        benchmark::DoNotOptimize(img.pixels.data());
    }
}

constexpr std::uint64_t points_1024 = 100000000ull, points_4096 = 1600000000ull;

void on_2_threads(benchmark::internal::Benchmark* b) {
    b->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);
}
void on_1_and_2_threads(benchmark::internal::Benchmark* b) {
    b->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);
}

} // namespace

BENCHMARK_CAPTURE(finish, ss1_gauss_1024, 1024, 1, 0.0, points_1024)->Apply(on_1_and_2_threads);
BENCHMARK_CAPTURE(finish, ss1_de9_1024, 1024, 1, 9.0, points_1024)->Apply(on_1_and_2_threads);
BENCHMARK_CAPTURE(finish, ss2_gauss_1024, 1024, 2, 0.0, points_1024)->Apply(on_2_threads);
BENCHMARK_CAPTURE(finish, ss2_de9_1024, 1024, 2, 9.0, points_1024)->Apply(on_2_threads);
BENCHMARK_CAPTURE(finish, de9_4096, 4096, 1, 9.0, points_4096)->Apply(on_2_threads);
BENCHMARK_CAPTURE(render, fern_4096, 4096, points_4096)->Apply(on_2_threads);

BENCHMARK_MAIN();
