// lp — the l_p metric of paper 04, eq. (14): d(a, b) = (|ax - bx|^p + |ay - by|^p)^(1/p), p >= 1.
//
// p = 2 is the Euclidean metric of the original orbit-trap method, p = 1 the taxicab metric.
// `p: .inf` is accepted and is the Chebyshev metric max(|dx|, |dy|) (the limit p -> infinity,
// paper 04 Fig. 6f; the same as the `chebyshev` plugin), so a sweep over p stays one plugin.
// p < 1 is refused: then the formula breaks the triangle inequality and is no metric.
//
// p = 1, 2 and infinity have closed forms; other p compute m ((|dx| / m)^p + (|dy| / m)^p)^(1/p)
// with m = max(|dx|, |dy|), which neither overflows nor underflows for large p. distance() is
// the distance itself (orbit traps colour by d / r); for comparisons p = 2 offers the key d^2
// (Metric::distance_key, no root) and takes roots of the few keys that need them (from_key),
// with the same bits as distance(). Other p use the distance as key.
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

// The Euclidean metric compares squared distances (distance_key: no root) and takes the root
// only of the keys of caught points (from_key). Both vectorise: plugins build with
// -fno-math-errno, so std::sqrt is the correctly rounded instruction of every instruction set,
// every path gives the same bits, distance() is exactly from_key(distance_key()), and a batch
// equals its points one by one.
template <class T>
void squared(const T* __restrict x, const T* __restrict y, T cx, T cy, T* __restrict out, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
        const T dx = x[i] - cx, dy = y[i] - cy;
        out[i] = dx * dx + dy * dy;
    }
}

template <class T>
void sqrt_inplace(T* __restrict v, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) v[i] = std::sqrt(v[i]);
}

constexpr fp::ParamSpec params[] = {
    fp::param::real("p", "the exponent p >= 1 of eq. (14): 1 taxicab, 2 Euclidean, .inf Chebyshev")
        .def("2")
        .nonfinite(),
};

class Lp final : public fp::Metric {
public:
    explicit Lp(const fp::ParamBag& b) : p_(b.real("p")) {
        if (std::isnan(p_) || p_ < 1)
            throw fp::ParamError(
                "p", "the lp metric needs p >= 1 (for p < 1 the triangle inequality fails), got " +
                         fp::number_text(p_));
        mode_ = p_ == 1 ? Mode::one : p_ == 2 ? Mode::two : std::isinf(p_) ? Mode::inf : Mode::general;
    }

    void distance(fp::Points<const float> p, fp::Vec2 c, float* out) const override { run(p, c, out); }
    void distance(fp::Points<const double> p, fp::Vec2 c, double* out) const override { run(p, c, out); }

    // p = 2: the key is d^2; otherwise the distance itself.
    void distance_key(fp::Points<const float> p, fp::Vec2 c, float* out) const override {
        run_key(p, c, out);
    }
    void distance_key(fp::Points<const double> p, fp::Vec2 c, double* out) const override {
        run_key(p, c, out);
    }
    double key(double d) const override { return mode_ == Mode::two ? d * d : d; }
    void from_key(float* k, std::size_t n) const override {
        if (mode_ == Mode::two) sqrt_inplace(k, n);
    }
    void from_key(double* k, std::size_t n) const override {
        if (mode_ == Mode::two) sqrt_inplace(k, n);
    }
    // p = 2: squared() and sqrt_inplace() are exactly Metric::Kind::euclidean's formulas.
    Kind kind() const override { return mode_ == Mode::two ? Kind::euclidean : Kind::other; }

private:
    enum class Mode { one, two, inf, general };

    template <class T>
    void run_key(fp::Points<const T> p, fp::Vec2 c, T* out) const {
        if (mode_ == Mode::two) return squared(p.x, p.y, T(c.x), T(c.y), out, p.n);
        run(p, c, out);
    }

    template <class T>
    void run(fp::Points<const T> p, fp::Vec2 c, T* __restrict out) const {
        const T cx = T(c.x), cy = T(c.y);
        const T* __restrict x = p.x;
        const T* __restrict y = p.y;
        switch (mode_) {
        case Mode::one:
            for (std::size_t i = 0; i < p.n; ++i) out[i] = std::fabs(x[i] - cx) + std::fabs(y[i] - cy);
            return;
        case Mode::two:
            squared(x, y, cx, cy, out, p.n);
            sqrt_inplace(out, p.n);
            return;
        case Mode::inf:
            for (std::size_t i = 0; i < p.n; ++i)
                out[i] = std::max(std::fabs(x[i] - cx), std::fabs(y[i] - cy));
            return;
        case Mode::general: {
            const T e = T(p_), inv = T(1) / T(p_);
            for (std::size_t i = 0; i < p.n; ++i) {
                const T ax = std::fabs(x[i] - cx), ay = std::fabs(y[i] - cy);
                const T m = std::max(ax, ay);
                out[i] = m > 0 ? m * std::pow(std::pow(ax / m, e) + std::pow(ay / m, e), inv) : T(0);
            }
            return;
        }
        }
    }

    double p_;
    Mode mode_ = Mode::two;
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Lp>(fp::Kind::Metric, "lp",
                                 "the l_p metric (|dx|^p + |dy|^p)^(1/p), p >= 1 (paper 04, eq. (14))",
                                 params)
                    .with_example("{p: 1.5}"))
