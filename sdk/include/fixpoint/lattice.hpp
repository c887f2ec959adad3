// The lattice reductions of the wallpaper maps (paper 04's "mod 2 pi"), written once for the
// wallpaper transform (plugins/transforms/wallpaper*) and the orbit-trap renderer, which reduce
// with the same functions so that a point the map reduced is one the renderer leaves alone.
// Scalar and branch-free: only +, -, *, fabs, copysign and selects, no call, branch or FMA, so
// that the loops calling them vectorise on every instruction set with the same bits. The lanes of
// the hexagon's test, for kernels that hold the points in vectors, are in kernels-inl.hpp.
//
// Square lattice 2 pi Z^2 (reduce_fmod, reduce_centred, reduce_floor): v mod 2 pi as
// v - k * 2 pi with 2 pi split in two parts (k * first part is exact for |k| < 2^15 in float,
// 2^22 in double), k = trunc / nearbyint / floor of v / 2 pi.
//
// Hexagonal lattice L = 2 pi Z (1, 0) + 2 pi Z (1/2, sqrt 3 / 2) (reduce_hexagonal): the
// reduction `hexagonal` of the wallpaper transform (for p3, p3m1, p31m, p6, p6m) and of the
// orbit-trap renderer.
//
// Why (derivation)
// ----------------
// The hexagonal maps of eqs. (7) and (8) are sums of cos / sin(w . p) with every wave vector w an
// integer combination of v0 = (1, -1/sqrt 3) and v1 = (0, -2/sqrt 3)
// (plugins/transforms/wallpaper_groups.hpp). So f is periodic under L = {t : v0 . t, v1 . t in 2 pi Z}, the
// lattice spanned by
//     e0 = 2 pi (1, 0),   e1 = 2 pi (1/2, sqrt 3 / 2)
// (v0 . e0 = 2 pi, v1 . e0 = 0; v0 . e1 = 0, v1 . e1 = -2 pi), and not under 2 pi (0, 1): the
// square lattice 2 pi Z^2 of the paper's "mod [2 pi, 2 pi]" is not a lattice of periods of f, and
// R3 does not map it to itself. L is the hexagonal lattice with minimal length 2 pi; R3, R6 and
// both mirrors (-x, y), (x, -y) map L onto itself (R6 e0 = e1, R6 e1 = e1 - e0, (-x, y) e1 =
// e1 - e0, (x, -y) e1 = e0 - e1).
//
// Take as fundamental domain the Voronoi cell of 0, the hexagon
//     H = {q : |q . n| <= pi for n = (1, 0), (1/2, sqrt 3 / 2), (-1/2, sqrt 3 / 2)}
// (the points nearer to 0 than to any other lattice point; inradius pi, circumradius
// 2 pi / sqrt 3 = 3.628, vertices at 30, 90, ... degrees), and reduce p to p - N(p), N(p) the
// lattice point nearest to p. Since every g of the point group (R3, R6, the mirrors) is an
// isometry mapping L onto itself, N(g p) = g N(p) for every p not equidistant from two lattice
// points (the boundaries of the cells), so
//     red(g p) = g p - g N(p) = g red(p),
// and, f being L-periodic and equivariant (f(g p) = g f(p) for the group's g, exactly in real
// arithmetic),
//     F(g p) = red(f(g p)) = red(g f(p)) = g red(f(p)) = g F(p)     (F = red o f)
// unless f(p) lies on a cell boundary: the reduced orbit of g p is g times the orbit of p. (Under
// the square reduction this fails whenever the y reduction acts: red_sq(g q) - g red_sq(q) is then
// some 2 pi (m, n) + g 2 pi (m', n') not in L, and f, not periodic under it, sends the two orbits
// apart. fmod's x reduction alone is a translation by a multiple of e0, which is harmless.)
// Under Picard a reduction by a lattice vector does not change the next step at all (f(p - N) =
// f(p)): `hexagonal` and `none` give the same orbits up to lattice vectors, and differ only in
// where the traps are tested (the traps, not being L-periodic, meet the folded point). Under the
// S-iteration (eq. (13)) u = (1 - beta) p + beta f(p) is not L-periodic in p, so the reduction
// enters the dynamics; `hexagonal` keeps R3 / R6 exact there too (real and complex alpha, beta
// commute with rotations), `fmod` does not.
//
// N(p) in a few operations: write p = a e0 + b e1 (b = y / (pi sqrt 3), a = x / (2 pi) - b / 2)
// and take (fa, fb) = (floor a, floor b). The parallelogram fa + [0, 1] by fb + [0, 1] is two
// equilateral triangles (its short diagonal joins (1, 0) and (0, 1)); the triangles are the
// Delaunay triangles of L, each contains its circumcentre, and so the nearest lattice point of a
// point of a triangle is one of that triangle's vertices. So N(p) is the nearest of the four
// corners (fa + i, fb + j), i, j in {0, 1}: four squared distances, compared in the order (0, 0),
// (1, 0), (0, 1), (1, 1), a later corner replacing the best only when strictly nearer (the tie
// rule: the first of equally near corners wins).
//
// In floating point (T = float or double; only +, -, *, fabs, floor by nearbyint and selects, no
// call, branch or FMA: the same bits on every instruction set, vectorised by the compiler):
//   - a corner (A, B) is the lattice point (pi k, pi sqrt 3 B) with k = 2 A + B (an integer), and
//     the difference is x - pi k = (x - k P1) - k P2, y - pi sqrt 3 B = (y - B S1) - B S2, with
//     pi = P1 + P2 and pi sqrt 3 = S1 + S2 split so that k P1 and B S1 are exact (P1, S1 have 8
//     significant bits in float, 30 in double): the result carries the rounding of the last
//     subtraction and of k P2, not k times the rounding of pi;
//   - points already in H stay as they are, bit for bit: `in_cell` (|x| < pi, |x / 2 + h y| < pi,
//     |x / 2 - h y| < pi, h = sqrt 3 / 2 rounded to T, pi rounded to T; strict, so the boundary
//     is reduced) selects the input itself. The renderer checks exactly this range (a point in it
//     is one the reduction leaves alone), so its fused pass and its general pass reduce the same
//     points the same way;
//   - near the boundary the rounding decides, so red(g p) and g red(p) can differ there by a
//     lattice vector (a set of measure about the rounding error times the boundary's length);
//     elsewhere they differ by the rounding of g and of the subtraction: a few ulps of |p|;
//   - not finite in, not finite out (the renderer counts such samples as bad values).
#pragma once

#include <cmath>
#include <string_view>

namespace fp::kernels {

/// "mod 2 pi": the square lattice's reductions of each coordinate (fmod, centred, floor), none,
/// or the hexagonal lattice's of the point (the wallpaper transform's and orbit-trap's
/// `reduction`).
enum class Reduction { fmod, centred, floor, none, hexagonal };

/// The reduction a recipe names (one of "fmod|centred|floor|none|hexagonal", checked by the
/// parameter's schema; anything else is fmod, the default).
inline Reduction reduction_named(std::string_view s) {
    return s == "centred"     ? Reduction::centred
           : s == "floor"     ? Reduction::floor
           : s == "none"      ? Reduction::none
           : s == "hexagonal" ? Reduction::hexagonal
                              : Reduction::fmod;
}

// ------------------------------------------------------------------ rounding

/// trunc(v) and floor(v) from nearbyint (which vectorises), exact for every v.
/// nearbyint(v) in the default rounding mode (to nearest, ties to even), in arithmetic: for
/// |v| < 2^23 (2^52) the sum |v| + 2^23 is rounded to the nearest integer and the difference
/// is exact; larger values are integers already. The same bits as std::nearbyint, but inline
/// on every instruction set (nearbyint is a library call unless the target has a rounding
/// instruction, and a call keeps the loops from vectorising; GCC does not vectorise std::floor
/// and std::trunc without -fno-trapping-math).
template <class T>
[[gnu::always_inline]] inline T round_even_(T v) {
    constexpr T big = sizeof(T) == 4 ? T(8388608.0) : T(4503599627370496.0);
    const T a = std::fabs(v);
    const T r = (a + big) - big;
    return std::copysign(a < big ? r : a, v);
}
template <class T>
[[gnu::always_inline]] inline T trunc_(T v) {
    const T a = std::fabs(v), t = round_even_(a);
    return std::copysign(t > a ? t - T(1) : t, v);
}
template <class T>
[[gnu::always_inline]] inline T floor_(T v) {
    const T t = round_even_(v);
    return t > v ? t - T(1) : t;
}

// ------------------------------------------------------------------ the square lattice

template <class T>
struct SquareConst;

template <>
struct SquareConst<float> {
    // 2 pi = t1 + t2, t1 = 201 / 32 (8 significant bits)
    static constexpr float inv_two_pi = 0.159154943091895336f;
    static constexpr float t1 = 6.28125f, t2 = 1.9353071795864769e-3f;
    static constexpr float two_pi = 6.28318530717958648f, pi = 3.14159265358979324f;
};

template <>
struct SquareConst<double> {
    // 2 pi = t1 + t2, t1 = floor(2 pi 2^27) / 2^27 (30 significant bits)
    static constexpr double inv_two_pi = 0.159154943091895336;
    static constexpr double t1 = 6.283185303211212158203125, t2 = 3.968374318722162e-09;
    static constexpr double two_pi = 6.28318530717958648, pi = 3.14159265358979324;
};

/// C's fmod(v, 2 pi): v - 2 pi trunc(v / 2 pi), in (-2 pi, 2 pi) with the sign of v (up to
/// rounding next to multiples of 2 pi); odd: reduce_fmod(-v) = -reduce_fmod(v) bitwise.
/// |v| < 2 pi comes back unchanged (but within an ulp of 2 pi, where v / 2 pi rounds to 1).
template <class T>
[[gnu::always_inline]] inline T reduce_fmod(T v) {
    using K = SquareConst<T>;
    const T k = trunc_(v * K::inv_two_pi);
    return (v - k * K::t1) - k * K::t2;
}

/// Into [-pi, pi): v - 2 pi round(v / 2 pi), moved down by 2 pi at pi (odd except at +-pi).
template <class T>
[[gnu::always_inline]] inline T reduce_centred(T v) {
    using K = SquareConst<T>;
    const T k = round_even_(v * K::inv_two_pi);
    const T r = (v - k * K::t1) - k * K::t2;
    return r >= K::pi ? r - K::two_pi : r;
}

/// Into [0, 2 pi): v - 2 pi floor(v / 2 pi) (GLSL's mod; not odd: it breaks the mirror
/// symmetries through 0).
template <class T>
[[gnu::always_inline]] inline T reduce_floor(T v) {
    using K = SquareConst<T>;
    const T k = floor_(v * K::inv_two_pi);
    T r = (v - k * K::t1) - k * K::t2;
    r = r < T(0) ? r + K::two_pi : r;
    return r >= K::two_pi ? r - K::two_pi : r;
}

// ------------------------------------------------------------------ the hexagonal lattice

template <class T>
struct HexConst;

template <>
struct HexConst<float> {
    static constexpr float inv_pi_sqrt3 = 0.183776298473930683f; // 1 / (pi sqrt 3)
    static constexpr float inv_two_pi = 0.159154943091895336f;
    static constexpr float p1 = 3.140625f, p2 = 9.67653589793e-4f;               // pi
    static constexpr float s1 = 5.4375f, s2 = 3.8980927026535e-3f;               // pi sqrt 3
    static constexpr float pi = 3.14159265358979324f, h = 0.866025403784438647f; // h = sqrt 3 / 2
};

template <>
struct HexConst<double> {
    static constexpr double inv_pi_sqrt3 = 0.183776298473930683;
    static constexpr double inv_two_pi = 0.159154943091895336;
    static constexpr double p1 = 3.141592651605606, p2 = 1.984187159361081e-09;
    static constexpr double s1 = 5.441398091614246, s2 = 1.0884071833740317e-09;
    static constexpr double pi = 3.14159265358979324, h = 0.866025403784438647;
};

/// Whether (x, y) is inside the hexagon H (strictly; NaN: no). Points inside are left alone by
/// reduce_hexagonal, so this is also the orbit-trap renderer's range check (kernels-inl.hpp's
/// in_cell is the same test on lanes).
template <class T>
[[gnu::always_inline]] inline bool in_cell(T x, T y) {
    using K = HexConst<T>;
    const T hx = x * T(0.5), hy = y * K::h;
    // (& on ints, not &&: no branches, so that the loops calling this vectorise.)
    return (int(std::fabs(x) < K::pi) & int(std::fabs(hx + hy) < K::pi) & int(std::fabs(hx - hy) < K::pi)) !=
           0;
}

/// (x, y) <- (x, y) - N(x, y), N the nearest point of the hexagonal lattice L (see above);
/// unchanged when in_cell(x, y).
template <class T>
[[gnu::always_inline]] inline void reduce_hexagonal(T& x, T& y) {
    using K = HexConst<T>;
    const T b = y * K::inv_pi_sqrt3;
    const T a = x * K::inv_two_pi - b * T(0.5);
    const T fa = floor_(a), fb = floor_(b);
    T bx = x, by = y, bd = T(0);
    // The four corners in the order (0, 0), (1, 0), (0, 1), (1, 1); strictly nearer replaces.
    const auto corner = [&](T A, T B, bool first) __attribute__((always_inline)) {
        const T k = (A + A) + B;
        const T dx = (x - k * K::p1) - k * K::p2;
        const T dy = (y - B * K::s1) - B * K::s2;
        const T d = dx * dx + dy * dy;
        const bool nearer = first | (d < bd);
        bx = nearer ? dx : bx;
        by = nearer ? dy : by;
        bd = nearer ? d : bd;
    };
    corner(fa, fb, true);
    corner(fa + T(1), fb, false);
    corner(fa, fb + T(1), false);
    corner(fa + T(1), fb + T(1), false);
    const bool in = in_cell(x, y);
    x = in ? x : bx;
    y = in ? y : by;
}

} // namespace fp::kernels
