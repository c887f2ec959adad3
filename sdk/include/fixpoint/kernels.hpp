// The known kernels as batch functions: the transform and shape plugins that are known kernels
// (fp::KnownKernel: inversion in a circle about its centre, affine, Gumowski-Mira) compute their
// points with these, and the renderers that run the same maps fused (chaos-game) compute them
// with the formulas these are made of (fixpoint/kernels-inl.hpp), so the two agree to the bit.
// Compiled once per instruction set in the SDK library (sdk/src/kernels.cpp) and dispatched at run
// time, like a plugin's own kernels (fixpoint/simd.hpp). Values are rounded to the batch's type
// first, then computed in the formulas' order, with no FMA.
#pragma once

#include <fixpoint/batch.hpp>

namespace fp::kernels {

/// The affine map x' = (a x + b y) + e, y' = (c x + d y) + f with k = {a, b, c, d, e, f}, on the
/// active points.
void affine(const double (&k)[6], Points<float> p, Mask mask);
void affine(const double (&k)[6], Points<double> p, Mask mask);

/// The Gumowski-Mira map with k = {alpha, mu, 2 (1 - mu)}, on the active points.
void gumowski_mira(const double (&k)[3], Points<float> p, Mask mask);
void gumowski_mira(const double (&k)[3], Points<double> p, Mask mask);

/// out[i] = 1 where p[i] lies inside the circle of centre (cx, cy) and squared radius r2,
/// |p - c|^2 < r2 (NaN: outside), else 0.
void in_circle(float cx, float cy, float r2, Points<const float> p, unsigned char* out);
void in_circle(double cx, double cy, double r2, Points<const double> p, unsigned char* out);

/// s[i] = r2 / |d_i|^2: the factor of the inversion in a circle about its centre (paper 01, eq.
/// (2); t_b^2 of eq. (4) without a square root).
void inversion_factor(float r2, Points<const float> d, float* s);
void inversion_factor(double r2, Points<const double> d, double* s);

/// The directions d = p - o of eq. (4) into dx, dy (an inactive point: the zero direction);
/// whether any point is active.
bool directions(float ox, float oy, Points<const float> p, Mask mask, float* dx, float* dy);
bool directions(double ox, double oy, Points<const double> p, Mask mask, double* dx, double* dy);

/// Eq. (4)'s last step p' = o + t (p - o) on the active points, t[i] the point's factor.
void scale_from(float ox, float oy, Points<float> p, Mask mask, const float* t);
void scale_from(double ox, double oy, Points<double> p, Mask mask, const double* t);

/// out[i] = 1 where p[i] lies strictly inside the hexagon of the hexagonal lattice reduction
/// (fixpoint/lattice.hpp's in_cell) by the lanes' test a kernel makes (kernels-inl.hpp), else 0.
void in_cell(Points<const float> p, unsigned char* out);
void in_cell(Points<const double> p, unsigned char* out);

} // namespace fp::kernels
