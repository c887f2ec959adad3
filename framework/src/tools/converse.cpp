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

/// The map of `text` as a transform ("map i" in messages).
std::shared_ptr<const Transform> map_of(const Registry& reg, const std::string& text,
                                        const std::string& name) {
    return std::dynamic_pointer_cast<const Transform>(
        build_from_text(reg, Kind::Transform, text, "<" + name + ">", "transform"));
}

/// f at the points (x, y), in place; throws naming the map when one goes to infinity.
void apply_at(const Transform& t, std::vector<double>& x, std::vector<double>& y, const std::string& name) {
    t.apply(Points<double>{x.data(), y.data(), x.size()}, nullptr);
    for (std::size_t j = 0; j < x.size(); ++j)
        if (!std::isfinite(x[j]) || !std::isfinite(y[j]))
            throw InputError(name + ": the map sends a point to infinity");
}

/// x solving x A = b for the n x n matrix A (row major), by Gaussian elimination with partial
/// pivoting on A^T; false when a pivot falls below 1e-12 of A's largest entry.
bool solve_left(std::vector<double> A, std::vector<double> b, std::size_t n, std::vector<double>& x) {
    double big = 0;
    for (double v : A) big = std::max(big, std::fabs(v));
    std::vector<double> T(n * n); // A^T: x A = b is A^T x^T = b^T
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) T[i * n + j] = A[j * n + i];
    for (std::size_t c = 0; c < n; ++c) {
        std::size_t piv = c;
        for (std::size_t r = c + 1; r < n; ++r)
            if (std::fabs(T[r * n + c]) > std::fabs(T[piv * n + c])) piv = r;
        if (!(std::fabs(T[piv * n + c]) > 1e-12 * big)) return false;
        for (std::size_t k = 0; k < n; ++k) std::swap(T[c * n + k], T[piv * n + k]);
        std::swap(b[c], b[piv]);
        for (std::size_t r = c + 1; r < n; ++r) {
            const double m = T[r * n + c] / T[c * n + c];
            for (std::size_t k = c; k < n; ++k) T[r * n + k] -= m * T[c * n + k];
            b[r] -= m * b[c];
        }
    }
    x.assign(n, 0);
    for (std::size_t c = n; c-- > 0;) {
        double v = b[c];
        for (std::size_t k = c + 1; k < n; ++k) v -= T[c * n + k] * x[k];
        x[c] = v / T[c * n + c];
    }
    return true;
}

std::string point_text(double x, double y) { return "(" + number_text(x) + ", " + number_text(y) + ")"; }

/// Four control points lifted with z = x y (converse.hpp).
std::vector<SubdivisionMatrix> quad_matrices(const Registry& reg, const std::vector<Vec2>& p,
                                             const std::vector<std::string>& maps) {
    std::vector<double> P;
    for (const Vec2& q : p) P.insert(P.end(), {q.x, q.y, q.x * q.y, 1.0});
    std::vector<double> Pt(16), probe;
    for (std::size_t r = 0; r < 4; ++r)
        for (std::size_t c = 0; c < 4; ++c) Pt[c * 4 + r] = P[r * 4 + c];
    if (!solve_left(P, {0, 0, 0, 1}, 4, probe))
        throw InputError("--points: the four control points lifted to (x, y, x y) lie in a plane (P is "
                         "singular): all four on a line or on a curve a x + b y + c x y + d = 0 (two lines "
                         "parallel to the axes, or a hyperbola with such asymptotes)");
    double size = 0;
    for (const Vec2& q : p) size = std::max({size, std::fabs(q.x - p[0].x), std::fabs(q.y - p[0].y)});
    std::vector<SubdivisionMatrix> out;
    for (std::size_t i = 0; i < maps.size(); ++i) {
        const std::string name = "map " + std::to_string(i + 1);
        const auto t = map_of(reg, maps[i], name);
        // The control points, and two more inside their box that are none of them.
        const Vec2 lo{std::min({p[0].x, p[1].x, p[2].x, p[3].x}), std::min({p[0].y, p[1].y, p[2].y, p[3].y})};
        const std::array<Vec2, 2> extra = {Vec2{lo.x + 0.3 * size, lo.y + 0.6 * size},
                                           Vec2{lo.x + 0.7 * size, lo.y + 0.2 * size}};
        std::vector<double> x, y;
        for (const Vec2& q : p) x.push_back(q.x), y.push_back(q.y);
        for (const Vec2& q : extra) x.push_back(q.x), y.push_back(q.y);
        apply_at(*t, x, y, name);
        // The affine map through the images of three control points that span the plane, and
        // the bilinear one through all four: which one the others follow.
        std::vector<double> wx, wy;
        solve_left(Pt, {x[0], x[1], x[2], x[3]}, 4, wx); // P wx = x': x' = wx . (x, y, x y, 1) at the p_j
        solve_left(Pt, {y[0], y[1], y[2], y[3]}, 4, wy);
        const auto bil = [&](const std::vector<double>& w, Vec2 q) {
            return w[0] * q.x + w[1] * q.y + w[2] * q.x * q.y + w[3];
        };
        double scale = std::max(1.0, size);
        for (std::size_t j = 0; j < x.size(); ++j)
            scale = std::max({scale, std::fabs(x[j]), std::fabs(y[j])});
        const double tol = 1e-9 * scale;
        bool bilinear = true;
        for (std::size_t k = 0; k < 2; ++k)
            bilinear = bilinear && std::fabs(bil(wx, extra[k]) - x[4 + k]) <= tol &&
                       std::fabs(bil(wy, extra[k]) - y[4 + k]) <= tol;
        const bool affine =
            bilinear && std::fabs(wx[2]) * size * size <= tol && std::fabs(wy[2]) * size * size <= tol;
        if (!affine) {
            if (bilinear)
                throw InputError(
                    name + ": a bilinear map, not an affine one (x' has x y coefficient " +
                    number_text(wx[2]) + ", y' " + number_text(wy[2]) +
                    "): on control points lifted with z = x y its "
                    "subdivision map agrees with it on the control points and their children, but "
                    "the grandchildren's z is no longer their x y, so the polygons leave its images "
                    "from there (docs/papers.md); subdivision maps of the plane are affine");
            throw InputError(name + ": not an affine map: it sends " + point_text(extra[0].x, extra[0].y) +
                             " to " + point_text(x[4], y[4]) + ", not to " +
                             point_text(bil(wx, extra[0]), bil(wy, extra[0])) +
                             ": subdivision matrices represent affine maps only");
        }
        // S = L P^-1: row j the weights of the lifted image (f(p_j), f_x f_y, 1) in the lifted p_k.
        SubdivisionMatrix S;
        for (std::size_t j = 0; j < 4; ++j) {
            std::vector<double> row;
            solve_left(P, {x[j], y[j], x[j] * y[j], 1.0}, 4, row);
            S.insert(S.end(), row.begin(), row.end());
        }
        out.push_back(S);
    }
    return out;
}

} // namespace

std::vector<SubdivisionMatrix> subdivision_matrices(const Registry& reg, const std::vector<Vec2>& points,
                                                    const std::vector<std::string>& maps) {
    if (points.size() == 4) return quad_matrices(reg, points, maps);
    if (points.size() != 3)
        throw InputError(
            "--points: " + std::to_string(points.size()) +
            " control points have no lift the subdivision plugin knows: give 3 (a triangle) or 4 "
            "(lifted with z = x y)");
    const std::array<Vec2, 3> p = {points[0], points[1], points[2]};
    const double d = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
    const double size = std::max({std::fabs(p[1].x - p[0].x), std::fabs(p[1].y - p[0].y),
                                  std::fabs(p[2].x - p[0].x), std::fabs(p[2].y - p[0].y)});
    if (!std::isfinite(d) || !(std::fabs(d) > 1e-12 * size * size))
        throw InputError("--points: the three control points lie on a line: they must span a triangle");
    std::vector<SubdivisionMatrix> out;
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
        SubdivisionMatrix s(9);
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
