// The conformance suite.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/conformance/conformance.hpp>
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include "conformance_detail.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <thread>

namespace fp::host {

namespace {

using detail::Findings;
using detail::Sampler;

const std::string not_std_exception = "an exception that is not a std::exception (throw fp::InputError or "
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

// ------------------------------------------------------------------ Shape
void check_shape(const Shape& s, Findings& f) {
    const Box b = s.bounds();
    const double w = b.xmax - b.xmin, h = b.ymax - b.ymin;
    if (!(w > 0 && h > 0)) {
        f.push_back("shape: bounds() is empty");
        return;
    }
    Sampler smp;
    constexpr std::size_t n = 1000;
    std::vector<double> x(n), y(n), dx(n), dy(n);
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = smp.in(b.xmin - 0.2 * w, b.xmax + 0.2 * w);
        y[i] = smp.in(b.ymin - 0.2 * h, b.ymax + 0.2 * h);
        const double a = smp.in(0, 2 * M_PI);
        dx[i] = std::cos(a);
        dy[i] = std::sin(a);
    }
    const Vec2 o = s.centre();
    if (!s.in_kernel(o)) f.push_back("shape: centre() is not in the kernel");
    auto inside_batch = [&] {
        std::vector<unsigned char> out(n);
        s.inside(Points<const double>{x.data(), y.data(), n}, out.data());
        return out;
    };
    auto ray_batch = [&] {
        std::vector<double> t(n);
        s.ray_exit(o, Points<const double>{dx.data(), dy.data(), n}, t.data());
        return t;
    };
    const auto ins = inside_batch();
    const auto ts = ray_batch();
    std::vector<unsigned char> ins1(n);
    std::vector<double> ts1(n);
    for (std::size_t i = 0; i < n; ++i) {
        s.inside(Points<const double>{&x[i], &y[i], 1}, &ins1[i]);
        s.ray_exit(o, Points<const double>{&dx[i], &dy[i], 1}, &ts1[i]);
    }
    if (ins != ins1) f.push_back("shape: inside() on a batch differs from point-by-point");
    if (!bit_equal(ts, ts1)) f.push_back("shape: ray_exit() on a batch differs from point-by-point");
    if (!same_on_two_threads(inside_batch) || !same_on_two_threads(ray_batch))
        f.push_back("shape: results differ when evaluated from two threads at once");
    // The inside test agrees with the boundary: just inside and just outside the ray's hit.
    std::size_t disagree = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!(ts[i] > 0) || !std::isfinite(ts[i])) {
            ++disagree;
            continue;
        }
        double px[2] = {o.x + 0.98 * ts[i] * dx[i], o.x + 1.02 * ts[i] * dx[i]};
        double py[2] = {o.y + 0.98 * ts[i] * dy[i], o.y + 1.02 * ts[i] * dy[i]};
        unsigned char in2[2];
        s.inside(Points<const double>{px, py, 2}, in2);
        if (in2[0] != 1 || in2[1] != 0) ++disagree;
    }
    if (disagree)
        f.push_back("shape: inside() disagrees with ray_exit() along " + std::to_string(disagree) +
                    " of 1000 rays");
    // Float path close to the double path.
    std::vector<float> fx(dx.begin(), dx.end()), fy(dy.begin(), dy.end()), ft(n);
    s.ray_exit(o, Points<const float>{fx.data(), fy.data(), n}, ft.data());
    std::size_t off = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (!(std::fabs(ft[i] - ts[i]) <= 1e-3 * std::fabs(ts[i]) + 1e-6)) ++off;
    if (off)
        f.push_back("shape: float ray_exit() differs from double in " + std::to_string(off) +
                    " of 1000 rays");
}

// ------------------------------------------------------------------ Transform
// A map that reports a KnownKernel promises apply() and contains() to the bit (renderers run the
// kernel in their own loops instead): check the promise in the batch's type T.
template <class T>
void check_known_kernel(const Transform& t, const std::vector<double>& x0, const std::vector<double>& y0,
                        Findings& f) {
    const KnownKernel k = t.kernel();
    using Kind = KnownKernel::Kind;
    if (k.kind == Kind::none) return;
    if (k.kind != Kind::circle_inversion && k.kind != Kind::affine && k.kind != Kind::gumowski_mira) {
        f.push_back("transform: kernel() reports an unknown kind");
        return;
    }
    const std::size_t n = x0.size();
    std::vector<T> x(x0.begin(), x0.end()), y(y0.begin(), y0.end());
    std::vector<unsigned char> in(n, 0);
    if (k.kind == Kind::circle_inversion) t.contains(Points<const T>{x.data(), y.data(), n}, in.data());
    t.apply(Points<T>{x.data(), y.data(), n}, nullptr);
    const T cx = T(k.cx), cy = T(k.cy), r2 = T(k.r2);
    T c[6];
    for (int i = 0; i < 6; ++i) c[i] = T(k.c[i]);
    std::size_t bad = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const T px = T(x0[i]), py = T(y0[i]);
        T ex = 0, ey = 0;
        unsigned char ein = 0;
        if (k.kind == Kind::circle_inversion) {
            const T dx = px - cx, dy = py - cy, d2 = dx * dx + dy * dy, s = r2 / d2;
            ex = cx + s * dx, ey = cy + s * dy, ein = d2 < r2 ? 1 : 0;
        } else if (k.kind == Kind::affine) {
            ex = (c[0] * px + c[1] * py) + c[4];
            ey = (c[2] * px + c[3] * py) + c[5];
        } else {
            auto g = [&](T u) {
                const T u2 = u * u;
                return c[1] * u + (c[2] * u2) / (T(1) + u2);
            };
            ex = (py + (c[0] * (T(1) - (T(0.05) * py) * py)) * py) + g(px);
            ey = -px + g(ex);
        }
        bad += std::memcmp(&ex, &x[i], sizeof(T)) != 0 || std::memcmp(&ey, &y[i], sizeof(T)) != 0 ||
               in[i] != ein;
    }
    static const char* const names[] = {"", "inversion in a circle", "an affine map",
                                        "the Gumowski-Mira map"};
    if (bad)
        f.push_back(std::string("transform: kernel() promises ") + names[std::size_t(k.kind)] +
                    ", but apply() or contains() differs from it (" + (sizeof(T) == 4 ? "float" : "double") +
                    ") for " + std::to_string(bad) + " of " + std::to_string(n) + " points");
}

void check_transform(const Transform& t, Findings& f) {
    const Box b = t.sample_domain();
    Sampler smp;
    constexpr std::size_t n = 1000;
    std::vector<double> x0(n), y0(n);
    for (std::size_t i = 0; i < n; ++i) {
        x0[i] = smp.in(b.xmin, b.xmax);
        y0[i] = smp.in(b.ymin, b.ymax);
    }
    auto apply = [&](Points<double> p) { t.apply(p, nullptr); };
    auto batch = [&] { return map_batch_and_pointwise(x0, y0, apply).batch; };
    const MapResults res = map_batch_and_pointwise(x0, y0, apply);
    const std::vector<double>& r = res.batch;
    if (!bit_equal(r, res.pointwise))
        f.push_back("transform: apply() on a batch differs from point-by-point");
    if (!same_on_two_threads(batch))
        f.push_back("transform: results differ when evaluated from two threads at once");
    std::size_t nonfinite = 0;
    for (double v : r) nonfinite += !std::isfinite(v);
    if (nonfinite)
        f.push_back("transform: " + std::to_string(nonfinite) +
                    " non-finite outputs for finite inputs in the sample domain");
    // Mask: inactive points stay.
    {
        std::vector<double> x = x0, y = y0;
        std::vector<unsigned char> m(n);
        for (std::size_t i = 0; i < n; ++i) m[i] = i % 3 == 0;
        t.apply(Points<double>{x.data(), y.data(), n}, m.data());
        std::size_t bad = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const bool moved_right =
                m[i] ? (x[i] == r[i] && y[i] == r[n + i]) : (x[i] == x0[i] && y[i] == y0[i]);
            bad += !moved_right;
        }
        if (bad) f.push_back("transform: the mask is not honoured for " + std::to_string(bad) + " points");
    }
    // Float path.
    {
        std::vector<float> x(x0.begin(), x0.end()), y(y0.begin(), y0.end());
        t.apply(Points<float>{x.data(), y.data(), n}, nullptr);
        std::size_t off = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const double sc = 1 + std::fabs(r[i]) + std::fabs(r[n + i]);
            if (!(std::fabs(x[i] - r[i]) <= 1e-3 * sc && std::fabs(y[i] - r[n + i]) <= 1e-3 * sc)) ++off;
        }
        if (off > n / 100)
            f.push_back("transform: the float path differs from double for " + std::to_string(off) +
                        " of 1000 points");
    }
    if (t.is_involution()) {
        std::vector<double> x(r.begin(), r.begin() + n), y(r.begin() + n, r.end());
        t.apply(Points<double>{x.data(), y.data(), n}, nullptr);
        std::size_t bad = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const double sc = 1 + std::fabs(x0[i]) + std::fabs(y0[i]);
            if (!(std::fabs(x[i] - x0[i]) <= 1e-9 * sc && std::fabs(y[i] - y0[i]) <= 1e-9 * sc)) ++bad;
        }
        if (bad)
            f.push_back("transform: declared an involution, but T(T(p)) != p for " + std::to_string(bad) +
                        " of 1000 points");
    }
    if (t.has_region()) {
        std::vector<unsigned char> c(n), c1(n);
        t.contains(Points<const double>{x0.data(), y0.data(), n}, c.data());
        for (std::size_t i = 0; i < n; ++i) t.contains(Points<const double>{&x0[i], &y0[i], 1}, &c1[i]);
        if (c != c1) f.push_back("transform: contains() on a batch differs from point-by-point");
    }
    check_known_kernel<double>(t, x0, y0, f);
    check_known_kernel<float>(t, x0, y0, f);
}

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

// ------------------------------------------------------------------ NumberSystem
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

// ------------------------------------------------------------------ Colourer
// Rows [row0, row0 + n) of h (n clipped to its height) as a histogram of their own, in h's form
// (bins, last colours, or hit counts alone).
Histogram rows_of(const Histogram& h, int row0, int n) {
    Histogram part;
    part.width = h.width;
    part.height = std::min(n, h.height - row0);
    const auto b0 = std::ptrdiff_t(row0) * h.width, nb = std::ptrdiff_t(part.height) * h.width;
    auto cut = [&](const auto& from, auto& to) {
        if (!from.empty()) to.assign(from.begin() + b0, from.begin() + b0 + nb);
    };
    cut(h.bins, part.bins);
    cut(h.last, part.last);
    cut(h.hits, part.hits);
    return part;
}

// h shaded as a render in strips of `strip` rows shades it: the strips summarised one after
// another, then each shaded with resolve_rows() (on 2 workers) into its rows of rgb.
void resolve_in_strips(const Colourer& c, const Histogram& h, int strip, Rgb background, float* rgb) {
    HistogramSummary whole;
    whole.begin(h.width, h.height);
    for (int row0 = 0; row0 < h.height; row0 += strip) whole.add(rows_of(h, row0, strip), row0);
    Runtime rt(2, nullptr);
    for (int row0 = 0; row0 < h.height; row0 += strip)
        c.resolve_rows(rows_of(h, row0, strip), row0, whole, background,
                       rgb + 3 * std::size_t(row0) * std::size_t(h.width), rt);
}

// A colourer whose reads_hits_only() is true may be given hit counts alone (Histogram::hits,
// `bins` empty): each resolve entry point must then give the pixels of the same bins with
// their colour sums 0.
void check_hits_only(const Colourer& c, const Histogram& big, Findings& f) {
    if (c.needs_colour()) {
        f.push_back("colourer: reads_hits_only() is true but needs_colour() too");
        return;
    }
    Histogram zero = big, alone;
    for (HistBin& b : zero.bins) b.r = b.g = b.b = 0;
    alone.width = big.width;
    alone.height = big.height;
    for (const HistBin& b : big.bins) alone.hits.push_back(b.hits);
    const Rgb bg{0.1f, 0.2f, 0.3f};
    std::vector<float> want(big.bins.size() * 3), got(want.size());
    c.resolve(zero, bg, want.data());
    auto differs = [&] { return std::memcmp(want.data(), got.data(), want.size() * sizeof(float)) != 0; };
    c.resolve(alone, bg, got.data());
    if (differs()) {
        f.push_back("colourer: resolve() of hit counts alone differs from resolve() of the bins");
        return;
    }
    Runtime rt(2, nullptr);
    c.resolve_parallel(alone, bg, got.data(), rt);
    if (differs()) {
        f.push_back("colourer: resolve_parallel() of hit counts alone differs from resolve() of the bins");
        return;
    }
    if (!c.resolves_rows()) return;
    resolve_in_strips(c, alone, 7, bg, got.data());
    if (differs())
        f.push_back("colourer: resolve_rows() of hit counts alone differs from resolve() of the bins");
}

// Orbit-trap colouring (paper 04): batch == point by point, values in [0, 1], untrapped samples
// take the given background exactly, the same on two threads.
void check_trap_colours(const Colourer& c, Findings& f) {
    constexpr std::size_t n = 301;
    Sampler smp;
    std::vector<std::int32_t> trap(n);
    std::vector<float> ratio(n);
    std::vector<std::uint32_t> it(n);
    for (std::size_t i = 0; i < n; ++i) {
        trap[i] = std::int32_t(i % 5) - 1;
        ratio[i] = i % 7 == 0 ? 0.0f : float(smp.in(0, 1));
        if (ratio[i] >= 1) ratio[i] = 0.5f;
        it[i] = std::uint32_t(1 + i % 100);
    }
    const Rgb bg{0.1f, 0.2f, 0.3f};
    auto batch = [&](const Rgb* background) {
        std::vector<float> rgb(3 * n, -1.0f);
        c.colour_hits(trap.data(), ratio.data(), it.data(), n, background, rgb.data());
        return rgb;
    };
    const auto all = batch(&bg), own = batch(nullptr);
    std::vector<float> one(3 * n);
    for (std::size_t i = 0; i < n; ++i) c.colour_hits(&trap[i], &ratio[i], &it[i], 1, &bg, &one[3 * i]);
    if (all != one) f.push_back("colourer: colour_hits() on a batch differs from point-by-point");
    std::size_t bad = 0, background = 0;
    for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) bad += !(all[3 * i + k] >= 0 && all[3 * i + k] <= 1);
        for (int k = 0; k < 3; ++k) bad += !(own[3 * i + k] >= 0 && own[3 * i + k] <= 1);
        if (trap[i] < 0)
            background += !(all[3 * i] == bg.r && all[3 * i + 1] == bg.g && all[3 * i + 2] == bg.b);
    }
    if (bad) f.push_back("colourer: colour_hits() gives values outside [0, 1]");
    if (background) f.push_back("colourer: colour_hits() does not give untrapped samples the background");
    if (!same_on_two_threads([&] { return batch(&bg); }))
        f.push_back("colourer: colour_hits() differs when evaluated from two threads at once");
}

void check_colourer(const Colourer& c, Findings& f) {
    constexpr std::size_t n = 257;
    const Rgb maps[3] = {{1, 0, 0}, {0, 1, 0}, {0.2f, 0.3f, 1}};
    Sampler smp;
    std::vector<std::uint32_t> idx(n);
    std::vector<float> r0(n), g0(n), b0(n);
    for (std::size_t i = 0; i < n; ++i) {
        idx[i] = std::uint32_t(i % 3);
        r0[i] = float(smp.in(0, 1)), g0[i] = float(smp.in(0, 1)), b0[i] = float(smp.in(0, 1));
    }
    auto batch = [&] {
        std::vector<float> r = r0, g = g0, b = b0;
        c.update(idx.data(), {r.data(), g.data(), b.data(), n}, maps, nullptr);
        r.insert(r.end(), g.begin(), g.end());
        r.insert(r.end(), b.begin(), b.end());
        return r;
    };
    const auto all = batch();
    std::vector<float> one(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        float r = r0[i], g = g0[i], b = b0[i];
        c.update(&idx[i], {&r, &g, &b, 1}, maps, nullptr);
        one[i] = r, one[n + i] = g, one[2 * n + i] = b;
    }
    if (all != one) f.push_back("colourer: update() on a batch differs from point-by-point");
    if (const ColourRule rule = c.colour_rule(); rule != ColourRule::none) {
        // The promise of colour_rule(), bit for bit (renderers apply the rule themselves).
        std::size_t bad = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const Rgb m = maps[idx[i]];
            const float e[3] = {rule == ColourRule::map ? m.r : (r0[i] + m.r) * 0.5f,
                                rule == ColourRule::map ? m.g : (g0[i] + m.g) * 0.5f,
                                rule == ColourRule::map ? m.b : (b0[i] + m.b) * 0.5f};
            for (int ch = 0; ch < 3; ++ch) bad += std::memcmp(&e[ch], &all[ch * n + i], sizeof(float)) != 0;
        }
        if (rule != ColourRule::map && rule != ColourRule::average)
            f.push_back("colourer: colour_rule() reports an unknown rule");
        else if (bad)
            f.push_back("colourer: colour_rule() promises " +
                        std::string(rule == ColourRule::map ? "the map's colour" : "the running average") +
                        ", but update() differs from it in " + std::to_string(bad) + " of " +
                        std::to_string(3 * n) + " values");
    }
    if (!same_on_two_threads(batch))
        f.push_back("colourer: results differ when evaluated from two threads at once");
    Histogram h;
    h.resize(16, 16);
    for (std::size_t i = 0; i < h.bins.size(); ++i) {
        const std::uint64_t hits = i % 5 == 0 ? 0 : 1 + (i * 7919) % 1000;
        h.bins[i] = {hits, hits * (i % 3 == 0 ? colour_scale : 0), hits * colour_scale / 2,
                     hits * colour_scale / 4};
    }
    auto resolve = [&] {
        std::vector<float> px(h.bins.size() * 3);
        c.resolve(h, Rgb{0.1f, 0.2f, 0.3f}, px.data());
        return px;
    };
    const auto px = resolve();
    std::size_t bad = 0;
    for (float v : px) bad += !(v >= 0 && v <= 1);
    if (bad) f.push_back("colourer: resolve() gives values outside [0, 1]");
    if (px[0] != 0.1f || px[1] != 0.2f || px[2] != 0.3f)
        f.push_back("colourer: an empty bin does not take the background");
    if (!same_on_two_threads(resolve))
        f.push_back("colourer: resolve() differs when evaluated from two threads at once");
    {
        // Renderers call resolve_parallel(): it must give resolve()'s bytes on any number of
        // workers. 53 rows: several pieces of rows, the last one short.
        Histogram big;
        big.resize(37, 53);
        for (std::size_t i = 0; i < big.bins.size(); ++i) {
            const std::uint64_t hits = i % 7 == 0 ? 0 : 1 + (i * 104729) % 70000;
            big.bins[i] = {hits, hits * (i % 2 ? colour_scale : colour_scale / 3), hits * colour_scale / 5,
                           0};
        }
        std::vector<float> serial(big.bins.size() * 3), par(big.bins.size() * 3);
        c.resolve(big, Rgb{0.1f, 0.2f, 0.3f}, serial.data());
        for (unsigned threads : {1u, 2u, 3u}) {
            Runtime rt(threads, nullptr);
            c.resolve_parallel(big, Rgb{0.1f, 0.2f, 0.3f}, par.data(), rt);
            if (std::memcmp(serial.data(), par.data(), serial.size() * sizeof(float)) != 0) {
                f.push_back("colourer: resolve_parallel() with " + std::to_string(threads) + " worker" +
                            (threads == 1 ? "" : "s") + " differs from resolve()");
                break;
            }
        }
        // A render in strips (a histogram too large for memory) summarises the strips one after
        // another, then shades each with resolve_rows(): resolve()'s bytes, row for row.
        if (c.resolves_rows()) {
            for (int strip : {1, 7, 20}) {
                resolve_in_strips(c, big, strip, Rgb{0.1f, 0.2f, 0.3f}, par.data());
                if (std::memcmp(serial.data(), par.data(), serial.size() * sizeof(float)) != 0) {
                    f.push_back("colourer: resolve_rows() in strips of " + std::to_string(strip) +
                                " row(s) differs from resolve()");
                    break;
                }
            }
        }
        if (c.reads_hits_only()) check_hits_only(c, big, f);
    }
    if (c.colours_trap_hits()) check_trap_colours(c, f);
}

// ------------------------------------------------------------------ Renderer
// A renderer that streams its rows (beyond the memory budget) must give render()'s pixels, in
// order, each row once, within the least budget it names: the host streams exactly then.
namespace {
class CollectedRows final : public RowSink {
public:
    explicit CollectedRows(std::size_t width) : width_(width) {}
    void rows(int y0, int rows, const float* rgb) override {
        if (y0 != next_ || rows < 0) in_order_ = false;
        pixels_.insert(pixels_.end(), rgb, rgb + std::size_t(std::max(rows, 0)) * width_ * 3);
        next_ = y0 + std::max(rows, 0);
    }
    std::vector<float> pixels_;
    bool in_order_ = true;

private:
    std::size_t width_;
    int next_ = 0;
};
} // namespace

void check_streamed_rows(const Renderer& r, const std::vector<float>& whole, Findings& f) {
    for (unsigned threads : {1u, 2u}) {
        Runtime rt(threads, nullptr);
        rt.set_memory_budget(r.memory_within(threads, 0)); // the least it can do with
        RenderStats st;
        CollectedRows rows(std::size_t(r.width()));
        try {
            r.render_rows(rt, st, rows);
        } catch (const std::exception& e) {
            f.push_back("renderer: render_rows() within memory_within()'s least budget failed: " +
                        std::string(e.what()));
            return;
        }
        if (!rows.in_order_) f.push_back("renderer: render_rows() gave its rows out of order");
        if (rows.pixels_ != whole) {
            f.push_back("renderer: render_rows() on " + std::to_string(threads) +
                        " thread(s) differs from render()");
            return;
        }
    }
}

void check_renderer(const Renderer& r, Findings& f) {
    if (r.width() <= 0 || r.height() <= 0) f.push_back("renderer: non-positive size");
    if (r.memory_bytes(2) == 0) f.push_back("renderer: memory_bytes() is 0");
    if (std::uint64_t(r.width()) * std::uint64_t(r.height()) > 512u * 512u) {
        f.push_back("renderer: the example is too large for the conformance suite (at most 512x512)");
        return;
    }
    auto render = [&](unsigned threads) {
        Runtime rt(threads, nullptr);
        RenderStats st;
        Image img = r.render(rt, st);
        return img.pixels;
    };
    const auto a = render(1), b = render(2);
    if (a.size() != std::size_t(r.width()) * std::size_t(r.height()) * 3)
        f.push_back("renderer: image has the wrong size");
    if (a != b) f.push_back("renderer: 1 and 2 threads give different images");
    std::size_t bad = 0, lit = 0;
    for (float v : a) bad += !std::isfinite(v), lit += v > 0;
    if (bad) f.push_back("renderer: non-finite pixel values");
    if (!lit) f.push_back("renderer: the example renders a black image");
    if (r.streams_rows()) check_streamed_rows(r, a, f);
}

bool snake_or_paper(const char* s) {
    if (!s || !*s) return false;
    for (const char* c = s; *c; ++c)
        if (!std::isalnum((unsigned char)*c) && *c != '_') return false;
    return true;
}

// The example (the plugin's own unless `given`) with `type:` added, as a node.
CNode example_node(const PluginDescriptor& d, const std::string* given) {
    CNode n = given ? parse_yaml(*given, "--example")
                    : parse_yaml(d.example ? d.example : "{}", std::string("<example of ") + d.name + ">");
    if (n.type == CNode::Type::Null) n = map_node();
    n.keys.insert(n.keys.begin(), {"type", scalar_node(d.name)});
    n.key_marks.insert(n.key_marks.begin(), n.mark);
    return n;
}

// Expect validation or construction of `n` to be refused with a bad-input error.
void expect_refused(const Registry& reg, const PluginDescriptor& d, const CNode& n, const std::string& what,
                    Findings& f) {
    const std::size_t before = f.size();
    try {
        auto t = validate(reg, d.kind, n, d.name);
        build(reg, *t);
        f.push_back("parameters: " + what + " was accepted");
    } catch (const InputError&) {
        // refused as it should be
    } catch (const std::exception& e) {
        f.push_back("parameters: " + what + " gave a non-parameter error: " + e.what());
    } catch (...) {
        f.push_back("parameters: " + what + " threw " + not_std_exception);
    }
    f.record("parameters: " + what + " is refused", before);
}

void set_param(CNode& n, const std::string& key, CNode v) {
    if (CNode* p = n.find(key))
        *p = std::move(v);
    else {
        n.keys.emplace_back(key, std::move(v));
        n.key_marks.push_back(n.mark);
    }
}

// The kind's checks on an object. Schemes record their checks one by one; the other kinds
// record one check for all of theirs (their findings say which failed).
void check_kind(const Object& obj, Kind kind, Findings& f) {
    const std::size_t before = f.size();
    switch (kind) {
    case Kind::Shape: check_shape(dynamic_cast<const Shape&>(obj), f); break;
    case Kind::Transform: check_transform(dynamic_cast<const Transform&>(obj), f); break;
    case Kind::IterationScheme: detail::check_scheme(dynamic_cast<const IterationScheme&>(obj), f); return;
    case Kind::NumberSystem: check_numbers(dynamic_cast<const NumberSystem&>(obj), f); break;
    case Kind::Trap: check_trap(dynamic_cast<const Trap&>(obj), f); break;
    case Kind::Metric: check_metric(dynamic_cast<const Metric&>(obj), f); break;
    case Kind::Colourer: check_colourer(dynamic_cast<const Colourer&>(obj), f); break;
    case Kind::Renderer: check_renderer(dynamic_cast<const Renderer&>(obj), f); break;
    }
    f.record(std::string(kind_name(kind)) + ": the kind's checks", before);
}

// check_kind(), with what the plugin throws reported as a finding.
void checks_of(const Object& obj, Kind kind, Findings& f) {
    try {
        check_kind(obj, kind, f);
    } catch (const std::exception& err) {
        f.check("checks: the plugin does not throw", std::string("checks: the plugin threw: ") + err.what());
    } catch (...) {
        f.check("checks: the plugin does not throw", "checks: the plugin threw " + not_std_exception);
    }
}

// A scheme's behaviour depends on its parameters more than a shape's: besides the example,
// it is checked with a few values drawn from the declared ranges (finite Real and Int
// ranges; sequences, which have no range, as periodic lists of weights in [0, 1]). Each
// draw goes through validate and build like a config; a draw the plugin refuses with a
// bad-input error (values fine alone but not together) is skipped. Findings name the draw.
void check_draws(const Registry& reg, const PluginDescriptor& d, const CNode& ex, Findings& f) {
    Rng rng = chain_stream(20261121, 13);
    // On a grid of a thousandth of the range: short to print, and as good a sample.
    auto draw = [&](double lo, double hi) { return lo + (hi - lo) * uniform_below(rng, 1001) / 1000; };
    constexpr int draws = 3;
    for (int k = 0; k < draws; ++k) {
        CNode n = ex;
        std::string what;
        for (std::uint32_t i = 0; i < d.n_params; ++i) {
            const ParamSpec& s = d.params[i];
            CNode v;
            if ((s.type == ParamType::Real || s.type == ParamType::Int) && std::isfinite(s.lo) &&
                std::isfinite(s.hi)) {
                double x = draw(s.lo, s.hi);
                if (s.type == ParamType::Int)
                    x = std::clamp(std::floor(x + 0.5), std::ceil(s.lo), std::floor(s.hi));
                if ((s.lo_open && x <= s.lo) || (s.hi_open && x >= s.hi)) x = 0.5 * (s.lo + s.hi);
                v = scalar_node(format_real(x));
            } else if (s.type == ParamType::Sequence) {
                // Three values: a list of two reads as one q-number.
                v = seq_node();
                for (int j = 0; j < 3; ++j) v.items.push_back(scalar_node(format_real(draw(0, 1))));
            } else {
                continue;
            }
            what += std::string(what.empty() ? "" : ", ") + s.name + ": " +
                    (v.is_seq()
                         ? "[" + v.items[0].scalar + ", " + v.items[1].scalar + ", " + v.items[2].scalar + "]"
                         : v.scalar);
            set_param(n, s.name, std::move(v));
        }
        if (what.empty()) return; // nothing to draw
        std::shared_ptr<const Object> obj;
        try {
            obj = build(reg, *validate(reg, d.kind, n, d.name));
        } catch (const InputError&) {
            continue; // refused as a whole: not a finding
        } catch (const std::exception& err) {
            f.push_back("build: drawn parameters (" + what + ") gave a non-parameter error: " + err.what());
            continue;
        } catch (...) {
            f.push_back("build: drawn parameters (" + what + ") threw " + not_std_exception);
            continue;
        }
        // A finding the example already gave is not repeated; new ones say the draw.
        Findings g;
        checks_of(*obj, d.kind, g);
        for (auto& c : g.checks) f.checks.push_back({c.name + " (drawn: " + what + ")", c.passed});
        for (auto& m : g.failures)
            if (std::find(f.failures.begin(), f.failures.end(), m) == f.failures.end())
                f.push_back(m + " (with drawn parameters " + what + ")");
    }
}

} // namespace

std::vector<std::string> check_object(const Object& obj, Kind kind) {
    Findings f;
    check_kind(obj, kind, f);
    return f.failures;
}

std::vector<std::string> run_conformance(const Registry& reg, const PluginEntry& e) {
    return conformance_report(reg, e).findings;
}

ConformanceReport conformance_report(const Registry& reg, const PluginEntry& e, const std::string* example) {
    Findings f;
    const PluginDescriptor& d = *e.desc;
    const std::size_t before_meta = f.size();
    if (!d.summary || !*d.summary) f.push_back("metadata: no summary");
    if (!d.version || !*d.version) f.push_back("metadata: no version");
    for (std::uint32_t i = 0; i < d.n_params; ++i) {
        const ParamSpec& s = d.params[i];
        const std::string name = s.name ? s.name : "";
        if (!snake_or_paper(s.name)) f.push_back("metadata: parameter name '" + name + "' is not snake_case");
        if (!s.doc || !*s.doc) f.push_back("metadata: parameter '" + name + "' has no doc line");
        if (s.type == ParamType::Objects)
            for (std::uint32_t j = 0; j < s.n_item_params; ++j)
                if (!s.item_params[j].doc || !*s.item_params[j].doc)
                    f.push_back("metadata: item parameter '" + std::string(s.item_params[j].name) +
                                "' has no doc line");
    }
    f.record("metadata: summary, version, parameter names and docs", before_meta);
    // Builds from its example.
    const std::size_t before_build = f.size();
    CNode ex;
    std::shared_ptr<const Object> obj;
    try {
        ex = example_node(d, example);
        auto t = validate(reg, d.kind, ex, d.name);
        obj = build(reg, *t);
    } catch (const std::exception& err) {
        f.push_back(std::string("build: the example does not build: ") + err.what());
    } catch (...) {
        f.push_back("build: the example does not build: it threw " + not_std_exception);
    }
    f.record("build: the example builds", before_build);
    if (!obj) return {f.failures, f.checks};
    // Bad parameters are refused.
    {
        CNode n = ex;
        set_param(n, "no_such_parameter_zz", scalar_node("1"));
        expect_refused(reg, d, n, "an unknown parameter", f);
    }
    for (std::uint32_t i = 0; i < d.n_params; ++i) {
        const ParamSpec& s = d.params[i];
        const std::string nm = s.name;
        {
            CNode n = ex;
            CNode wrong = s.type == ParamType::Object || s.type == ParamType::String
                              ? map_node()
                              : scalar_node("not-a-value", true);
            if (s.type == ParamType::Object)
                wrong.keys.emplace_back("x", scalar_node("1")), wrong.key_marks.resize(1);
            set_param(n, nm, wrong);
            expect_refused(reg, d, n, "a value of the wrong type for '" + nm + "'", f);
        }
        const bool numeric = s.type == ParamType::Real || s.type == ParamType::Int;
        if (numeric && std::isfinite(s.lo)) {
            CNode n = ex;
            set_param(n, nm, scalar_node(format_real(s.lo_open ? s.lo : s.lo - 1)));
            expect_refused(reg, d, n, "a value below the range of '" + nm + "'", f);
        }
        if (numeric && std::isfinite(s.hi)) {
            CNode n = ex;
            set_param(n, nm, scalar_node(format_real(s.hi_open ? s.hi : s.hi + 1)));
            expect_refused(reg, d, n, "a value above the range of '" + nm + "'", f);
        }
        if ((numeric || s.type == ParamType::Sequence) && !s.allow_nonfinite) {
            CNode n = ex;
            set_param(n, nm, scalar_node(".nan"));
            expect_refused(reg, d, n, "NaN for '" + nm + "'", f);
        }
        if ((s.type == ParamType::Vec2 || s.type == ParamType::Reals) && !s.allow_nonfinite) {
            CNode n = ex;
            CNode v = seq_node();
            const std::size_t len =
                s.type == ParamType::Vec2 ? 2 : std::max<std::size_t>({1, s.count, s.min_count});
            for (std::size_t k = 0; k < len; ++k) v.items.push_back(scalar_node(".nan"));
            set_param(n, nm, v);
            expect_refused(reg, d, n, "NaN in '" + nm + "'", f);
        }
    }
    checks_of(*obj, d.kind, f);
    if (d.kind == Kind::IterationScheme) check_draws(reg, d, ex, f);
    return {f.failures, f.checks};
}

} // namespace fp::host
