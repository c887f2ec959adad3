// flam3's variations as one table: their numbers, names, parameters, defaults and the random
// numbers each draws, as flam3 3.1.1 defines them (variations.c, initialize_xforms and the
// parser's attribute names). Everything else is generated from it: the plugins' descriptors
// (flam3.cpp), the xform's parameters, the evaluation's dispatch (eval-inl.hpp) and the
// importer's attribute table.
//
// V(number, identifier, plugin name, randoms, summary): `randoms` is how many uniform numbers
// in [0, 1) one evaluation draws (flam3's flam3_random_isaac_01 calls; julia's random bit is one
// number, u < 0.5), 0 for the deterministic variations.
// P(variation number, parameter, default, description): the variation's own parameters under
// flam3's attribute names, with initialize_xforms' defaults.
#pragma once

#include <cstddef>
#include <cstdint>

// clang-format off
#define FP_FLAM3_VARIATIONS(V) \
    V(0, linear, "linear", 0, "p") \
    V(1, sinusoidal, "sinusoidal", 0, "(sin x, sin y)") \
    V(2, spherical, "spherical", 0, "p / (r^2 + 1e-10)") \
    V(3, swirl, "swirl", 0, "(x sin r^2 - y cos r^2, x cos r^2 + y sin r^2)") \
    V(4, horseshoe, "horseshoe", 0, "((x - y)(x + y), 2 x y) / r") \
    V(5, polar, "polar", 0, "(theta / pi, r - 1), theta = atan2(x, y)") \
    V(6, handkerchief, "handkerchief", 0, "r (sin(theta + r), cos(theta - r))") \
    V(7, heart, "heart", 0, "r (sin(theta r), -cos(theta r))") \
    V(8, disc, "disc", 0, "theta / pi (sin(pi r), cos(pi r))") \
    V(9, spiral, "spiral", 0, "(cos theta + sin r, sin theta - cos r) / r") \
    V(10, hyperbolic, "hyperbolic", 0, "(sin theta / r, r cos theta)") \
    V(11, diamond, "diamond", 0, "(sin theta cos r, cos theta sin r)") \
    V(12, ex, "ex", 0, "r (sin^3(theta + r) + cos^3(theta - r), sin^3(theta + r) - cos^3(theta - r))") \
    V(13, julia, "julia", 1, "a square root of the point: sqrt(r) (cos(theta/2 + k pi), sin(...)), k random") \
    V(14, bent, "bent", 0, "(x < 0 ? 2 x : x, y < 0 ? y / 2 : y)") \
    V(15, waves, "waves", 0, "(x + b sin(y / e^2), y + d sin(x / f^2)), b d e f of the xform's coefs") \
    V(16, fisheye, "fisheye", 0, "2 / (r + 1) (y, x)") \
    V(17, popcorn, "popcorn", 0, "(x + e sin(tan 3y), y + f sin(tan 3x)), e f of the xform's coefs") \
    V(18, exponential, "exponential", 0, "e^(x - 1) (cos(pi y), sin(pi y))") \
    V(19, power, "power", 0, "r^(sin theta) (cos theta, sin theta)") \
    V(20, cosine, "cosine", 0, "(cos(pi x) cosh y, -sin(pi x) sinh y)") \
    V(21, rings, "rings", 0, "rings of width e^2 (e of the xform's coefs)") \
    V(22, fan, "fan", 0, "fan blades of angle pi e^2 (e, f of the xform's coefs)") \
    V(23, blob, "blob", 0, "r modulated by blob_low .. blob_high with blob_waves waves") \
    V(24, pdj, "pdj", 0, "(sin(a y) - cos(b x), sin(c x) - cos(d y))") \
    V(25, fan2, "fan2", 0, "fan with its own fan2_x, fan2_y") \
    V(26, rings2, "rings2", 0, "rings of width rings2_val^2") \
    V(27, eyefish, "eyefish", 0, "2 p / (r + 1)") \
    V(28, bubble, "bubble", 0, "p / (r^2 / 4 + 1)") \
    V(29, cylinder, "cylinder", 0, "(sin x, y)") \
    V(30, perspective, "perspective", 0, "a plane seen at perspective_angle from perspective_dist") \
    V(31, noise, "noise", 2, "p scaled by a random factor, per axis by cos and sin of a random angle") \
    V(32, julian, "julian", 1, "a random julian_power-th root, raised to julian_dist") \
    V(33, juliascope, "juliascope", 1, "julian with every other root mirrored") \
    V(34, blur, "blur", 2, "a uniform point of the unit disc (the input ignored)") \
    V(35, gaussian_blur, "gaussian-blur", 5, "a random point, gaussian-like radius, random angle") \
    V(36, radial_blur, "radial-blur", 4, "a blur along spin and zoom, radial_blur_angle between them") \
    V(37, pie, "pie", 3, "a random point of one of pie_slices slices") \
    V(38, ngon, "ngon", 0, "a ngon_sides-gon, ngon_power, ngon_circle, ngon_corners") \
    V(39, curl, "curl", 0, "p / (1 + c1 z + c2 z^2) in complex numbers") \
    V(40, rectangles, "rectangles", 0, "reflections in a grid of rectangles_x by rectangles_y") \
    V(41, arch, "arch", 1, "a random arch (the weight used as an angle: flam3's own rule)") \
    V(42, tangent, "tangent", 0, "(sin x / cos y, tan y)") \
    V(43, square, "square", 2, "a uniform point of the unit square (the input ignored)") \
    V(44, rays, "rays", 1, "rays (the weight used as an angle: flam3's own rule)") \
    V(45, blade, "blade", 1, "blades (the weight used as a radius: flam3's own rule)") \
    V(46, secant2, "secant2", 0, "(x, 1 / cos(w r) -+ 1) (the weight inside: flam3's own rule)") \
    V(47, twintrian, "twintrian", 1, "twin triangles (the weight inside: flam3's own rule)") \
    V(48, cross, "cross", 0, "p / |x^2 - y^2|") \
    V(49, disc2, "disc2", 0, "disc with disc2_rot and disc2_twist") \
    V(50, super_shape, "super-shape", 1, "Gielis' superformula with super_shape_* parameters") \
    V(51, flower, "flower", 1, "a rose of flower_petals petals, flower_holes") \
    V(52, conic, "conic", 1, "a conic of conic_eccentricity, conic_holes") \
    V(53, parabola, "parabola", 2, "random points under parabola_height, parabola_width") \
    V(54, bent2, "bent2", 0, "bent with factors bent2_x, bent2_y") \
    V(55, bipolar, "bipolar", 0, "bipolar coordinates, bipolar_shift") \
    V(56, boarders, "boarders", 1, "tiles with borders (the Apophysis plugin pack)") \
    V(57, butterfly, "butterfly", 0, "a butterfly (the Apophysis plugin pack)") \
    V(58, cell, "cell", 0, "interleaved cells of cell_size") \
    V(59, cpow, "cpow", 1, "a complex power z^(cpow_r + i cpow_i) / cpow_power, a random branch") \
    V(60, curve, "curve", 0, "(x + xamp e^(-y^2 / xlength^2), y + yamp e^(-x^2 / ylength^2))") \
    V(61, edisc, "edisc", 0, "elliptic disc (the Apophysis plugin pack)") \
    V(62, elliptic, "elliptic", 0, "elliptic coordinates (the Apophysis plugin pack)") \
    V(63, escher, "escher", 0, "Escher's droste spiral, escher_beta") \
    V(64, foci, "foci", 0, "foci (the Apophysis plugin pack)") \
    V(65, lazysusan, "lazysusan", 0, "a turntable of radius the weight (flam3's own rule)") \
    V(66, loonie, "loonie", 0, "loonie (the weight used as a radius: flam3's own rule)") \
    V(67, pre_blur, "pre-blur", 5, "a gaussian-like blur of the affine image before the other variations") \
    V(68, modulus, "modulus", 0, "p modulo the box of half sides modulus_x, modulus_y") \
    V(69, oscilloscope, "oscilloscope", 0, "an oscilloscope trace mirrors y") \
    V(70, polar2, "polar2", 0, "(theta / pi, log r^2 / (2 pi))") \
    V(71, popcorn2, "popcorn2", 0, "popcorn with its own popcorn2_x, popcorn2_y, popcorn2_c") \
    V(72, scry, "scry", 0, "scry (the weight inside: flam3's own rule)") \
    V(73, separation, "separation", 0, "separation of the half planes (the Apophysis plugin pack)") \
    V(74, split, "split", 0, "axes flipped in stripes of split_xsize, split_ysize") \
    V(75, splits, "splits", 0, "the quadrants moved apart by splits_x, splits_y") \
    V(76, stripes, "stripes", 0, "stripes of stripes_space, stripes_warp") \
    V(77, wedge, "wedge", 0, "wedges of wedge_angle, wedge_count, wedge_hole, wedge_swirl") \
    V(78, wedge_julia, "wedge-julia", 1, "julian in wedges") \
    V(79, wedge_sph, "wedge-sph", 0, "spherical in wedges") \
    V(80, whorl, "whorl", 0, "a whorl of radius the weight (flam3's own rule)") \
    V(81, waves2, "waves2", 0, "waves with their own scales and frequencies") \
    V(82, exp, "exp", 0, "the complex exponential") \
    V(83, log, "log", 0, "the complex logarithm (the principal one)") \
    V(84, sin, "sin", 0, "the complex sine") \
    V(85, cos, "cos", 0, "the complex cosine, conjugated") \
    V(86, tan, "tan", 0, "the complex tangent") \
    V(87, sec, "sec", 0, "the complex secant") \
    V(88, csc, "csc", 0, "the complex cosecant, conjugated") \
    V(89, cot, "cot", 0, "the complex cotangent") \
    V(90, sinh, "sinh", 0, "the complex hyperbolic sine") \
    V(91, cosh, "cosh", 0, "the complex hyperbolic cosine") \
    V(92, tanh, "tanh", 0, "the complex hyperbolic tangent") \
    V(93, sech, "sech", 0, "the complex hyperbolic secant, conjugated") \
    V(94, csch, "csch", 0, "the complex hyperbolic cosecant, conjugated") \
    V(95, coth, "coth", 0, "the complex hyperbolic cotangent") \
    V(96, auger, "auger", 0, "auger, auger_freq, auger_weight, auger_sym, auger_scale") \
    V(97, flux, "flux", 0, "flux (the weight inside: flam3's own rule), flux_spread") \
    V(98, mobius, "mobius", 0, "the Moebius map (a z + b) / (c z + d), complex a b c d")

#define FP_FLAM3_PARAMS(P) \
    P(23, blob_low, 0, "the radius factor at the blob's waists") \
    P(23, blob_high, 1, "the radius factor at the blob's crests") \
    P(23, blob_waves, 1, "the number of waves around the blob") \
    P(24, pdj_a, 0, "a of sin(a y)") \
    P(24, pdj_b, 0, "b of cos(b x)") \
    P(24, pdj_c, 0, "c of sin(c x)") \
    P(24, pdj_d, 0, "d of cos(d y)") \
    P(25, fan2_x, 0, "the blades' angle is pi fan2_x^2") \
    P(25, fan2_y, 0, "the blades' offset angle") \
    P(26, rings2_val, 0, "the rings' width is rings2_val^2") \
    P(30, perspective_angle, 0, "the plane's tilt, in quarter turns") \
    P(30, perspective_dist, 0, "the distance of the eye") \
    P(32, julian_power, 1, "n: the n-th root (negative: of the inverse)") \
    P(32, julian_dist, 1, "the radius is r^(julian_dist / julian_power)") \
    P(33, juliascope_power, 1, "n: the n-th root (negative: of the inverse)") \
    P(33, juliascope_dist, 1, "the radius is r^(juliascope_dist / juliascope_power)") \
    P(36, radial_blur_angle, 0, "between a spin (1) and a zoom (0), in quarter turns") \
    P(37, pie_slices, 6, "the number of slices") \
    P(37, pie_rotation, 0, "the angle of the first slice") \
    P(37, pie_thickness, 0.5, "the part of each slice filled") \
    P(38, ngon_sides, 5, "the polygon's sides") \
    P(38, ngon_power, 3, "the radius's power") \
    P(38, ngon_circle, 1, "the circle's share") \
    P(38, ngon_corners, 2, "the corners' share") \
    P(39, curl_c1, 1, "c1 of 1 + c1 z + c2 z^2") \
    P(39, curl_c2, 0, "c2 of 1 + c1 z + c2 z^2") \
    P(40, rectangles_x, 1, "the rectangles' width (0: no reflection in x)") \
    P(40, rectangles_y, 1, "the rectangles' height (0: no reflection in y)") \
    P(49, disc2_rot, 0, "the rotation, in half turns per unit of x + y") \
    P(49, disc2_twist, 0, "the twist") \
    P(50, super_shape_rnd, 0, "the share of a random radius") \
    P(50, super_shape_m, 0, "m: the symmetry") \
    P(50, super_shape_n1, 1, "n1") \
    P(50, super_shape_n2, 1, "n2") \
    P(50, super_shape_n3, 1, "n3") \
    P(50, super_shape_holes, 0, "the hole's radius") \
    P(51, flower_petals, 0, "the petals") \
    P(51, flower_holes, 0, "the hole's radius") \
    P(52, conic_eccentricity, 1, "the eccentricity") \
    P(52, conic_holes, 0, "the hole's radius") \
    P(53, parabola_height, 0, "the height") \
    P(53, parabola_width, 0, "the width") \
    P(54, bent2_x, 1, "the factor of negative x") \
    P(54, bent2_y, 1, "the factor of negative y") \
    P(55, bipolar_shift, 0, "the shift") \
    P(58, cell_size, 1, "the cells' side") \
    P(59, cpow_r, 1, "the power's real part") \
    P(59, cpow_i, 0, "the power's imaginary part") \
    P(59, cpow_power, 1, "the number of branches") \
    P(60, curve_xamp, 0, "the x amplitude") \
    P(60, curve_yamp, 0, "the y amplitude") \
    P(60, curve_xlength, 1, "the x length") \
    P(60, curve_ylength, 1, "the y length") \
    P(63, escher_beta, 0, "the spiral's angle") \
    P(65, lazysusan_spin, 0, "the turn inside") \
    P(65, lazysusan_space, 0, "the space outside") \
    P(65, lazysusan_twist, 0, "the twist inside") \
    P(65, lazysusan_x, 0, "the centre's x") \
    P(65, lazysusan_y, 0, "the centre's y (flam3's sign: the centre is (x, -y))") \
    P(68, modulus_x, 0, "the box's half width") \
    P(68, modulus_y, 0, "the box's half height") \
    P(69, oscilloscope_separation, 1, "the trace's offset") \
    P(69, oscilloscope_frequency, 3.14159265358979323846, "the trace's frequency") \
    P(69, oscilloscope_amplitude, 1, "the trace's amplitude") \
    P(69, oscilloscope_damping, 0, "the trace's damping") \
    P(71, popcorn2_x, 0, "the x amplitude") \
    P(71, popcorn2_y, 0, "the y amplitude") \
    P(71, popcorn2_c, 0, "the frequency") \
    P(73, separation_x, 0, "the x separation") \
    P(73, separation_xinside, 0, "the x inside factor") \
    P(73, separation_y, 0, "the y separation") \
    P(73, separation_yinside, 0, "the y inside factor") \
    P(74, split_xsize, 0, "the stripes of x") \
    P(74, split_ysize, 0, "the stripes of y") \
    P(75, splits_x, 0, "the x shift") \
    P(75, splits_y, 0, "the y shift") \
    P(76, stripes_space, 0, "the space between stripes") \
    P(76, stripes_warp, 0, "the stripes' warp") \
    P(77, wedge_angle, 0, "the wedges' angle") \
    P(77, wedge_hole, 0, "the hole's radius") \
    P(77, wedge_count, 1, "the wedges") \
    P(77, wedge_swirl, 0, "the swirl") \
    P(78, wedge_julia_angle, 0, "the wedges' angle") \
    P(78, wedge_julia_count, 1, "the wedges") \
    P(78, wedge_julia_power, 1, "n: the n-th root") \
    P(78, wedge_julia_dist, 0, "the radius's exponent times 2 n") \
    P(79, wedge_sph_angle, 0, "the wedges' angle") \
    P(79, wedge_sph_hole, 0, "the hole's radius") \
    P(79, wedge_sph_count, 1, "the wedges") \
    P(79, wedge_sph_swirl, 0, "the swirl") \
    P(80, whorl_inside, 0, "the turn inside the radius") \
    P(80, whorl_outside, 0, "the turn outside the radius") \
    P(81, waves2_scalex, 0, "the x amplitude") \
    P(81, waves2_scaley, 0, "the y amplitude") \
    P(81, waves2_freqx, 0, "the x frequency") \
    P(81, waves2_freqy, 0, "the y frequency") \
    P(96, auger_freq, 1, "the frequency") \
    P(96, auger_weight, 0.5, "the auger's weight") \
    P(96, auger_sym, 0, "the symmetry") \
    P(96, auger_scale, 1, "the scale") \
    P(97, flux_spread, 0, "the spread") \
    P(98, mobius_re_a, 0, "Re a") \
    P(98, mobius_im_a, 0, "Im a") \
    P(98, mobius_re_b, 0, "Re b") \
    P(98, mobius_im_b, 0, "Im b") \
    P(98, mobius_re_c, 0, "Re c") \
    P(98, mobius_im_c, 0, "Im c") \
    P(98, mobius_re_d, 0, "Re d") \
    P(98, mobius_im_d, 0, "Im d")
// clang-format on

namespace fp_flam3 {

/// The variations' numbers (flam3's), as enumerators v_NAME.
enum Var : std::uint32_t {
#define FP_FLAM3_V(num, id, name, rnd, summary) v_##id = (num),
    FP_FLAM3_VARIATIONS(FP_FLAM3_V)
#undef FP_FLAM3_V
        var_count
};

/// The parameters' indices into a flat array, as enumerators p_NAME.
enum Param : std::uint32_t {
#define FP_FLAM3_P(var, id, def, desc) p_##id,
    FP_FLAM3_PARAMS(FP_FLAM3_P)
#undef FP_FLAM3_P
        param_count
};

struct VarInfo {
    const char* name;      ///< flam3's attribute name (with underscores)
    const char* plugin;    ///< the plugin's (kebab-case)
    std::uint32_t randoms; ///< uniform numbers drawn per evaluation
    const char* summary;
};

inline constexpr VarInfo var_info[var_count] = {
#define FP_FLAM3_V(num, id, name, rnd, summary) {#id, name, rnd, summary},
    FP_FLAM3_VARIATIONS(FP_FLAM3_V)
#undef FP_FLAM3_V
};

struct ParamInfo {
    std::uint32_t var;
    const char* name;
    double def;
    const char* def_text;
    const char* desc;
};

inline constexpr ParamInfo param_info[param_count] = {
#define FP_FLAM3_P(var, id, def, desc) {var, #id, def, #def, desc},
    FP_FLAM3_PARAMS(FP_FLAM3_P)
#undef FP_FLAM3_P
};

/// Parameters of variation v.
constexpr std::size_t params_of(std::uint32_t v) {
    std::size_t n = 0;
    for (const ParamInfo& p : param_info) n += p.var == v;
    return n;
}

} // namespace fp_flam3
