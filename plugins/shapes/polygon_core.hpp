// Polygon machinery shared by the `polygon` and `star-polygon` shapes (paper 01, Sec. 3,
// Definition 2).
//
// Validation (in the user's vertex order, so that messages name the user's edges; edge i
// runs from vertex i to vertex i + 1, numbered from 0):
//   - at least 3 vertices;
//   - no repeated consecutive vertices (an edge of zero length has no direction);
//   - no two non-adjacent edges meet (crossing, touching or overlapping);
//   - non-zero area (checked after crossings: a bow-tie has zero signed area but is better
//     reported as the crossing it is);
//   - no two adjacent edges fold back onto each other (a spike of zero width).
// The polygon is then normalised to counter-clockwise order, so "inside" is to the left of
// every edge.
//
// Kernel (the points that see the whole polygon): for a simple polygon it is the
// intersection of the inner half-planes of its edges. We clip a box holding the polygon by
// each edge line (Sutherland–Hodgman; the clipped region stays convex) and take the centroid
// of the result as the default centre of inversion: it lies strictly inside the kernel
// whenever the kernel has an interior.
//
// in_kernel(o): o strictly on the inner side of every edge line, by more than 1e-12 of the
// polygon's size, so that rays from o leave every edge line transversally.
//
// inside: crossing number along the horizontal ray to +x with the half-open rule
// (y_i > py) != (y_j > py): a vertex on the ray counts once for the edge above it, and a
// horizontal edge on the ray is never counted, so rays through vertices and along
// horizontal edges give the right parity.
//
// ray_exit: for each edge solve o + t d = v_i + s e_i by Cramer's rule. For o in the kernel
// the ray crosses every edge line at most once, from inside to outside, which for a CCW
// polygon means cross(d, e_i) > 0; only those edges are candidates. We accept t > 0 and
// s in [-eps_i, 1 + eps_i] and keep the smallest t. eps_i is a few hundred ulps of the
// polygon size measured along edge i, so a ray through a vertex is caught by at least one
// of its two edges despite rounding; any hit accepted within that slack is the same
// boundary point up to rounding.
//
// The batch loops (polygon-inl.hpp) run per SIMD target, one point per lane, with the same
// operations per lane as written above.
//
// The batch geometry (in float and in double) is stored relative to a reference point near
// the polygon, and the ray origin is made relative to it in double before rounding, so a
// small polygon far from the origin keeps its precision in the float path.
#pragma once

#include "kernel_clip.hpp"
#include "polygon_kernels.hpp"
#include "polygon_simple.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace fp_shapes {

using fp::number_text;

inline std::string point_text(fp::Vec2 p) { return "(" + number_text(p.x) + ", " + number_text(p.y) + ")"; }

namespace detail {

// cross, sub and orient: polygon_simple.hpp.

/// c, known to be collinear with segment ab, lies on it (closed).
inline bool on_segment(fp::Vec2 a, fp::Vec2 b, fp::Vec2 c) {
    return std::min(a.x, b.x) <= c.x && c.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= c.y &&
           c.y <= std::max(a.y, b.y);
}

/// Closed segments p1p2 and q1q2 share at least one point.
inline bool segments_meet(fp::Vec2 p1, fp::Vec2 p2, fp::Vec2 q1, fp::Vec2 q2) {
    const double d1 = orient(q1, q2, p1), d2 = orient(q1, q2, p2);
    const double d3 = orient(p1, p2, q1), d4 = orient(p1, p2, q2);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
    return (d1 == 0 && on_segment(q1, q2, p1)) || (d2 == 0 && on_segment(q1, q2, p2)) ||
           (d3 == 0 && on_segment(p1, p2, q1)) || (d4 == 0 && on_segment(p1, p2, q2));
}

inline double signed_area(const std::vector<fp::Vec2>& v) {
    double a = 0;
    for (std::size_t i = 0, n = v.size(); i < n; ++i) a += cross(v[i], v[(i + 1) % n]);
    return a / 2;
}

/// The bounding box.
inline fp::Box bounds(const std::vector<fp::Vec2>& v) {
    fp::Box b{v[0].x, v[0].x, v[0].y, v[0].y};
    for (const auto& p : v) {
        b.xmin = std::min(b.xmin, p.x);
        b.xmax = std::max(b.xmax, p.x);
        b.ymin = std::min(b.ymin, p.y);
        b.ymax = std::max(b.ymax, p.y);
    }
    return b;
}

/// Largest side of the bounding box.
inline double extent(const std::vector<fp::Vec2>& v) {
    const fp::Box b = bounds(v);
    return std::max(b.xmax - b.xmin, b.ymax - b.ymin);
}

} // namespace detail

/// Throws fp::ParamError(param, ...) unless `v` is a simple polygon of non-zero area.
inline void validate_polygon(const std::vector<fp::Vec2>& v, const std::string& param) {
    using namespace detail;
    const std::size_t n = v.size();
    if (n < 3) throw fp::ParamError(param, "polygon needs at least 3 vertices, got " + std::to_string(n));
    const double size = extent(v);
    if (!(size > 0)) throw fp::ParamError(param, "polygon has zero area");

    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        const fp::Vec2 e = sub(v[j], v[i]);
        if (std::hypot(e.x, e.y) <= 1e-12 * size)
            throw fp::ParamError(param, "polygon has repeated consecutive vertices " +
                                            std::to_string(std::min(i, j)) + " and " +
                                            std::to_string(std::max(i, j)) + " at " + point_text(v[i]));
    }

    // Non-adjacent edges must not meet at all (edges that fold back onto their neighbour are
    // refused below; the sweep only skips testing neighbours against each other).
    if (const auto c = find_crossing(v, segments_meet))
        throw fp::ParamError(param, "polygon self-intersects: edges " + std::to_string(c->first) + " and " +
                                        std::to_string(c->second) + " cross");

    if (std::abs(signed_area(v)) <= 1e-12 * size * size) throw fp::ParamError(param, "polygon has zero area");

    // Adjacent edges meet only at their shared vertex, unless they fold back (collinear and
    // opposite), which makes a spike of zero width.
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n, k = (i + 2) % n;
        const fp::Vec2 a = sub(v[j], v[i]), b = sub(v[k], v[j]);
        const double la = std::hypot(a.x, a.y), lb = std::hypot(b.x, b.y);
        if (std::abs(cross(a, b)) <= 1e-12 * la * lb && a.x * b.x + a.y * b.y < 0)
            throw fp::ParamError(param, "polygon self-intersects: edges " + std::to_string(std::min(i, j)) +
                                            " and " + std::to_string(std::max(i, j)) + " cross");
    }
}

/// The box both kernel computations start from: the polygon's bounding box grown by `size` on
/// every side, counter-clockwise.
inline std::array<fp::Vec2, 4> start_box(const std::vector<fp::Vec2>& v, double size) {
    const fp::Box b = detail::bounds(v);
    const double x0 = b.xmin, x1 = b.xmax, y0 = b.ymin, y1 = b.ymax;
    return {{{x0 - size, y0 - size}, {x1 + size, y0 - size}, {x1 + size, y1 + size}, {x0 - size, y1 + size}}};
}

/// The kernel of a simple CCW polygon of many vertices, in O(n log n): the intersection of the
/// inner half-planes of its edges (and of a box around it) by angle, with a deque. Clipping edge
/// by edge costs O(n) per edge once the kernel has many vertices (3.5 s at 40 000).
inline std::vector<fp::Vec2> polygon_kernel_sorted(const std::vector<fp::Vec2>& v) {
    using namespace detail;
    struct Half {
        fp::Vec2 p, d; // the inner side is the left of the line p + t d
        double angle;
    };
    const double size = extent(v);
    const auto b = start_box(v, size);
    const std::size_t n = v.size();
    std::vector<Half> h;
    h.reserve(n + 4);
    auto add = [&h](fp::Vec2 p, fp::Vec2 q) {
        const fp::Vec2 d = sub(q, p);
        h.push_back({p, d, std::atan2(d.y, d.x)});
    };
    for (std::size_t i = 0; i < n; ++i) add(v[i], v[(i + 1) % n]);
    for (int i = 0; i < 4; ++i) add(b[i], b[(i + 1) % 4]);
    std::sort(h.begin(), h.end(), [](const Half& a, const Half& c) { return a.angle < c.angle; });
    auto out = [](const Half& a, fp::Vec2 q) { return cross(a.d, sub(q, a.p)) < 0; }; // strictly outside
    auto meet = [](const Half& a, const Half& c) {
        const double t = cross(c.d, sub(c.p, a.p)) / cross(c.d, a.d);
        return fp::Vec2{a.p.x + t * a.d.x, a.p.y + t * a.d.y};
    };
    std::vector<Half> dq(h.size());
    std::size_t lo = 0, hi = 0; // dq[lo, hi)
    for (const Half& c : h) {
        while (hi - lo >= 2 && out(c, meet(dq[hi - 2], dq[hi - 1]))) --hi;
        while (hi - lo >= 2 && out(c, meet(dq[lo], dq[lo + 1]))) ++lo;
        if (hi > lo && std::abs(cross(c.d, dq[hi - 1].d)) <=
                           1e-15 * std::hypot(c.d.x, c.d.y) * std::hypot(dq[hi - 1].d.x, dq[hi - 1].d.y)) {
            if (c.d.x * dq[hi - 1].d.x + c.d.y * dq[hi - 1].d.y < 0) return {}; // opposite: no area
            if (out(c, dq[hi - 1].p)) dq[hi - 1] = c; // parallel, same way: keep the inner one
            continue;
        }
        dq[hi++] = c;
    }
    while (hi - lo >= 3 && out(dq[lo], meet(dq[hi - 2], dq[hi - 1]))) --hi;
    while (hi - lo >= 3 && out(dq[hi - 1], meet(dq[lo], dq[lo + 1]))) ++lo;
    if (hi - lo < 3) return {};
    std::vector<fp::Vec2> k;
    for (std::size_t i = lo; i < hi; ++i) k.push_back(meet(dq[i], dq[i + 1 < hi ? i + 1 : lo]));
    if (k.size() < 3 || signed_area(k) <= 1e-12 * size * size) return {};
    return k;
}

/// The kernel of a simple CCW polygon by clipping a box with each edge's inner half-plane in
/// turn: O(n k) for a kernel of k vertices.
inline std::vector<fp::Vec2> polygon_kernel_clipped(const std::vector<fp::Vec2>& v) {
    using namespace detail;
    const double size = extent(v);
    const auto b = start_box(v, size);
    const std::size_t n = v.size();
    std::vector<Line> edges(n);
    for (std::size_t i = 0; i < n; ++i) edges[i] = {v[i], sub(v[(i + 1) % n], v[i])};
    const auto k = clip_by_lines(std::vector<fp::Vec2>(b.begin(), b.end()), edges);
    if (k.size() < 3 || signed_area(k) <= 1e-12 * size * size) return {};
    return k;
}

/// The kernel of a simple CCW polygon, as a convex polygon (empty when it has no interior
/// worth the name). Up to 512 vertices (every polygon of configs/) by clipping, whose kernels,
/// and so default centres, renders depend on to the bit; beyond, by the sorted intersection.
inline std::vector<fp::Vec2> polygon_kernel(const std::vector<fp::Vec2>& v) {
    return v.size() > 512 ? polygon_kernel_sorted(v) : polygon_kernel_clipped(v);
}

/// A simple polygon as a Shape. Derived plugins pass the vertices (validated or built valid)
/// and, optionally, a centre known to lie in the kernel.
class PolygonShape : public fp::Shape {
public:
    /// `vertices` must already have passed validate_polygon(). Without `centre`, the centre is
    /// the centroid of the kernel; an empty kernel (or a given centre outside it) is refused as
    /// ParamError(param, empty_kernel).
    PolygonShape(std::vector<fp::Vec2> vertices, const std::string& param, const fp::Vec2* centre = nullptr,
                 const std::string& empty_kernel = "polygon is not star-shaped: its kernel is empty") {
        if (detail::signed_area(vertices) < 0) std::reverse(vertices.begin(), vertices.end());
        v_ = std::move(vertices);
        const std::size_t n = v_.size();
        size_ = detail::extent(v_);
        kernel_tol_ = 1e-12 * size_;

        box_ = {v_[0].x, v_[0].x, v_[0].y, v_[0].y};
        for (const auto& p : v_) {
            box_.xmin = std::min(box_.xmin, p.x);
            box_.xmax = std::max(box_.xmax, p.x);
            box_.ymin = std::min(box_.ymin, p.y);
            box_.ymax = std::max(box_.ymax, p.y);
        }
        // The batch geometry is stored relative to ref_, the middle of the box rounded to float,
        // so that a small polygon far from the origin keeps its precision in float.
        ref_ = {double(float((box_.xmin + box_.xmax) / 2)), double(float((box_.ymin + box_.ymax) / 2))};

        nx_.resize(n);
        ny_.resize(n);
        fill(d_, n);
        fill(f_, n);
        for (std::size_t i = 0; i < n; ++i) {
            const fp::Vec2 a = v_[i], b = v_[(i + 1) % n];
            const double ex = b.x - a.x, ey = b.y - a.y, len = std::hypot(ex, ey);
            nx_[i] = -ey / len; // inward unit normal of a CCW polygon
            ny_[i] = ex / len;
            const double sx = ey != 0 ? ex / ey : 0; // dx/dy along the edge (crossing number)
            set(d_, i, a, ex, ey, sx, len, std::numeric_limits<double>::epsilon());
            set(f_, i, a, ex, ey, sx, len, double(std::numeric_limits<float>::epsilon()));
        }

        if (centre) {
            centre_ = *centre;
        } else {
            const auto k = polygon_kernel(v_);
            if (k.empty()) throw fp::ParamError(param, empty_kernel);
            centre_ = centroid(k);
        }
        if (!in_kernel(centre_)) throw fp::ParamError(param, empty_kernel);
    }

    fp::Vec2 centre() const override { return centre_; }

    bool in_kernel(fp::Vec2 o) const override {
        for (std::size_t i = 0; i < v_.size(); ++i)
            if (!(nx_[i] * (o.x - v_[i].x) + ny_[i] * (o.y - v_[i].y) > kernel_tol_)) return false;
        return true;
    }

    fp::Box bounds() const override { return box_; }

    /// The vertices, counter-clockwise (closed implicitly: the last joins the first).
    std::vector<fp::Vec2> outline(std::size_t) const override { return v_; }

    void inside(fp::Points<const float> p, unsigned char* out) const override { inside_t(p, out); }
    void inside(fp::Points<const double> p, unsigned char* out) const override { inside_t(p, out); }
    void ray_exit(fp::Vec2 o, fp::Points<const float> d, float* t) const override { ray_t(o, d, t); }
    void ray_exit(fp::Vec2 o, fp::Points<const double> d, double* t) const override { ray_t(o, d, t); }

    const std::vector<fp::Vec2>& vertices() const { return v_; }

private:
    // The loops run in polygon-inl.hpp, per SIMD target: per lane, the operations of the
    // crossing number and the ray exit described at the top of this file.
    template <class T>
    void inside_t(fp::Points<const T> p, unsigned char* out) const {
        polygon_inside(view<T>(), T(ref_.x), T(ref_.y), p, out); // exact: ref_ is a float
    }

    template <class T>
    void ray_t(fp::Vec2 o, fp::Points<const T> d, T* t) const {
        polygon_ray(view<T>(), T(o.x - ref_.x), T(o.y - ref_.y), d, t);
    }

    /// Per-edge data in the precision of the batch; vx, vy hold n + 1 entries (closed).
    template <class T>
    struct Edges {
        std::size_t n = 0;
        std::vector<T> vx, vy, ex, ey, sx, s_lo, s_hi;
    };

    template <class T>
    static void fill(Edges<T>& e, std::size_t n) {
        e.n = n;
        e.vx.resize(n + 1);
        e.vy.resize(n + 1);
        for (auto* a : {&e.ex, &e.ey, &e.sx, &e.s_lo, &e.s_hi}) a->resize(n);
    }

    template <class T>
    void set(Edges<T>& e, std::size_t i, fp::Vec2 a, double ex, double ey, double sx, double len,
             double ulp) {
        const std::size_t n = v_.size();
        e.vx[i] = T(a.x - ref_.x);
        e.vy[i] = T(a.y - ref_.y);
        if (i == 0) {
            e.vx[n] = e.vx[0];
            e.vy[n] = e.vy[0];
        }
        e.ex[i] = T(ex);
        e.ey[i] = T(ey);
        e.sx[i] = T(sx);
        // Slack on the edge parameter s: 256 ulps of the polygon size, measured along this edge.
        const double slack = 256 * ulp * size_ / len;
        e.s_lo[i] = T(-slack);
        e.s_hi[i] = T(1 + slack);
    }

    template <class T>
    EdgeView<T> view() const {
        const Edges<T>& e = [this]() -> const Edges<T>& {
            if constexpr (std::is_same_v<T, float>)
                return f_;
            else
                return d_;
        }();
        return {e.n,         e.vx.data(), e.vy.data(),   e.ex.data(),
                e.ey.data(), e.sx.data(), e.s_lo.data(), e.s_hi.data()};
    }

    std::vector<fp::Vec2> v_; ///< CCW
    std::vector<double> nx_, ny_;
    Edges<double> d_;
    Edges<float> f_;
    fp::Box box_;
    fp::Vec2 ref_, centre_;
    double size_ = 0, kernel_tol_ = 0;
};

} // namespace fp_shapes
