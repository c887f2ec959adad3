// TransformBase: write a map as one inline per-point function
//
//   template <class T> void map_pt(T& x, T& y) const;
//
// and get the masked and unmasked batch loops in float and double, inlined (no call per
// point; the loops vectorise where the function allows).
#pragma once

#include <fixpoint/transform.hpp>

namespace fp {

template <class D>
class TransformBase : public Transform {
public:
    void apply(Points<float> p, Mask mask) const override { run(p, mask); }
    void apply(Points<double> p, Mask mask) const override { run(p, mask); }

private:
    template <class T>
    void run(Points<T> p, Mask mask) const {
        const D& self = static_cast<const D&>(*this);
        if (!mask) {
            for (std::size_t i = 0; i < p.n; ++i) self.map_pt(p.x[i], p.y[i]);
            return;
        }
        for (std::size_t i = 0; i < p.n; ++i) {
            T x = p.x[i], y = p.y[i];
            self.map_pt(x, y);
            p.x[i] = mask[i] ? x : p.x[i];
            p.y[i] = mask[i] ? y : p.y[i];
        }
    }
};

} // namespace fp
