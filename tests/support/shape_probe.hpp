// One ray exit or inside test of a shape at a time, as the shape tests ask them (a batch of
// one: the kernels' own path, with its padding).
#pragma once

#include <fixpoint/fixpoint.hpp>

namespace fp::test {

inline double ray(const fp::Shape& s, fp::Vec2 o, fp::Vec2 d) {
    double t = 0;
    s.ray_exit(o, fp::Points<const double>{&d.x, &d.y, 1}, &t);
    return t;
}

inline float ray_f(const fp::Shape& s, fp::Vec2 o, fp::Vec2 d) {
    const float dx = float(d.x), dy = float(d.y);
    float t = 0;
    s.ray_exit(o, fp::Points<const float>{&dx, &dy, 1}, &t);
    return t;
}

inline bool inside(const fp::Shape& s, double x, double y) {
    unsigned char out = 2;
    s.inside(fp::Points<const double>{&x, &y, 1}, &out);
    return out == 1;
}

inline bool inside_f(const fp::Shape& s, float x, float y) {
    unsigned char out = 2;
    s.inside(fp::Points<const float>{&x, &y, 1}, &out);
    return out == 1;
}

} // namespace fp::test
