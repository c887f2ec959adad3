// What the conformance suite's files share: conformance.cpp runs the suite on a plugin (its
// metadata, its refusals, its draws) and hands each object to its kind's checks, one file a
// family: geometry.cpp (shapes, transforms), metric_trap.cpp (metrics, traps, number systems),
// colourer.cpp, renderer.cpp, conformance_scheme.cpp (iteration schemes).
#pragma once

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/conformance/conformance.hpp>

#include <cmath>
#include <cstring>
#include <exception>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace fp::host::detail {

/// The failures found so far, and the list of checks run (for `conformance --verbose`).
struct Findings {
    std::vector<std::string> failures;
    std::vector<CheckResult> checks;

    void push_back(std::string s) { failures.push_back(std::move(s)); }
    std::size_t size() const { return failures.size(); }
    /// Records check `name`: it passed when it added no failure since `before` (= size()).
    void record(std::string name, std::size_t before) {
        checks.push_back({std::move(name), failures.size() == before});
    }
    /// Records check `name` with its finding ("" when it passed).
    void check(std::string name, std::string finding) {
        checks.push_back({std::move(name), finding.empty()});
        if (!finding.empty()) failures.push_back(std::move(finding));
    }
};

/// Deterministic sample points.
struct Sampler {
    Rng rng = chain_stream(20261121, 7);
    double in(double a, double b) { return a + (b - a) * uniform_double(rng); }
};

/// Equal to the bit, except that any NaN equals any NaN (a NaN's payload is not a result).
template <class T>
bool same_bits(T a, T b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0 || (std::isnan(a) && std::isnan(b));
}

inline const std::string not_std_exception =
    "an exception that is not a std::exception (throw fp::InputError or "
    "another std::exception)";

// Run `f` twice at once on two threads and once alone; all three must agree.
template <class F>
bool same_on_two_threads(F f) {
    auto a = f();
    decltype(a) b, c;
    // An exception escaping a std::thread ends the process: carry it to this thread instead.
    std::exception_ptr eb, ec;
    std::thread t1([&] {
        try {
            b = f();
        } catch (...) {
            eb = std::current_exception();
        }
    });
    std::thread t2([&] {
        try {
            c = f();
        } catch (...) {
            ec = std::current_exception();
        }
    });
    t1.join();
    t2.join();
    if (eb) std::rethrow_exception(eb);
    if (ec) std::rethrow_exception(ec);
    return a == b && a == c;
}

template <class T>
bool bit_equal(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!(a[i] == b[i] || (std::isnan(double(a[i])) && std::isnan(double(b[i]))))) return false;
    return true;
}

// An in-place map of the plane (a transform, one step of a scheme) evaluated on the whole
// batch, and point by point; both as [x..., y...].
struct MapResults {
    std::vector<double> batch, pointwise;
};
template <class F>
MapResults map_batch_and_pointwise(const std::vector<double>& x0, const std::vector<double>& y0, F map) {
    const std::size_t n = x0.size();
    MapResults r;
    std::vector<double> x = x0, y = y0;
    map(Points<double>{x.data(), y.data(), n});
    r.batch = x;
    r.batch.insert(r.batch.end(), y.begin(), y.end());
    r.pointwise.resize(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
        double px = x0[i], py = y0[i];
        map(Points<double>{&px, &py, 1});
        r.pointwise[i] = px, r.pointwise[n + i] = py;
    }
    return r;
}

// The kinds' checks, each adding its failures to `f`.
void check_shape(const Shape& s, Findings& f);
void check_transform(const Transform& t, Findings& f);
void check_metric(const Metric& m, Findings& f);
void check_trap(const Trap& t, Findings& f);
void check_numbers(const NumberSystem& ns, Findings& f);
void check_colourer(const Colourer& c, Findings& f);
void check_renderer(const Renderer& r, Findings& f);
void check_filter(const Filter& flt, Findings& f);
void check_scheme(const IterationScheme& s, Findings& f);

} // namespace fp::host::detail
