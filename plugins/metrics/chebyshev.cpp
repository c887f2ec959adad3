// chebyshev — the Chebyshev (l_infinity) metric of paper 04, eq. (15):
// d(a, b) = max(|ax - bx|, |ay - by|). Its circles are axis-aligned squares (Fig. 2b).
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace {

class Chebyshev final : public fp::Metric {
public:
    explicit Chebyshev(const fp::ParamBag&) {}

    void distance(fp::Points<const float> p, fp::Vec2 c, float* out) const override { run(p, c, out); }
    void distance(fp::Points<const double> p, fp::Vec2 c, double* out) const override { run(p, c, out); }

private:
    template <class T>
    static void run(fp::Points<const T> p, fp::Vec2 c, T* __restrict out) {
        const T cx = T(c.x), cy = T(c.y);
        const T* __restrict x = p.x;
        const T* __restrict y = p.y;
        for (std::size_t i = 0; i < p.n; ++i) out[i] = std::max(std::fabs(x[i] - cx), std::fabs(y[i] - cy));
    }
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Chebyshev>(fp::Kind::Metric, "chebyshev",
                                        "the Chebyshev metric max(|dx|, |dy|) (paper 04, eq. (15))"))
