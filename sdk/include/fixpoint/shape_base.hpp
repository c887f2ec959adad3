// ShapeBase: write a shape as two inline per-point functions; the batch loops, in float and
// double, are generated here and inlined, so there is no call per point.
//
//   template <class T> bool inside_pt(T x, T y) const;
//   template <class T> T ray_exit_pt(T ox, T oy, T dx, T dy) const;
#pragma once

#include <fixpoint/shape.hpp>

namespace fp {

template <class D>
class ShapeBase : public Shape {
public:
    void inside(Points<const float> p, unsigned char* out) const override { inside_t(p, out); }
    void inside(Points<const double> p, unsigned char* out) const override { inside_t(p, out); }
    void ray_exit(Vec2 o, Points<const float> d, float* t) const override { ray_t(o, d, t); }
    void ray_exit(Vec2 o, Points<const double> d, double* t) const override { ray_t(o, d, t); }

private:
    template <class T>
    void inside_t(Points<const T> p, unsigned char* out) const {
        const D& self = static_cast<const D&>(*this);
        for (std::size_t i = 0; i < p.n; ++i) out[i] = self.inside_pt(p.x[i], p.y[i]) ? 1 : 0;
    }
    template <class T>
    void ray_t(Vec2 o, Points<const T> d, T* t) const {
        const D& self = static_cast<const D&>(*this);
        const T ox = T(o.x), oy = T(o.y);
        for (std::size_t i = 0; i < d.n; ++i) t[i] = self.ray_exit_pt(ox, oy, d.x[i], d.y[i]);
    }
};

} // namespace fp
