// The curved shapes' batch kernels alone (paper 01, Sec. 3), M rays or points per second on
// one thread: the ray exit about the set's centre and about another point of its kernel (a
// centre of inversion moved off it), and the inside test on points spread over twice the
// set's box (a chaos game's points mostly miss a set, as here three in four do).
//
//   shapes/ray_centre/NAME, shapes/ray_off/NAME, shapes/inside/NAME
//
// NAME: polygon (a 10-vertex star, the exact reference), superformula (fig6d's five lobes)
// and bezier (fig6d-bezier's flower of ten cubic segments), each about the origin.
//
//   fixpoint_bench_shapes [--benchmark_filter=...]
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/host.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace {

const fp::host::Host& host() {
    static const fp::host::Host h;
    return h;
}

std::string flower() {
    std::string s = "{type: bezier, points: [";
    for (int k = 0; k < 10; ++k) {
        const double a0 = M_PI * k / 5, a1 = M_PI * (k + 1) / 5, r0 = k % 2 ? 0.3 : 0.6,
                     r1 = k % 2 ? 0.6 : 0.3;
        const auto pt = [&](double r, double a) {
            return "[" + std::to_string(r * std::cos(a)) + ", " + std::to_string(r * std::sin(a)) + "]";
        };
        s += (k ? ", " : "") + pt(r0, a0) + ", " + pt(r0, a0 + 0.25 * (a1 - a0)) + ", " +
             pt(r1, a1 - 0.25 * (a1 - a0));
    }
    return s + "]}";
}

std::shared_ptr<const fp::Shape> shape(const std::string& name) {
    if (name == "polygon")
        return host().make<fp::Shape>(
            "{type: star-polygon, points: 5, inner_radius: 0.3, outer_radius: 0.6}");
    if (name == "superformula")
        return host().make<fp::Shape>("{type: superformula, m: 5, n1: 2, n2: 7, n3: 7, scale: 0.2523}");
    return host().make<fp::Shape>(flower());
}

constexpr std::size_t batch = 4096;

void ray(benchmark::State& state, const std::string& name, bool off) {
    const auto s = shape(name);
    const fp::Vec2 o = off ? fp::Vec2{0.05, -0.03} : s->centre();
    std::vector<double> dx(batch), dy(batch), t(batch);
    for (std::size_t i = 0; i < batch; ++i)
        dx[i] = std::cos(0.618 * double(i * i)), dy[i] = std::sin(0.618 * double(i * i));
    for (auto _ : state) {
        s->ray_exit(o, fp::Points<const double>{dx.data(), dy.data(), batch}, t.data());
        benchmark::DoNotOptimize(t.data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(batch));
}

void inside(benchmark::State& state, const std::string& name) {
    const auto s = shape(name);
    const fp::Box b = s->bounds();
    std::vector<double> x(batch), y(batch);
    std::vector<unsigned char> in(batch);
    for (std::size_t i = 0; i < batch; ++i) {
        const double u = std::fmod(0.7548776662 * double(i), 1.0),
                     v = std::fmod(0.5698402910 * double(i), 1.0);
        x[i] = b.xmin + (2 * u - 0.5) * (b.xmax - b.xmin);
        y[i] = b.ymin + (2 * v - 0.5) * (b.ymax - b.ymin);
    }
    for (auto _ : state) {
        s->inside(fp::Points<const double>{x.data(), y.data(), batch}, in.data());
        benchmark::DoNotOptimize(in.data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(batch));
}

const bool registered = [] {
    for (const std::string name : {"polygon", "superformula", "bezier"}) {
        benchmark::RegisterBenchmark(("shapes/ray_centre/" + name).c_str(), ray, name, false);
        benchmark::RegisterBenchmark(("shapes/ray_off/" + name).c_str(), ray, name, true);
        benchmark::RegisterBenchmark(("shapes/inside/" + name).c_str(), inside, name);
    }
    return true;
}();

} // namespace

BENCHMARK_MAIN();
