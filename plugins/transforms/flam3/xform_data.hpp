// What one flam3 xform evaluates, fixed when it is built (xform.cpp, variation.cpp), and the
// evaluation on the SIMD layer (eval.cpp): flam3's apply_xform (variations.c) on a chunk of
// points in double lanes:
//   t = the affine pre-transform of p: tx = c00 x + c10 y + c20, ty = c01 x + c11 y + c21
//       (coefs in flam3's order c00 c01 c10 c11 c20 c21);
//   pre_blur, when present, moves t first;
//   q = sum over the active variations, in flam3's order of their numbers, of V_i(t; w_i);
//   p' = the post affine of q (when not the identity).
// flam3's precalculated values are computed for the chunk: r^2 = tx^2 + ty^2, r = sqrt(r^2),
// atan2(tx, ty) (flam3's "atan": x first), atan2(ty, tx) ("atanyx"), sina = tx / r and
// cosa = ty / r.
#pragma once

#include <fixpoint/flam3_table.hpp>

#include <cstddef>
#include <cstdint>

namespace fp_flam3 {

/// flam3's EPS.
constexpr double eps = 1e-10;

/// Values flam3 precalculates per xform from its parameters (xform_precalc).
enum Derived : std::uint32_t {
    d_julian_rn,
    d_julian_cn,
    d_juliascope_rn,
    d_juliascope_cn,
    d_persp_vsin,
    d_persp_vfcos,
    d_radial_spin,
    d_radial_zoom,
    d_waves_dx2,
    d_waves_dy2,
    d_disc2_timespi,
    d_disc2_sinadd,
    d_disc2_cosadd,
    d_ss_pm4,
    d_ss_pneg1_n1,
    d_wj_cf,
    d_wj_rn,
    d_wj_cn,
    d_escher_seb,
    d_escher_ceb,
    derived_count
};

struct XformData {
    double coef[6] = {1, 0, 0, 1, 0, 0}; ///< the pre-transform, flam3's order
    double post[6] = {1, 0, 0, 1, 0, 0}; ///< the post-transform, flam3's order
    bool has_post = false;
    std::uint32_t n = 0; ///< active variations (pre_blur apart)
    std::uint32_t var[var_count] = {};
    double weight[var_count] = {};
    std::uint32_t roff[var_count] = {}; ///< the first of each one's rows of randoms
    double pre_blur = 0;
    std::uint32_t pre_blur_roff = 0;
    std::uint32_t randoms = 0; ///< rows of randoms an evaluation draws
    bool atan = false, atanyx = false, angles = false;
    double prm[param_count] = {};
    double der[derived_count] = {};
};

/// Which of flam3's precalculated angles variation v reads (prepare_precalc_flags).
constexpr bool reads_atan(std::uint32_t v) {
    switch (v) {
    case v_polar:
    case v_handkerchief:
    case v_heart:
    case v_disc:
    case v_ex:
    case v_julia:
    case v_fan:
    case v_blob:
    case v_fan2:
    case v_disc2:
    case v_polar2: return true;
    default: return false;
    }
}
constexpr bool reads_atanyx(std::uint32_t v) {
    switch (v) {
    case v_julian:
    case v_juliascope:
    case v_radial_blur:
    case v_ngon:
    case v_super_shape:
    case v_flower:
    case v_conic:
    case v_cpow:
    case v_escher:
    case v_wedge:
    case v_wedge_julia:
    case v_wedge_sph:
    case v_whorl:
    case v_log: return true;
    default: return false;
    }
}
constexpr bool reads_angles(std::uint32_t v) {
    switch (v) {
    case v_spiral:
    case v_hyperbolic:
    case v_diamond:
    case v_power:
    case v_rings:
    case v_blob:
    case v_rings2: return true;
    default: return false;
    }
}

/// Adds variation v with weight w to x (after those added before it; v in increasing order).
void add_variation(XformData& x, std::uint32_t v, double w);
/// Fills x.der from x.prm and x.coef, in the SIMD layer's arithmetic (the same bits on every
/// target, unlike libm's sin and cos).
void derive(XformData& x);
/// The xform on n <= fp::chunk_size points, in place; rnd: x.randoms rows of fp::chunk_size
/// uniform numbers in [0, 1) (row j, point i at rnd[j * chunk_size + i]).
void eval_chunk(const XformData& x, double* px, double* py, std::size_t n, const double* rnd);

} // namespace fp_flam3
