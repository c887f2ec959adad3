// Paper 05, Sec. 3.1, the converse construction (after Schaefer et al.): from an IFS of affine
// maps to subdivision matrices. Given control points P = {p_1, ..., p_n}, each map f_i gives
// the matrix S_i whose row j holds the weights of f_i(p_j) as an affine combination of the p_k
// (f_i(p_j) = sum_k alpha_jk p_k, rows summing to 1); then f~_i(A) = A P^-1 S_i P (eq. (3.1)) is
// f_i on every set of control points, and the `subdivision` plugin takes (points, S).
//
// With three control points (a triangle, no lift) the weights are the barycentric coordinates
// of f_i(p_j), unique when the triangle is not degenerate; an affine map of the plane is then
// represented exactly. A map that is not affine is refused: its value at a fourth point must be
// the same affine combination of its values at the p_k.
//
// With four control points, lifted as the `subdivision` plugin lifts them (z = x y, paper 05's
// Example 1: P's rows (x, y, x y, 1)), S = L P^-1 where L's rows are the lifted images
// (f(p_j), f_x(p_j) f_y(p_j), 1): the children of the control points are then lifted points.
// Every affine map is represented on the plane, at every level: M = P^-1 S P sends (x, y, z, 1)
// to x' = a x + b y + e, y' = c x + d y + f, with no part of z in them (x' and y', affine,
// are their own interpolants in span{1, x, y, x y}). The lift itself is kept at every level
// (a child's z its x y) exactly when x' y' lies in that span too, that is when f's linear part
// is diagonal or anti-diagonal (scalings along the axes, their reflections and swaps);
// otherwise only the plane, which is what is drawn, follows f below the first level. A map
// that is not affine is refused, naming why: a bilinear map (x', y' in span{1, x, y, x y})
// agrees with its subdivision map on the control points and their children, but its
// grandchildren's lifted coordinates are no longer x y, so from there on the polygons leave
// its images (docs/papers.md gives the counterexample). Other numbers of control points have
// no lift the plugin knows: refused.
#pragma once

#include <fixpoint/host/core/registry.hpp>
#include <fixpoint/types.hpp>

#include <array>
#include <string>
#include <vector>

namespace fp::host {

/// One map's subdivision matrix, row major (n x n for n control points).
using SubdivisionMatrix = std::vector<double>;

/// The subdivision matrices of `maps` (YAML flow mappings of transforms) on the 3 or 4 control
/// `points`. Throws fp::InputError naming the map ("map 2: ...") for a map that is not a
/// transform or not affine, and "--points: ..." for control points that give no invertible P.
std::vector<SubdivisionMatrix> subdivision_matrices(const Registry& reg, const std::vector<Vec2>& points,
                                                    const std::vector<std::string>& maps);

} // namespace fp::host
