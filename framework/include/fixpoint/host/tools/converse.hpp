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
#pragma once

#include <fixpoint/host/core/registry.hpp>
#include <fixpoint/types.hpp>

#include <array>
#include <string>
#include <vector>

namespace fp::host {

/// One map's subdivision matrix, row major (3 x 3).
using Subdivision3 = std::array<double, 9>;

/// The subdivision matrices of `maps` (YAML flow mappings of transforms) on the triangle
/// `points`. Throws fp::InputError naming the map ("map 2: ...") for a map that is not a
/// transform, not affine, or a degenerate triangle.
std::vector<Subdivision3> subdivision_matrices(const Registry& reg, const std::array<Vec2, 3>& points,
                                               const std::vector<std::string>& maps);

} // namespace fp::host
