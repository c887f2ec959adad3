// real: the real numbers, the default arithmetic of the iteration schemes. A parameter a acts
// on the plane as a I; a q-system number (b != 0) is refused by the schemes.
#include <fixpoint/fixpoint.hpp>

namespace {

class Real final : public fp::NumberSystem {
public:
    explicit Real(const fp::ParamBag&) {}
    fp::Mat2 multiplier(fp::Vec2 a) const override { return {a.x, 0, 0, a.x}; }
    void multiply(fp::Points<const double> u, fp::Points<const double> v,
                  fp::Points<double> out) const override {
        // Componentwise: (x, y) are two real numbers side by side.
        for (std::size_t i = 0; i < u.n; ++i) {
            out.x[i] = u.x[i] * v.x[i];
            out.y[i] = u.x[i] * v.y[i];
        }
    }
    bool divide(fp::Vec2 u, fp::Vec2 v, fp::Vec2& out) const override {
        if (v.x == 0) return false;
        out = {u.x / v.x, u.y / v.x};
        return true;
    }
    bool is_real() const override { return true; }
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Real>(fp::Kind::NumberSystem, "real",
                                   "the real numbers (parameters act as a I)"))
