// Whether a polygon is simple, in O(n log n): the Shamos–Hoey sweep. The check it replaces
// tested every pair of edges, which took 17.6 s for one polygon of 40 000 vertices.
//
// A vertical line sweeps the edges from left to right; the edges it crosses are kept in a set
// ordered from bottom to top. If any two edges that are not neighbours along the polygon meet,
// the leftmost such meeting is between two edges that are next to each other in that order at
// some moment before the line passes it, so it is enough to test each edge against its
// neighbours in the order when it enters, and the two neighbours of an edge when it leaves.
// Neighbours along the polygon meet at their shared vertex and are never tested against each
// other (the caller refuses repeated vertices and edges that fold back beforehand).
#pragma once

#include <fixpoint/types.hpp>

#include <algorithm>
#include <cstddef>
#include <optional>
#include <set>
#include <utility>
#include <vector>

namespace fp_shapes::detail {

inline double cross(fp::Vec2 a, fp::Vec2 b) { return a.x * b.y - a.y * b.x; }
inline fp::Vec2 sub(fp::Vec2 a, fp::Vec2 b) { return {a.x - b.x, a.y - b.y}; }
/// > 0 when c lies to the left of the directed line a -> b.
inline double orient(fp::Vec2 a, fp::Vec2 b, fp::Vec2 c) { return cross(sub(b, a), sub(c, a)); }

inline bool lex_less(fp::Vec2 a, fp::Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

/// Two edges of the polygon that are not neighbours along it and meet (as closed segments),
/// as (smaller index, larger index); nothing when the polygon is simple. Edge i runs from v[i]
/// to v[i + 1 mod n]. `meet` is the test of two closed segments.
template <class Meet>
std::optional<std::pair<std::size_t, std::size_t>> find_crossing(const std::vector<fp::Vec2>& v, Meet meet) {
    const std::size_t n = v.size();
    struct Edge {
        fp::Vec2 l, r; // left (lexicographically smaller) and right end
    };
    std::vector<Edge> e(n);
    for (std::size_t i = 0; i < n; ++i) {
        const fp::Vec2 a = v[i], b = v[(i + 1) % n];
        e[i] = lex_less(b, a) ? Edge{b, a} : Edge{a, b};
    }
    // "Edge a lies below edge b" where both cross the sweep line, decided at the end of the two
    // that entered last; collinear edges are ordered by index (they meet, and are then tested).
    auto below = [&e](std::size_t a, std::size_t b) {
        if (a == b) return false;
        const Edge &A = e[a], &B = e[b];
        if (!lex_less(B.l, A.l) && !(A.l.x == B.l.x && A.l.y == B.l.y)) { // A entered first
            const double s = orient(A.l, A.r, B.l);
            if (s != 0) return s > 0;
            const double t = orient(A.l, A.r, B.r);
            return t != 0 ? t > 0 : a < b;
        }
        if (A.l.x == B.l.x && A.l.y == B.l.y) { // same left end: by the other ends
            const double t = orient(A.l, A.r, B.r);
            return t != 0 ? t > 0 : a < b;
        }
        const double s = orient(B.l, B.r, A.l); // B entered first
        if (s != 0) return s < 0;
        const double t = orient(B.l, B.r, A.r);
        return t != 0 ? t < 0 : a < b;
    };
    // Events: every edge enters at its left end and leaves at its right end; at one point,
    // entries come first, so that edges touching there are in the order together.
    struct Event {
        fp::Vec2 at;
        int leave; // 0: enters, 1: leaves
        std::size_t edge;
    };
    std::vector<Event> ev;
    ev.reserve(2 * n);
    for (std::size_t i = 0; i < n; ++i) ev.push_back({e[i].l, 0, i}), ev.push_back({e[i].r, 1, i});
    std::sort(ev.begin(), ev.end(), [](const Event& a, const Event& b) {
        if (a.at.x != b.at.x) return a.at.x < b.at.x;
        if (a.at.y != b.at.y) return a.at.y < b.at.y;
        if (a.leave != b.leave) return a.leave < b.leave;
        return a.edge < b.edge;
    });
    auto neighbours = [n](std::size_t a, std::size_t b) {
        return a + 1 == b || b + 1 == a || (a == 0 && b == n - 1) || (b == 0 && a == n - 1);
    };
    auto crossing = [&](std::size_t a, std::size_t b) -> bool {
        return !neighbours(a, b) && meet(v[a], v[(a + 1) % n], v[b], v[(b + 1) % n]);
    };
    auto found = [](std::size_t a, std::size_t b) { return std::make_pair(std::min(a, b), std::max(a, b)); };

    using Order = std::set<std::size_t, decltype(below)>;
    Order order(below);
    // Where each edge stands in the order: an edge leaves by its position, never by a search
    // (a search would trust the ordering across a crossing not yet found).
    std::vector<typename Order::iterator> at(n, order.end());
    for (const Event& x : ev) {
        const std::size_t s = x.edge;
        if (!x.leave) {
            const auto [it, inserted] = order.insert(s);
            if (!inserted) return found(s, *it); // the order cannot tell them apart: they overlap
            at[s] = it;
            if (it != order.begin() && crossing(*std::prev(it), s)) return found(*std::prev(it), s);
            if (std::next(it) != order.end() && crossing(s, *std::next(it))) return found(s, *std::next(it));
        } else {
            const auto it = at[s];
            if (it != order.begin() && std::next(it) != order.end() &&
                crossing(*std::prev(it), *std::next(it)))
                return found(*std::prev(it), *std::next(it));
            order.erase(it);
        }
    }
    return std::nullopt;
}

} // namespace fp_shapes::detail
