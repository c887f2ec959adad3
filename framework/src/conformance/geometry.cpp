// The conformance checks of shapes and transforms (conformance_detail.hpp).
#include "conformance_detail.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp::host::detail {

namespace {

// ------------------------------------------------------------------ Shape
} // namespace

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

namespace {

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

} // namespace

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

} // namespace fp::host::detail
