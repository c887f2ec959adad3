// The 17 wallpaper groups of paper 04 as conditions on the coefficients of its maps.
//
// Every map is written as f(p) = u(X)^T Q v(Y), u(t) = v(t) = [1, cos t, cos 2t, sin t, sin 2t],
// Q a 5 x 5 matrix of 2-vectors (output vectors in the plane):
//   - square lattice (p1 ... p4g, eq. (1)): (X, Y) = (x, y) and Q = P;
//   - hexagonal lattice (p3 ... p6m, eqs. (2)-(9)): (X, Y) = (v0 . p, v1 . p). Every wave vector
//     of eqs. (5)-(8) is R^i v_j or R^i sigma(v_j), an integer combination a v0 + b v1 with
//     |a|, |b| <= 2, and cos / sin(a X + b Y) expand by the addition formulas into the same 5 x 5
//     form (hex_coefficients below). So one evaluator serves all 17 groups.
//
// Symmetry conditions (derived here; Appendix A of the paper is damaged in our text)
// --------------------------------------------------------------------------------
// A symmetry g: p -> A p + t (A a signed permutation, t in {0, pi}^2) of a square-lattice group
// requires
//                       f(A p + t) = A f(p)        (modulo 2 pi Z^2),
// the output transformed by the linear part A only. The full affine action, f(A p + t) =
// A f(p) + t, is impossible for t not in 2 pi Z^2 with a trigonometric polynomial: averaging both
// sides over the torus gives (I - A) P00 = t (mod 2 pi), and for a glide (t parallel to the
// mirror line, where I - A vanishes) that has no solution. (Consequence for orbit-trap patterns:
// rotations and mirrors through the origin with traps sharing them, and the centring translations
// of cm and cmm (f(p + t) = f(p)), are exact symmetries of the pattern; a glide acts exactly only
// on the first step, f(g p) = A f(p), so glide groups need not give glide-symmetric patterns.)
// The legible parts of Appendix A (the masks of p2, pm, pg, cm, pmm, pmg, pgg and the forms of p4
// and p4m) agree with the conditions derived below with these generators (the origin placed as
// those masks imply):
//   p2   rotation by pi: -p                      pmg  (x, -y), (-x, y + pi)
//   pm   mirror (x, -y)                          pgg  (x + pi, -y), (-x, y + pi)
//   pg   glide (x + pi, -y)                      p4   rotation by pi/2: (-y, x)
//   cm   (x, -y), centring (x + pi, y + pi)      p4m  (-y, x), (x, -y)
//   pmm  (x, -y), (-x, y)                        p4g  (-y, x), (x + pi, pi - y)
//   cmm  (x, -y), (-x, y), (x + pi, y + pi)      p1   none
// With u_i(s x + pi t) = sigma_i u_i(x) (sigma_i = +-1 from the parity of cos / sin and of the
// frequency) each condition relates single components of the coefficients:
//   no swap (A diagonal):  P_ij = sigma_i sigma_j A^T P_ij,
//   swap (A antidiagonal): P_ij = sigma_j sigma_i A^T P_ji   (the signs of the two arguments),
// i.e. "slot = +-slot" relations between the 50 numbers P_ij.x, P_ij.y (e.g. p4: P30 = (P03.y,
// -P03.x), the form the paper prints). The relations of all generators link the slots into
// orbits; an orbit whose relations contradict themselves (slot = -slot) must be 0.
//   check:     given coefficients must satisfy every relation of every generator within a
//              relative tolerance of 1e-6 (the paper prints 6 digits); the first broken one is
//              reported, naming the later coefficient in row-major order;
//   project:   the orthogonal projection onto the symmetric coefficients (average over each
//              orbit, with the signs); applied to random coefficients, and to accepted given
//              ones too, so that the map is exactly symmetric in floating point.
// The hexagonal groups need no conditions: eqs. (7) and (8) are symmetric for any G_v, H_v
// (g_k(R p, v, G) = R g_k(p, v, G) by re-indexing the sum; with sigma a mirror, sigma R^i =
// R^-i sigma pairs the sigma terms of eq. (8)). Their generators, for the tests: R3 (p3, p3m1,
// p31m), R6 (p6, p6m), sigma = (-x, y) (p3m1) or (x, -y) (p31m, p6m); the lattice of periods is
// 2 pi Z (1, 0) + 2 pi Z (1/2, sqrt(3)/2) (the dual basis of v0, v1). Note that eq. (7)'s
// "mod [2 pi, 2 pi]" reduces on the square lattice, which R3 does not preserve: with a
// reduction the hexagonal maps commute with their rotations only modulo 2 pi Z^2 before the
// reduction, not after (the mirrors (x, -y) and (-x, y) are fine). `reduction: hexagonal`
// reduces modulo L itself, into the hexagon about 0, and keeps them (fixpoint/lattice.hpp).
#pragma once

#include <fixpoint/errors.hpp>
#include <fixpoint/types.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace fp_wallpaper {

using Matrix = std::array<std::array<fp::Vec2, 5>, 5>; // Q[i][j], i indexes u(X), j indexes v(Y)

constexpr const char* group_names = "p1|p2|pm|pg|cm|pmm|cmm|pmg|pgg|p4|p4m|p4g|p3|p3m1|p31m|p6|p6m";

/// A symmetry p -> A p + t of the plane, A = [a b; c d].
struct Op {
    double a, b, c, d, tx, ty;
    fp::Vec2 operator()(fp::Vec2 p) const { return {a * p.x + b * p.y + tx, c * p.x + d * p.y + ty}; }
    fp::Vec2 linear(fp::Vec2 p) const { return {a * p.x + b * p.y, c * p.x + d * p.y}; }
};

inline bool is_hexagonal(std::string_view g) {
    return g == "p3" || g == "p3m1" || g == "p31m" || g == "p6" || g == "p6m";
}

/// The generators of a group (with the lattice translations they generate the group).
inline std::vector<Op> generators(std::string_view g) {
    constexpr double pi = 3.14159265358979323846;
    const double h = std::sqrt(3.0) / 2;
    const Op rot2{-1, 0, 0, -1, 0, 0}, mirror_y{1, 0, 0, -1, 0, 0}, mirror_x{-1, 0, 0, 1, 0, 0};
    const Op centring{1, 0, 0, 1, pi, pi}, rot4{0, -1, 1, 0, 0, 0};
    const Op r3{-0.5, -h, h, -0.5, 0, 0}, r6{0.5, -h, h, 0.5, 0, 0};
    if (g == "p1") return {};
    if (g == "p2") return {rot2};
    if (g == "pm") return {mirror_y};
    if (g == "pg") return {{1, 0, 0, -1, pi, 0}};
    if (g == "cm") return {mirror_y, centring};
    if (g == "pmm") return {mirror_y, mirror_x};
    if (g == "cmm") return {mirror_y, mirror_x, centring};
    if (g == "pmg") return {mirror_y, {-1, 0, 0, 1, 0, pi}};
    if (g == "pgg") return {{1, 0, 0, -1, pi, 0}, {-1, 0, 0, 1, 0, pi}};
    if (g == "p4") return {rot4};
    if (g == "p4m") return {rot4, mirror_y};
    if (g == "p4g") return {rot4, {1, 0, 0, -1, pi, pi}};
    if (g == "p3") return {r3};
    if (g == "p3m1") return {r3, mirror_x};
    if (g == "p31m") return {r3, mirror_y};
    if (g == "p6") return {r6};
    if (g == "p6m") return {r6, mirror_y};
    throw fp::InternalError("wallpaper: unknown group " + std::string(g));
}

// ------------------------------------------------------------------ square lattice: slots

/// Slot s = (i * 5 + j) * 2 + component: one of the 50 numbers of P.
constexpr int slot(int i, int j, int comp) { return (i * 5 + j) * 2 + comp; }
inline std::string slot_name(int s) {
    return "P" + std::to_string(s / 10) + std::to_string(s / 2 % 5) + (s % 2 ? ".y" : ".x");
}
inline double& at(Matrix& P, int s) { return s % 2 ? P[s / 10][s / 2 % 5].y : P[s / 10][s / 2 % 5].x; }
inline double at(const Matrix& P, int s) { return s % 2 ? P[s / 10][s / 2 % 5].y : P[s / 10][s / 2 % 5].x; }

/// A square-lattice op as relations P[s] = sign[s] * P[src[s]].
struct Relations {
    std::array<int, 50> src;
    std::array<int, 50> sign;
};

/// u_k(s x + t) = parity * u_k(x) for s = +-1, t in {0, pi}.
inline int parity(int k, int s, bool shifted) {
    const int shift = shifted && (k == 1 || k == 3) ? -1 : 1; // cos x, sin x change sign at x + pi
    const int odd = (k == 3 || k == 4) ? s : 1;               // sines are odd
    return shift * odd;
}

inline Relations relations(const Op& g) {
    constexpr double pi = 3.14159265358979323846;
    const auto sgn = [](double v) { return v < 0 ? -1 : 1; };
    const bool tx = std::fabs(g.tx - pi) < 1e-9, ty = std::fabs(g.ty - pi) < 1e-9;
    Relations r{};
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) {
            if (g.b == 0) { // (x, y) -> (a x + tx, d y + ty)
                const int s = parity(i, sgn(g.a), tx) * parity(j, sgn(g.d), ty);
                // P_ij = s A^T P_ij: x-component times a, y-component times d
                r.src[slot(i, j, 0)] = slot(i, j, 0), r.sign[slot(i, j, 0)] = s * sgn(g.a);
                r.src[slot(i, j, 1)] = slot(i, j, 1), r.sign[slot(i, j, 1)] = s * sgn(g.d);
            } else { // (x, y) -> (b y + tx, c x + ty)
                const int s = parity(j, sgn(g.b), tx) * parity(i, sgn(g.c), ty);
                // P_ij = s A^T P_ji: (A^T w).x = c w.y, (A^T w).y = b w.x
                r.src[slot(i, j, 0)] = slot(j, i, 1), r.sign[slot(i, j, 0)] = s * sgn(g.c);
                r.src[slot(i, j, 1)] = slot(j, i, 0), r.sign[slot(i, j, 1)] = s * sgn(g.b);
            }
        }
    return r;
}

/// The first relation of the group's generators that P breaks by more than rel_tol (relative),
/// or an empty message. `blamed` receives the coefficient index i * 5 + j named.
inline std::string broken_relation(std::string_view group, const Matrix& P, int& blamed,
                                   double rel_tol = 1e-6) {
    const auto num = [](double v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", v);
        return std::string(buf);
    };
    for (const Op& g : generators(group)) {
        const Relations r = relations(g);
        for (int s = 0; s < 50; ++s) {
            const int o = r.src[s], sign = r.sign[s];
            const double lhs = at(P, s), rhs = sign * at(P, o);
            if (o == s && sign == 1) continue;
            if (std::fabs(lhs - rhs) <= rel_tol * std::max(std::fabs(lhs), std::fabs(rhs))) continue;
            const int b = std::max(s, o), other = std::min(s, o);
            blamed = b / 2;
            const fp::Vec2 e = P[b / 10][b / 2 % 5];
            std::string rel = slot_name(b) + " = ";
            if (b == other)
                rel += "0";
            else
                rel += (sign < 0 ? "-" : "") + slot_name(other) + " (" + num(sign * at(P, other)) + ")";
            return slot_name(b).substr(0, 3) + " = [" + num(e.x) + ", " + num(e.y) + "] breaks " +
                   std::string(group) + "'s " + rel;
        }
    }
    return {};
}

/// The orthogonal projection of P onto the coefficients with the group's symmetry.
inline Matrix project(std::string_view group, const Matrix& P) {
    std::vector<Relations> rels;
    for (const Op& g : generators(group)) rels.push_back(relations(g));
    Matrix out = P;
    std::array<int, 50> orbit_sign{}; // 0: not yet visited
    for (int start = 0; start < 50; ++start) {
        if (orbit_sign[start]) continue;
        std::vector<int> members{start};
        orbit_sign[start] = 1;
        bool contradiction = false;
        for (std::size_t k = 0; k < members.size(); ++k) {
            const int s = members[k];
            for (const Relations& r : rels) {
                // s and src[s] are linked both ways: P[s] = sign P[src], P[src] = sign P[s]
                for (int t = 0; t < 50; ++t) {
                    int other = -1;
                    if (t == s)
                        other = r.src[s];
                    else if (r.src[t] == s)
                        other = t;
                    if (other < 0) continue;
                    const int want = orbit_sign[s] * r.sign[t];
                    if (!orbit_sign[other]) {
                        orbit_sign[other] = want;
                        members.push_back(other);
                    } else if (orbit_sign[other] != want) {
                        contradiction = true;
                    }
                }
            }
        }
        double sum = 0;
        for (int m : members) sum += orbit_sign[m] * at(P, m);
        const double mean = contradiction ? 0.0 : sum / double(members.size());
        for (int m : members) at(out, m) = orbit_sign[m] * mean;
    }
    return out;
}

// ------------------------------------------------------------------ hexagonal lattice

/// Q of eq. (7) (mirror = false) or eq. (8) for k = 3 or 6, G[j] = G_vj, H[j] = H_vj;
/// sigma_x: sigma = (-x, y) (p3m1), else (x, -y) (p31m, p6m).
inline Matrix hex_coefficients(int k, bool mirror, bool sigma_x, const std::array<fp::Vec2, 3>& G,
                               const std::array<fp::Vec2, 3>& H) {
    const double h = std::sqrt(3.0) / 2;
    Matrix Q{};
    // Wave vectors w = a v0 + b v1 as integers (a, b). In that basis R3 (a, b) = (b, -a - b),
    // R6 (a, b) = (a + b, -a), (-x, y) (a, b) = (-a, a + b), (x, -y) (a, b) = (a, -a - b)
    // (from R3 v0 = -v1, R3 v1 = v0 - v1, R6 v0 = v0 - v1, R6 v1 = v0, ...).
    struct W {
        int a, b;
    };
    const auto rot = [k](W w) { return k == 3 ? W{w.b, -w.a - w.b} : W{w.a + w.b, -w.a}; };
    const auto rot_vec = [k, h](fp::Vec2 g) {
        return k == 3 ? fp::Vec2{-0.5 * g.x - h * g.y, h * g.x - 0.5 * g.y}
                      : fp::Vec2{0.5 * g.x - h * g.y, h * g.x + 0.5 * g.y};
    };
    const auto sig = [sigma_x](W w) { return sigma_x ? W{-w.a, w.a + w.b} : W{w.a, -w.a - w.b}; };
    const auto sig_vec = [sigma_x](fp::Vec2 g) {
        return sigma_x ? fp::Vec2{-g.x, g.y} : fp::Vec2{g.x, -g.y};
    };
    const auto cos_index = [](int n) { return n == 0 ? 0 : n; }; // cos(n t) = u_n, n = 0, 1, 2
    const auto sin_index = [](int n) { return n + 2; };          // sin(n t) = u_{n+2}, n = 1, 2
    const auto add = [&](W w, fp::Vec2 C, fp::Vec2 S) {          // C cos(w.p) + S sin(w.p)
        const int na = std::abs(w.a), nb = std::abs(w.b), sa = w.a < 0 ? -1 : 1, sb = w.b < 0 ? -1 : 1;
        if (na > 2 || nb > 2) throw fp::InternalError("wallpaper: hexagonal wave vector out of range");
        const auto acc = [&](int i, int j, double s, fp::Vec2 v) {
            Q[i][j].x += s * v.x;
            Q[i][j].y += s * v.y;
        };
        // cos(aX + bY) = cos aX cos bY - sin aX sin bY; sin(aX + bY) = sin aX cos bY + cos aX sin bY
        acc(cos_index(na), cos_index(nb), 1, C);
        if (na && nb) acc(sin_index(na), sin_index(nb), -sa * sb, C);
        if (na) acc(sin_index(na), cos_index(nb), sa, S);
        if (nb) acc(cos_index(na), sin_index(nb), sb, S);
    };
    const W v[3] = {{1, 0}, {0, 1}, {1, 1}};
    for (int j = 0; j < 3; ++j) {
        W w = v[j], ws = sig(v[j]);
        fp::Vec2 g = G[j], hh = H[j], gs = sig_vec(G[j]), hs = sig_vec(H[j]);
        for (int i = 0; i < k; ++i) {
            add(w, g, hh);
            if (mirror) add(ws, gs, hs);
            w = rot(w), ws = rot(ws);
            g = rot_vec(g), hh = rot_vec(hh), gs = rot_vec(gs), hs = rot_vec(hs);
        }
    }
    return Q;
}

} // namespace fp_wallpaper
