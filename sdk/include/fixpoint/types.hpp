// Small value types used across the SDK.
#pragma once

#include <cstdint>
#include <string_view>

namespace fp {

struct Vec2 {
    double x = 0, y = 0;
    friend bool operator==(const Vec2&, const Vec2&) = default;
};

/// Linear RGB in [0, 1] per channel.
struct Rgb {
    float r = 0, g = 0, b = 0;
    friend bool operator==(const Rgb&, const Rgb&) = default;
};

/// Axis-aligned box [xmin, xmax] x [ymin, ymax].
struct Box {
    double xmin = 0, xmax = 0, ymin = 0, ymax = 0;
};

/// 2x2 matrix, row major: [a b; c d]. Multiplying by a q-system number is such a map.
struct Mat2 {
    double a = 1, b = 0, c = 0, d = 1;
};

constexpr Mat2 operator+(const Mat2& p, const Mat2& q) {
    return {p.a + q.a, p.b + q.b, p.c + q.c, p.d + q.d};
}
constexpr Mat2 operator-(const Mat2& p, const Mat2& q) {
    return {p.a - q.a, p.b - q.b, p.c - q.c, p.d - q.d};
}
constexpr Vec2 operator*(const Mat2& m, Vec2 v) { return {m.a * v.x + m.b * v.y, m.c * v.x + m.d * v.y}; }

/// The interfaces a plugin can implement. The order is part of the ABI.
enum class Kind : std::uint32_t {
    Shape,
    Transform,
    IterationScheme,
    NumberSystem,
    Trap,
    Metric,
    Colourer,
    Renderer,
    Filter, ///< (ABI 17)
};

/// Kebab-case name of a kind, as written on the command line (`--kind shape`).
constexpr std::string_view kind_name(Kind k) {
    switch (k) {
    case Kind::Shape: return "shape";
    case Kind::Transform: return "transform";
    case Kind::IterationScheme: return "iteration-scheme";
    case Kind::NumberSystem: return "number-system";
    case Kind::Trap: return "trap";
    case Kind::Metric: return "metric";
    case Kind::Colourer: return "colourer";
    case Kind::Renderer: return "renderer";
    case Kind::Filter: return "filter";
    }
    return "?";
}

constexpr int kind_count = 9;

} // namespace fp
