// The bezier set's geometry in scalar double, run once per set (and once per new centre of
// inversion): segments, area, the exact kernel test, and the pieces the kernels take
// (bezier/curve.hpp). bezier.cpp's header gives the reasoning.
#pragma once

#include "bezier/curve.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

namespace fp_bezier {

inline double cross(fp::Vec2 a, fp::Vec2 b) { return a.x * b.y - a.y * b.x; }
inline double dot(fp::Vec2 a, fp::Vec2 b) { return a.x * b.x + a.y * b.y; }
inline fp::Vec2 sub(fp::Vec2 a, fp::Vec2 b) { return {a.x - b.x, a.y - b.y}; }

/// The squared distance from the origin to the segment ab.
inline double segment_distance2(fp::Vec2 a, fp::Vec2 b) {
    const fp::Vec2 e = sub(b, a);
    const double ee = dot(e, e), s = ee > 0 ? std::clamp(-dot(a, e) / ee, 0.0, 1.0) : 0.0;
    const fp::Vec2 q{a.x + s * e.x, a.y + s * e.y};
    return dot(q, q);
}

/// One segment: degree n (2 or 3) and its n + 1 Bernstein control points.
struct Seg {
    int n = 3;
    std::array<fp::Vec2, 4> p{};
};

/// The power basis of a segment (c[3] = 0 for a quadratic).
inline Poly power(const Seg& s) {
    Poly q;
    const auto& p = s.p;
    auto set = [&](int k, double x, double y) { q.x[k] = x, q.y[k] = y; };
    set(0, p[0].x, p[0].y);
    if (s.n == 2) {
        set(1, 2 * (p[1].x - p[0].x), 2 * (p[1].y - p[0].y));
        set(2, p[2].x - 2 * p[1].x + p[0].x, p[2].y - 2 * p[1].y + p[0].y);
    } else {
        set(1, 3 * (p[1].x - p[0].x), 3 * (p[1].y - p[0].y));
        set(2, 3 * (p[2].x - 2 * p[1].x + p[0].x), 3 * (p[2].y - 2 * p[1].y + p[0].y));
        set(3, p[3].x - 3 * p[2].x + 3 * p[1].x - p[0].x, p[3].y - 3 * p[2].y + 3 * p[1].y - p[0].y);
    }
    return q;
}

/// Horner's rule, the kernels' operations (bezier/kernels.cpp).
inline double horner(const std::array<double, 4>& c, double t) {
    return ((c[3] * t + c[2]) * t + c[1]) * t + c[0];
}
inline fp::Vec2 at(const Poly& q, double t) { return {horner(q.x, t), horner(q.y, t)}; }
inline fp::Vec2 tangent(const Poly& q, double t) {
    return {(3 * q.x[3] * t + 2 * q.x[2]) * t + q.x[1], (3 * q.y[3] * t + 2 * q.y[2]) * t + q.y[1]};
}

/// de Casteljau at t: the control points of [0, t] and [t, 1].
inline void split(const Seg& s, double t, Seg& left, Seg& right) {
    std::array<fp::Vec2, 4> w = s.p;
    left.n = right.n = s.n;
    for (int k = 0; k <= s.n; ++k) {
        left.p[k] = w[0];
        right.p[s.n - k] = w[s.n - k];
        for (int i = 0; i < s.n - k; ++i)
            w[i] = {w[i].x + t * (w[i + 1].x - w[i].x), w[i].y + t * (w[i + 1].y - w[i].y)};
    }
}

/// The control points of the part of s over [t0, t1].
inline Seg part(const Seg& s, double t0, double t1) {
    Seg l, r, m, unused;
    split(s, t1, l, r);
    if (t0 <= 0) return l;
    split(l, t0 / t1, unused, m);
    return m;
}

/// Twice the signed area enclosed by the closed chain of segments (Green's theorem, exact
/// for polynomials: the integral of cross(b, b') over each segment from its power basis).
inline double twice_area(const std::vector<Seg>& segs) {
    double a = 0;
    for (const Seg& s : segs) {
        const Poly q = power(s);
        for (int i = 0; i < 4; ++i)
            for (int j = 1; j < 4; ++j) a += j * (q.x[i] * q.y[j] - q.y[i] * q.x[j]) / (i + j);
    }
    return a;
}

/// Where g(t) = cross(b(t) - o, b'(t)) fails to exceed `tol` on a segment, if anywhere: g is
/// written in the Bernstein basis of degree 2n - 1 (the product of b - o, degree n, and b',
/// degree n - 1); all coefficients above tol prove g > tol on the interval (g is their convex
/// combination), an end coefficient at or below it is g's value there, and otherwise the
/// interval is halved (de Casteljau), up to 40 times.
inline std::optional<double> tangent_failure(const Seg& s, fp::Vec2 o, double tol) {
    const int n = s.n, m = 2 * n - 1;
    static constexpr double binom[6][6] = {{1, 0, 0, 0, 0, 0}, {1, 1, 0, 0, 0, 0}, {1, 2, 1, 0, 0, 0},
                                           {1, 3, 3, 1, 0, 0}, {1, 4, 6, 4, 1, 0}, {1, 5, 10, 10, 5, 1}};
    std::array<double, 6> beta{};
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j < n; ++j) {
            const fp::Vec2 q = sub(s.p[i], o),
                           dj{n * (s.p[j + 1].x - s.p[j].x), n * (s.p[j + 1].y - s.p[j].y)};
            beta[i + j] += binom[n][i] * binom[n - 1][j] / binom[m][i + j] * cross(q, dj);
        }
    struct Frame {
        std::array<double, 6> b;
        double t0, t1;
        int depth;
    };
    std::vector<Frame> stack{{beta, 0, 1, 0}};
    while (!stack.empty()) {
        const Frame f = stack.back();
        stack.pop_back();
        if (f.b[0] <= tol) return f.t0;
        if (f.b[m] <= tol) return f.t1;
        if (std::all_of(f.b.begin(), f.b.begin() + m + 1, [&](double v) { return v > tol; })) continue;
        if (f.depth == 40) return (f.t0 + f.t1) / 2;
        Frame l{{}, f.t0, (f.t0 + f.t1) / 2, f.depth + 1}, r{{}, l.t1, f.t1, f.depth + 1};
        std::array<double, 6> w = f.b;
        for (int k = 0; k <= m; ++k) {
            l.b[k] = w[0];
            r.b[m - k] = w[m - k];
            for (int i = 0; i < m - k; ++i) w[i] = (w[i] + w[i + 1]) / 2;
        }
        stack.push_back(r);
        stack.push_back(l);
    }
    return std::nullopt;
}

/// The ray pieces about o (curve.hpp), and the curve's total turn about o in radians: each
/// segment is halved until every part's control points lie in the closed sector between the
/// rays to its two ends, of less than a quarter turn (cross > 0, dot > 0), so that the part,
/// inside its control hull, turns about o by exactly that sector's angle. Gives up (nothing)
/// past `max_pieces`, which a centre in the kernel never needs. With `thin` > 0 (the inside
/// test's sectors), a good part is halved further while its distance bounds differ by more
/// than `thin` of the farther, as long as the pieces stay under `thin_pieces`.
inline std::optional<RayPieces> ray_pieces(const std::vector<Seg>& segs, const std::vector<Poly>& polys,
                                           fp::Vec2 o, double& turn, double thin = 0,
                                           std::size_t thin_pieces = 1024, std::size_t max_pieces = 1 << 14) {
    struct Piece {
        std::size_t seg;
        double t0, t1, in2, out2;
    };
    std::vector<Piece> out;
    turn = 0;
    for (std::size_t k = 0; k < segs.size(); ++k) {
        struct Frame {
            Seg s;
            double t0, t1;
        };
        std::vector<Frame> stack{{segs[k], 0, 1}};
        while (!stack.empty()) {
            const Frame f = stack.back();
            stack.pop_back();
            const fp::Vec2 u = sub(f.s.p[0], o), v = sub(f.s.p[f.s.n], o);
            bool good = cross(u, v) > 0 && dot(u, v) > 0;
            for (int i = 1; good && i < f.s.n; ++i) {
                const fp::Vec2 q = sub(f.s.p[i], o);
                good = cross(u, q) >= 0 && cross(q, v) >= 0;
            }
            if (good) {
                // Bounds of |b - o| over the part: its hull's nearest edge and farthest corner.
                double near = std::numeric_limits<double>::infinity(), far = 0;
                for (int i = 0; i <= f.s.n; ++i) {
                    const fp::Vec2 a = sub(f.s.p[i], o);
                    far = std::max(far, dot(a, a));
                    for (int j = i + 1; j <= f.s.n; ++j)
                        near = std::min(near, segment_distance2(a, sub(f.s.p[j], o)));
                }
                const bool thick = std::sqrt(far) - std::sqrt(near) > thin * std::sqrt(far);
                if (!(thin > 0 && thick && out.size() + stack.size() + 2 <= thin_pieces)) {
                    out.push_back({k, f.t0, f.t1, near * (1 - 1e-9), far * (1 + 1e-9)});
                    turn += std::atan2(cross(u, v), dot(u, v));
                    continue;
                }
            }
            if (out.size() + stack.size() > max_pieces || f.t1 - f.t0 < 1e-12) return std::nullopt;
            Seg l, r;
            split(f.s, 0.5, l, r);
            const double tm = (f.t0 + f.t1) / 2;
            stack.push_back({r, tm, f.t1});
            stack.push_back({l, f.t0, tm});
        }
    }
    // In curve order the start keys rise, wrapping once: start from the smallest.
    const std::size_t n = out.size();
    std::vector<double> key(n);
    for (std::size_t i = 0; i < n; ++i) {
        const fp::Vec2 u = sub(at(polys[out[i].seg], out[i].t0), o);
        key[i] = pseudo_angle(u.x, u.y);
    }
    const std::size_t first = std::size_t(std::min_element(key.begin(), key.end()) - key.begin());
    RayPieces r;
    r.o = o;
    r.n = n;
    r.n2 = 2;
    while (r.n2 <= n) r.n2 *= 2;
    r.key.assign(r.n2, std::numeric_limits<double>::infinity());
    for (auto* v : {&r.t0, &r.t1, &r.in2, &r.out2}) v->resize(n);
    for (int c = 0; c < 4; ++c) r.cx[c].resize(n), r.cy[c].resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t s = (first + i) % n;
        const Poly& q = polys[out[s].seg];
        r.key[i] = key[s];
        r.t0[i] = out[s].t0;
        r.t1[i] = out[s].t1;
        for (int c = 0; c < 4; ++c) r.cx[c][i] = q.x[c], r.cy[c][i] = q.y[c];
        r.cx[0][i] -= o.x;
        r.cy[0][i] -= o.y;
        r.in2[i] = out[s].in2;
        r.out2[i] = out[s].out2;
    }
    return r;
}

/// The inside test's pieces (curve.hpp): each segment cut at the roots of y'(t) in (0, 1).
/// A piece's end at t = 0 or 1 takes its control point's y, so that neighbouring segments
/// agree on their shared end to the bit (the half-open rule then counts it once).
inline YPieces y_pieces(const std::vector<Seg>& segs, const std::vector<Poly>& polys, fp::Vec2 ref,
                        fp::Box box, double margin) {
    YPieces c;
    c.ref = ref;
    c.box = box;
    for (std::size_t k = 0; k < segs.size(); ++k) {
        const Poly& q = polys[k];
        const double A = 3 * q.y[3], B = 2 * q.y[2], C = q.y[1];
        std::vector<double> cuts{0};
        std::vector<double> roots;
        if (A != 0) {
            const double disc = B * B - 4 * A * C;
            if (disc >= 0) {
                const double h = -(B + std::copysign(std::sqrt(disc), B)) / 2;
                if (h != 0)
                    roots.push_back(h / A), roots.push_back(C / h);
                else
                    roots.push_back(0);
            }
        } else if (B != 0) {
            roots.push_back(-C / B);
        }
        std::sort(roots.begin(), roots.end());
        for (double r : roots)
            if (r > 1e-12 && r < 1 - 1e-12 && r > cuts.back()) cuts.push_back(r);
        cuts.push_back(1);
        const Seg& s = segs[k];
        for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
            const double t0 = cuts[i], t1 = cuts[i + 1];
            const Seg p = part(s, t0, t1);
            double lo = p.p[0].x, hi = p.p[0].x;
            for (int j = 1; j <= s.n; ++j) lo = std::min(lo, p.p[j].x), hi = std::max(hi, p.p[j].x);
            c.t0.push_back(t0);
            c.t1.push_back(t1);
            c.y0.push_back(t0 == 0 ? s.p[0].y : horner(q.y, t0));
            c.y1.push_back(t1 == 1 ? s.p[s.n].y : horner(q.y, t1));
            c.xlo.push_back(lo - margin);
            c.xhi.push_back(hi + margin);
            c.poly.push_back(q);
        }
    }
    c.n = c.t0.size();
    return c;
}

} // namespace fp_bezier
