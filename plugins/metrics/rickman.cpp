// rickman — Rickman's rug metric of paper 04, eq. (16): d(a, b) = |ax - bx| + |ay - by|^gamma,
// 0 < gamma < 1 (Deza & Deza, Encyclopedia of Distances). |t|^gamma is a metric on the line
// for gamma in (0, 1] (a concave function of |t| vanishing only at 0), so the sum is one on the
// plane; gamma = 1 would be the taxicab metric (use lp with p = 1), and the paper takes the
// open interval, so both ends are refused. Its unit circle is |x| + |y|^gamma = 1 (Fig. 2c).
#include <fixpoint/fixpoint.hpp>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

constexpr fp::ParamSpec params[] = {
    fp::param::real("gamma", "the exponent gamma of eq. (16), in the open interval (0, 1)").def("0.5"),
};

class Rickman final : public fp::Metric {
public:
    explicit Rickman(const fp::ParamBag& b) : gamma_(b.real("gamma")) {
        if (!(gamma_ > 0 && gamma_ < 1))
            throw fp::ParamError("gamma",
                                 "Rickman's rug metric needs gamma in the open interval (0, 1), got " +
                                     fp::number_text(gamma_));
    }

    void distance(fp::Points<const float> p, fp::Vec2 c, float* out) const override { run(p, c, out); }
    void distance(fp::Points<const double> p, fp::Vec2 c, double* out) const override { run(p, c, out); }

private:
    template <class T>
    void run(fp::Points<const T> p, fp::Vec2 c, T* __restrict out) const {
        const T cx = T(c.x), cy = T(c.y), g = T(gamma_);
        const T* __restrict x = p.x;
        const T* __restrict y = p.y;
        for (std::size_t i = 0; i < p.n; ++i)
            out[i] = std::fabs(x[i] - cx) + std::pow(std::fabs(y[i] - cy), g);
    }

    double gamma_;
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Rickman>(
    fp::Kind::Metric, "rickman", "Rickman's rug metric |dx| + |dy|^gamma, 0 < gamma < 1 (paper 04, eq. (16))",
    params))
