// The kernel of a star-shaped set as the intersection of half-planes, by clipping a convex
// region with each line in turn (Sutherland–Hodgman; the region stays convex): the polygons'
// kernel (their edges, polygon_core.hpp) and the bezier set's sampled one (its tangents, for
// the default centre), with the centroid that serves as a default centre of inversion.
#pragma once

#include <fixpoint/types.hpp>

#include <cmath>
#include <cstddef>
#include <vector>

namespace fp_shapes {

/// A directed line a + s e; its inner half-plane is on the left.
struct Line {
    fp::Vec2 a, e;
};

/// The convex polygon `k` (counter-clockwise) clipped by the inner half-plane of every line,
/// in order (empty once nothing is left). A point on a line counts as inside it.
inline std::vector<fp::Vec2> clip_by_lines(std::vector<fp::Vec2> k, const std::vector<Line>& lines) {
    std::vector<fp::Vec2> next;
    for (std::size_t i = 0; i < lines.size() && !k.empty(); ++i) {
        const fp::Vec2 a = lines[i].a, e = lines[i].e;
        const double len = std::hypot(e.x, e.y);
        auto dist = [&](fp::Vec2 q) { return (e.x * (q.y - a.y) - e.y * (q.x - a.x)) / len; }; // > 0: inner
        next.clear();
        for (std::size_t j = 0, m = k.size(); j < m; ++j) {
            const fp::Vec2 p = k[j], q = k[(j + 1) % m];
            const double dp = dist(p), dq = dist(q);
            if (dp >= 0) next.push_back(p);
            if ((dp >= 0) != (dq >= 0)) {
                const double s = dp / (dp - dq);
                next.push_back({p.x + s * (q.x - p.x), p.y + s * (q.y - p.y)});
            }
        }
        k.swap(next);
    }
    return k;
}

/// Area centroid of a convex polygon with non-zero area.
inline fp::Vec2 centroid(const std::vector<fp::Vec2>& k) {
    // Relative to the first vertex, to keep the sums small.
    const fp::Vec2 o = k[0];
    double a = 0, cx = 0, cy = 0;
    for (std::size_t i = 1; i + 1 < k.size(); ++i) {
        const fp::Vec2 p{k[i].x - o.x, k[i].y - o.y}, q{k[i + 1].x - o.x, k[i + 1].y - o.y};
        const double c = p.x * q.y - p.y * q.x;
        a += c;
        cx += (p.x + q.x) * c;
        cy += (p.y + q.y) * c;
    }
    return {o.x + cx / (3 * a), o.y + cy / (3 * a)};
}

} // namespace fp_shapes
