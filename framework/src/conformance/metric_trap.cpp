// The conformance checks of metrics, traps and number systems (conformance_detail.hpp).
#include "conformance_detail.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp::host::detail {

namespace {

// ------------------------------------------------------------------ Metric
// A metric of a known kind promises distance_key() and key() to the bit (traps inline them).
template <class T>
void check_metric_kind(const Metric& m, const std::vector<double>& x0, const std::vector<double>& y0,
                       Findings& f) {
    if (m.kind() != Metric::Kind::euclidean) return;
    const std::size_t n = x0.size();
    const std::vector<T> x(x0.begin(), x0.end()), y(y0.begin(), y0.end());
    const Vec2 c{0.25, -0.5};
    std::vector<T> key(n);
    m.distance_key(Points<const T>{x.data(), y.data(), n}, c, key.data());
    std::size_t bad = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const T dx = x[i] - T(c.x), dy = y[i] - T(c.y), e = dx * dx + dy * dy;
        bad += std::memcmp(&e, &key[i], sizeof(T)) != 0;
    }
    for (double d : {0.5, 1.0, 3.5, 2.8284271247461903}) bad += m.key(d) != d * d;
    if (bad)
        f.push_back(std::string("metric: kind() is euclidean, but distance_key() or key() is not the squared "
                                "distance (") +
                    (sizeof(T) == 4 ? "float" : "double") + ")");
}

} // namespace

void check_metric(const Metric& m, Findings& f) {
    Sampler smp;
    constexpr std::size_t n = 300;
    std::vector<double> x(n), y(n);
    for (std::size_t i = 0; i < n; ++i) x[i] = smp.in(-3, 3), y[i] = smp.in(-3, 3);
    check_metric_kind<double>(m, x, y, f);
    check_metric_kind<float>(m, x, y, f);
    std::vector<double> d(n * n); // d[i*n + j] = d(p_j, p_i)
    for (std::size_t i = 0; i < n; ++i)
        m.distance(Points<const double>{x.data(), y.data(), n}, {x[i], y[i]}, &d[i * n]);
    std::size_t neg = 0, asym = 0, nonzero = 0, tri = 0;
    for (std::size_t i = 0; i < n; ++i) {
        nonzero += d[i * n + i] != 0;
        for (std::size_t j = 0; j < n; ++j) {
            neg += !(d[i * n + j] >= 0);
            asym += std::fabs(d[i * n + j] - d[j * n + i]) > 1e-12 * (1 + d[i * n + j]);
        }
    }
    for (std::size_t i = 0; i < 60; ++i)
        for (std::size_t j = 0; j < 60; ++j)
            for (std::size_t k = 0; k < 60; ++k)
                tri += d[i * n + k] > d[i * n + j] + d[j * n + k] + 1e-12 * (1 + d[i * n + k]);
    if (neg) f.push_back("metric: negative distances");
    if (asym) f.push_back("metric: not symmetric");
    if (nonzero) f.push_back("metric: d(p, p) != 0");
    if (tri) f.push_back("metric: triangle inequality fails on " + std::to_string(tri) + " triples");
    std::vector<double> d1(n);
    for (std::size_t j = 0; j < n; ++j)
        m.distance(Points<const double>{&x[j], &y[j], 1}, {x[0], y[0]}, &d1[j]);
    if (!bit_equal(d1, std::vector<double>(d.begin(), d.begin() + n)))
        f.push_back("metric: distance() on a batch differs from point-by-point");
    // The float path: batch equals point-by-point, and agrees with double.
    std::vector<float> xf(x.begin(), x.end()), yf(y.begin(), y.end()), df(n), df1(n);
    m.distance(Points<const float>{xf.data(), yf.data(), n}, {x[0], y[0]}, df.data());
    for (std::size_t j = 0; j < n; ++j)
        m.distance(Points<const float>{&xf[j], &yf[j], 1}, {x[0], y[0]}, &df1[j]);
    if (!bit_equal(df, df1)) f.push_back("metric: float distance() on a batch differs from point-by-point");
    std::size_t far = 0;
    for (std::size_t j = 0; j < n; ++j) far += !(std::fabs(double(df[j]) - d[j]) <= 1e-5 * (1 + d[j]));
    if (far) f.push_back("metric: float and double distances disagree on " + std::to_string(far) + " points");
    // Keys (comparisons without the expensive part): from_key(distance_key(p)) is distance(p)
    // bit for bit, in float and double; key() is increasing and the key of 0 is 0.
    std::vector<double> kd(n);
    m.distance_key(Points<const double>{x.data(), y.data(), n}, {x[0], y[0]}, kd.data());
    m.from_key(kd.data(), n);
    std::vector<float> kf(n);
    m.distance_key(Points<const float>{xf.data(), yf.data(), n}, {x[0], y[0]}, kf.data());
    m.from_key(kf.data(), n);
    if (!bit_equal(kd, std::vector<double>(d.begin(), d.begin() + n)) || !bit_equal(kf, df))
        f.push_back("metric: from_key(distance_key(p)) differs from distance(p)");
    bool increasing = m.key(0) == 0;
    for (double r = 0.01; r < 100; r *= 1.7) increasing = increasing && m.key(r) < m.key(r * 1.7);
    if (!increasing) f.push_back("metric: key() is not increasing from key(0) = 0");
}

namespace {

// ------------------------------------------------------------------ Trap
// A trap that reports a TrapKernel promises test() to the bit (orbit-trap runs the kernel in its
// own loop): check the promise in the batch's type T, on the sample points and on circles' rims.
template <class T>
void check_trap_kernel(const Trap& t, const std::vector<double>& x0, const std::vector<double>& y0,
                       Findings& f) {
    const TrapKernel k = t.kernel();
    if (k.kind == TrapKernel::Kind::none) return;
    if (k.kind != TrapKernel::Kind::euclidean_circles || !k.cx || !k.cy || !k.r || !k.key_f || !k.key_d) {
        f.push_back("trap: kernel() reports an unknown kind or missing arrays");
        return;
    }
    std::vector<T> x(x0.begin(), x0.end()), y(y0.begin(), y0.end());
    for (std::size_t c = 0; c < k.n; ++c) // points on and next to each rim
        for (double a : {0.0, 0.7, 2.1}) {
            x.push_back(T(k.cx[c] + k.r[c] * std::cos(a)));
            y.push_back(T(k.cy[c] + k.r[c] * std::sin(a)));
        }
    const std::size_t n = x.size();
    std::vector<std::int32_t> trap(n);
    std::vector<T> ratio(n);
    t.test(Points<const T>{x.data(), y.data(), n}, trap.data(), ratio.data());
    const T below_one = std::nextafter(T(1), T(0));
    std::size_t bad = 0;
    for (std::size_t i = 0; i < n; ++i) {
        std::int32_t et = -1;
        T er = 0;
        for (std::size_t c = 0; c < k.n && et < 0; ++c) {
            const T dx = x[i] - T(k.cx[c]), dy = y[i] - T(k.cy[c]), key = dx * dx + dy * dy;
            const T lim = sizeof(T) == 4 ? T(k.key_f[c]) : T(k.key_d[c]);
            if (key < lim) et = std::int32_t(c), er = std::min(std::sqrt(key) / T(k.r[c]), below_one);
        }
        bad += trap[i] != et || (et >= 0 && std::memcmp(&ratio[i], &er, sizeof(T)) != 0);
    }
    if (bad)
        f.push_back(std::string("trap: kernel() promises Euclidean circles, but test() differs from it (") +
                    (sizeof(T) == 4 ? "float" : "double") + ") for " + std::to_string(bad) + " of " +
                    std::to_string(n) + " points");
}

} // namespace

void check_trap(const Trap& t, Findings& f) {
    Sampler smp;
    constexpr std::size_t n = 1000;
    std::vector<double> x(n), y(n);
    for (std::size_t i = 0; i < n; ++i) x[i] = smp.in(-8, 8), y[i] = smp.in(-8, 8);
    struct Result {
        std::vector<std::int32_t> trap;
        std::vector<double> ratio;
        bool operator==(const Result& o) const {
            if (trap != o.trap) return false;
            for (std::size_t i = 0; i < trap.size(); ++i)
                if (trap[i] >= 0 && std::memcmp(&ratio[i], &o.ratio[i], sizeof(double)) != 0) return false;
            return true;
        }
    };
    auto batch = [&] {
        Result r{std::vector<std::int32_t>(n), std::vector<double>(n)};
        t.test(Points<const double>{x.data(), y.data(), n}, r.trap.data(), r.ratio.data());
        return r;
    };
    const auto r = batch();
    Result r1{std::vector<std::int32_t>(n), std::vector<double>(n)};
    for (std::size_t i = 0; i < n; ++i)
        t.test(Points<const double>{&x[i], &y[i], 1}, &r1.trap[i], &r1.ratio[i]);
    if (!(r == r1)) f.push_back("trap: test() on a batch differs from point-by-point");
    {
        std::vector<float> xf(x.begin(), x.end()), yf(y.begin(), y.end()), rf(n), rf1(n);
        std::vector<std::int32_t> tf(n), tf1(n);
        t.test(Points<const float>{xf.data(), yf.data(), n}, tf.data(), rf.data());
        for (std::size_t i = 0; i < n; ++i) t.test(Points<const float>{&xf[i], &yf[i], 1}, &tf1[i], &rf1[i]);
        bool same = tf == tf1;
        for (std::size_t i = 0; i < n && same; ++i) same = tf[i] < 0 || rf[i] == rf1[i];
        if (!same) f.push_back("trap: float test() on a batch differs from point-by-point");
        for (std::size_t i = 0; i < n; ++i)
            if (tf[i] >= 0 && !(rf[i] >= 0 && rf[i] < 1)) {
                f.push_back("trap: float ratio d/r of a trapped point outside [0, 1)");
                break;
            }
    }
    if (!same_on_two_threads(batch))
        f.push_back("trap: results differ when evaluated from two threads at once");
    check_trap_kernel<double>(t, x, y, f);
    check_trap_kernel<float>(t, x, y, f);
    for (std::size_t i = 0; i < n; ++i) {
        const auto v = r.trap[i];
        if (v < -1 || v >= std::int32_t(t.count())) {
            f.push_back("trap: index out of range");
            break;
        }
        if (v >= 0 && !(r.ratio[i] >= 0 && r.ratio[i] < 1)) {
            f.push_back("trap: ratio d/r of a trapped point outside [0, 1)");
            break;
        }
    }
}

namespace {

// ------------------------------------------------------------------ NumberSystem
} // namespace

void check_numbers(const NumberSystem& ns, Findings& f) {
    Sampler smp;
    constexpr std::size_t n = 200;
    std::vector<double> ux(n), uy(n), vx(n), vy(n), ox(n), oy(n);
    for (std::size_t i = 0; i < n; ++i)
        ux[i] = smp.in(-2, 2), uy[i] = smp.in(-2, 2), vx[i] = smp.in(-2, 2), vy[i] = smp.in(-2, 2);
    ns.multiply({ux.data(), uy.data(), n}, {vx.data(), vy.data(), n}, {ox.data(), oy.data(), n});
    std::size_t bad = 0, batch = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Mat2 m = ns.multiplier({ux[i], uy[i]});
        const double px = m.a * vx[i] + m.b * vy[i], py = m.c * vx[i] + m.d * vy[i];
        bad +=
            std::fabs(px - ox[i]) + std::fabs(py - oy[i]) > 1e-9 * (1 + std::fabs(ox[i]) + std::fabs(oy[i]));
        double x, y;
        ns.multiply({&ux[i], &uy[i], 1}, {&vx[i], &vy[i], 1}, {&x, &y, 1});
        batch += !(x == ox[i] && y == oy[i]);
    }
    if (bad) f.push_back("number-system: multiplier() disagrees with multiply()");
    if (batch) f.push_back("number-system: multiply() on a batch differs from point-by-point");
}

} // namespace fp::host::detail
