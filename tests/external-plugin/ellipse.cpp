// ellipse: a Shape plugin built outside the fixpoint tree, against the installed SDK only.
//
// The ellipse with semi-axes a, b, rotated by `rotation` about its centre. It is convex, so
// its kernel is its interior. Ray exit from o: with q = o - c and the ray o + t d in the
// ellipse's own frame (u = R^T q, v = R^T d), solve (u + t v)^T D (u + t v) = 1 with
// D = diag(1/a^2, 1/b^2) for its positive root.
//
// Written per point (inside_pt, ray_exit_pt) and vectorised with the SDK's SIMD layer
// (fixpoint/simd.hpp): the batch loops are compiled once per instruction set and dispatched at
// run time, as fast as a built-in shape. This file is compiled once per target by Highway's
// foreach_target (below): the class is kept to the first pass by ELLIPSE_CLASS.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/simd.hpp>

#include <cmath>

#ifndef ELLIPSE_CLASS
#define ELLIPSE_CLASS
namespace {

class Ellipse final : public fp::Shape {
public:
    explicit Ellipse(const fp::ParamBag& p)
        : c_(p.vec2("centre")), a_(p.real("a")), b_(p.real("b")), rot_(p.real("rotation")),
          cs_(std::cos(rot_)), sn_(std::sin(rot_)) {}

    fp::Vec2 centre() const override { return c_; }
    bool in_kernel(fp::Vec2 o) const override { return inside_pt(o.x, o.y); }
    fp::Box bounds() const override {
        const double ex = std::hypot(a_ * cs_, b_ * sn_), ey = std::hypot(a_ * sn_, b_ * cs_);
        return {c_.x - ex, c_.x + ex, c_.y - ey, c_.y + ey};
    }
    std::vector<fp::Vec2> outline(std::size_t samples) const override {
        std::vector<fp::Vec2> out;
        for (std::size_t i = 0; i < samples; ++i) {
            const double t = 2 * M_PI * double(i) / double(samples);
            const double u = a_ * std::cos(t), v = b_ * std::sin(t);
            out.push_back({c_.x + cs_ * u - sn_ * v, c_.y + sn_ * u + cs_ * v});
        }
        return out;
    }

    FIXPOINT_SIMD_SHAPE_OVERRIDES

    template <class T>
    FIXPOINT_INLINE bool inside_pt(T x, T y) const {
        const T dx = x - T(c_.x), dy = y - T(c_.y);
        const T u = T(cs_) * dx + T(sn_) * dy, v = -T(sn_) * dx + T(cs_) * dy;
        return u * u / T(a_ * a_) + v * v / T(b_ * b_) < T(1);
    }

    template <class T>
    FIXPOINT_INLINE T ray_exit_pt(T ox, T oy, T dx, T dy) const {
        const T qx = ox - T(c_.x), qy = oy - T(c_.y);
        const T ux = T(cs_) * qx + T(sn_) * qy, uy = -T(sn_) * qx + T(cs_) * qy;
        const T vx = T(cs_) * dx + T(sn_) * dy, vy = -T(sn_) * dx + T(cs_) * dy;
        const T ia = T(1 / (a_ * a_)), ib = T(1 / (b_ * b_));
        const T A = vx * vx * ia + vy * vy * ib;
        const T B = ux * vx * ia + uy * vy * ib;        // half the linear coefficient
        const T C = ux * ux * ia + uy * uy * ib - T(1); // < 0 inside
        // Positive root of A t^2 + 2 B t + C, in the form without cancellation.
        const T s = std::sqrt(B * B - A * C);
        return B > T(0) ? -C / (B + s) : (s - B) / A;
    }

private:
    fp::Vec2 c_;
    double a_, b_, rot_, cs_, sn_;
};

constexpr fp::ParamSpec params[] = {
    fp::param::vec2("centre", "centre of the ellipse").def("[0, 0]"),
    fp::param::real("a", "semi-axis along the (rotated) x axis").def("1").above(0),
    fp::param::real("b", "semi-axis along the (rotated) y axis").def("0.5").above(0),
    fp::param::real("rotation", "rotation about the centre, in radians").def("0"),
};

} // namespace
#endif // ELLIPSE_CLASS

// The batch loops, once per instruction set.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ellipse.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include <fixpoint/simd-inl.hpp>

FIXPOINT_SIMD_SHAPE(ellipse_kernels, Ellipse)

#if HWY_ONCE
FIXPOINT_SIMD_SHAPE_DISPATCH(ellipse_kernels, Ellipse)

FIXPOINT_PLUGIN(fp::describe<Ellipse>(fp::Kind::Shape, "ellipse",
                                      "an ellipse (example of an out-of-tree plugin)", params))
#endif
