// Paper 05's converse construction (host/converse.hpp).
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/tools/converse.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/transform.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

namespace fp::host {

namespace {

/// Barycentric coordinates of q in the triangle p (d: twice its signed area).
std::array<double, 3> barycentric(const std::array<Vec2, 3>& p, double d, Vec2 q) {
    const double l2 = ((q.x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (q.y - p[0].y)) / d;
    const double l3 = ((p[1].x - p[0].x) * (q.y - p[0].y) - (q.x - p[0].x) * (p[1].y - p[0].y)) / d;
    return {1 - l2 - l3, l2, l3};
}

} // namespace

std::vector<Subdivision3> subdivision_matrices(const Registry& reg, const std::array<Vec2, 3>& p,
                                               const std::vector<std::string>& maps) {
    const double d = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
    const double size = std::max({std::fabs(p[1].x - p[0].x), std::fabs(p[1].y - p[0].y),
                                  std::fabs(p[2].x - p[0].x), std::fabs(p[2].y - p[0].y)});
    if (!std::isfinite(d) || !(std::fabs(d) > 1e-12 * size * size))
        throw InputError("--points: the three control points lie on a line: they must span a triangle");
    std::vector<Subdivision3> out;
    for (std::size_t i = 0; i < maps.size(); ++i) {
        const std::string name = "map " + std::to_string(i + 1);
        const auto t = std::dynamic_pointer_cast<const Transform>(
            build_from_text(reg, Kind::Transform, maps[i], "<" + name + ">", "transform"));
        // The control points, and a fourth point inside the triangle that is none of them.
        const std::array<double, 3> w4 = {0.2, 0.3, 0.5};
        double x[4], y[4];
        for (int j = 0; j < 3; ++j) x[j] = p[j].x, y[j] = p[j].y;
        const Vec2 q = {w4[0] * p[0].x + w4[1] * p[1].x + w4[2] * p[2].x,
                        w4[0] * p[0].y + w4[1] * p[1].y + w4[2] * p[2].y};
        x[3] = q.x, y[3] = q.y;
        t->apply(Points<double>{x, y, 4}, nullptr);
        Subdivision3 s;
        for (int j = 0; j < 3; ++j) {
            if (!std::isfinite(x[j]) || !std::isfinite(y[j]))
                throw InputError(name + ": the map sends control point " + std::to_string(j + 1) +
                                 " to infinity");
            const auto a = barycentric(p, d, {x[j], y[j]});
            for (int k = 0; k < 3; ++k) s[std::size_t(3 * j + k)] = a[std::size_t(k)];
        }
        // Affine: the fourth point's image is the same combination of the control points' images.
        const double ex = w4[0] * x[0] + w4[1] * x[1] + w4[2] * x[2],
                     ey = w4[0] * y[0] + w4[1] * y[1] + w4[2] * y[2];
        const double scale = std::max({1.0, std::fabs(ex), std::fabs(ey), size});
        if (!(std::fabs(x[3] - ex) <= 1e-9 * scale && std::fabs(y[3] - ey) <= 1e-9 * scale))
            throw InputError(name + ": not an affine map: it sends (" + number_text(q.x) + ", " +
                             number_text(q.y) + ") to (" + number_text(x[3]) + ", " + number_text(y[3]) +
                             "), not to (" + number_text(ex) + ", " + number_text(ey) +
                             "): subdivision matrices represent affine maps only");
        out.push_back(s);
    }
    return out;
}

} // namespace fp::host
