// twirl: a transform written per point: each point turns about `centre` by an angle that
// grows with its squared distance from it (like flam3's swirl variation, which fixpoint
// ships as `swirl`),
//
//     T(p) = c + R(s |p - c|^2) (p - c),    R(t) the rotation by t radians.
//
// The transform example of docs/writing-a-scheme.md, built out of tree by
// tests/external-scheme/run.sh.
#include <fixpoint/fixpoint.hpp>

#include <cmath>

namespace {

class Twirl final : public fp::TransformBase<Twirl> {
public:
    static constexpr fp::ParamSpec params[] = {
        fp::param::vec2("centre", "the point the plane turns about").def("[0, 0]"),
        fp::param::real("strength", "s: radians of turn per unit of squared distance").def("1"),
    };
    explicit Twirl(const fp::ParamBag& p) : c_(p.vec2("centre")), s_(p.real("strength")) {}

    // One point, in float or double: TransformBase writes the batch loops around it.
    template <class T>
    void map_pt(T& x, T& y) const {
        const T dx = x - T(c_.x), dy = y - T(c_.y);
        const T t = T(s_) * (dx * dx + dy * dy);
        const T cs = std::cos(t), sn = std::sin(t);
        x = T(c_.x) + (cs * dx - sn * dy);
        y = T(c_.y) + (sn * dx + cs * dy);
    }

private:
    fp::Vec2 c_;
    double s_;
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Twirl>(fp::Kind::Transform, "twirl",
                                    "turns each point about the centre by strength * (squared distance)",
                                    Twirl::params))
