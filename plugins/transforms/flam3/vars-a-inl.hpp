// flam3's variations 0-40 (variations.c), one formula each, on double lanes: included by
// flam3/eval.cpp inside its per-target namespace, once per target (no include guard). Each
// case adds weight-scaled (ox, oy) for one vector of points: `p` holds t = (tx, ty), r^2 and
// r; p.atan() = atan2(tx, ty), p.atanyx() = atan2(ty, tx), p.sina() = tx / r, p.cosa() = ty / r;
// p.u(j) the variation's j-th random number. The formulas are written from flam3's, in its
// order of operations where that is cheap (so that the values agree to rounding).

HWY_INLINE bool vars_a(const Ctx& c, std::uint32_t v, std::uint32_t ro) {
    const VD W = c.W();
    switch (v) {
    case v_linear:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) { ox = mul(W, p.tx), oy = mul(W, p.ty); });
    case v_sinusoidal:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            ox = mul(W, sin_of(p.tx)), oy = mul(W, sin_of(p.ty));
        });
    case v_spherical:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD s = quo(W, add(p.r2, k(eps)));
            ox = mul(s, p.tx), oy = mul(s, p.ty);
        });
    case v_swirl:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.r2, s, co);
            ox = mul(W, sub(mul(s, p.tx), mul(co, p.ty)));
            oy = mul(W, add(mul(co, p.tx), mul(s, p.ty)));
        });
    case v_horseshoe:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD r = quo(W, add(p.r, k(eps)));
            ox = mul(mul(sub(p.tx, p.ty), add(p.tx, p.ty)), r);
            oy = mul(mul(mul(k(2.0), p.tx), p.ty), r);
        });
    case v_polar:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            ox = mul(W, mul(p.atan(), k(1.0 / pi)));
            oy = mul(W, sub(p.r, k(1.0)));
        });
    case v_handkerchief:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD a = p.atan();
            ox = mul(mul(W, p.r), sin_of(add(a, p.r)));
            oy = mul(mul(W, p.r), cos_of(sub(a, p.r)));
        });
    case v_heart:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(p.r, p.atan()), s, co);
            const VD r = mul(W, p.r);
            ox = mul(r, s), oy = mul(neg(r), co);
        });
    case v_disc:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD a = mul(p.atan(), k(1.0 / pi));
            VD s, co;
            sincos(mul(k(pi), p.r), s, co);
            ox = mul(mul(W, s), a), oy = mul(mul(W, co), a);
        });
    case v_spiral:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD r = add(p.r, k(eps)), r1 = quo(W, r);
            VD s, co;
            sincos(r, s, co);
            ox = mul(r1, add(p.cosa(), s)), oy = mul(r1, sub(p.sina(), co));
        });
    case v_hyperbolic:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD r = add(p.r, k(eps));
            ox = quo(mul(W, p.sina()), r), oy = mul(mul(W, p.cosa()), r);
        });
    case v_diamond:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.r, s, co);
            ox = mul(mul(W, p.sina()), co), oy = mul(mul(W, p.cosa()), s);
        });
    case v_ex:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD a = p.atan();
            const VD n0 = sin_of(add(a, p.r)), n1 = cos_of(sub(a, p.r));
            const VD m0 = mul(mul(mul(n0, n0), n0), p.r), m1 = mul(mul(mul(n1, n1), n1), p.r);
            ox = mul(W, add(m0, m1)), oy = mul(W, sub(m0, m1));
        });
    case v_julia:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            // flam3 adds pi on a random bit: here on u >= 1/2.
            const VD a = add(mul(k(0.5), p.atan()), hn::IfThenElseZero(hn::Ge(p.u(0), k(0.5)), k(pi)));
            const VD r = mul(W, sqrt_of(p.r));
            VD s, co;
            sincos(a, s, co);
            ox = mul(r, co), oy = mul(r, s);
        });
    case v_bent:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD nx = sel(hn::Lt(p.tx, k(0.0)), mul(p.tx, k(2.0)), p.tx);
            const VD ny = sel(hn::Lt(p.ty, k(0.0)), quo(p.ty, k(2.0)), p.ty);
            ox = mul(W, nx), oy = mul(W, ny);
        });
    case v_waves:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD nx = add(p.tx, mul(k(c.c(2)), sin_of(mul(p.ty, c.R(d_waves_dx2)))));
            const VD ny = add(p.ty, mul(k(c.c(3)), sin_of(mul(p.tx, c.R(d_waves_dy2)))));
            ox = mul(W, nx), oy = mul(W, ny);
        });
    case v_fisheye:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD r = quo(mul(k(2.0), W), add(p.r, k(1.0)));
            ox = mul(r, p.ty), oy = mul(r, p.tx);
        });
    case v_popcorn:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD dx = tan_of(mul(k(3.0), p.ty)), dy = tan_of(mul(k(3.0), p.tx));
            ox = mul(W, add(p.tx, mul(k(c.c(4)), sin_of(dx))));
            oy = mul(W, add(p.ty, mul(k(c.c(5)), sin_of(dy))));
        });
    case v_exponential:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD dx = mul(W, exp_of(sub(p.tx, k(1.0))));
            VD s, co;
            sincos(mul(k(pi), p.ty), s, co);
            ox = mul(dx, co), oy = mul(dx, s);
        });
    case v_power:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD r = mul(W, pow_of(p.r, p.sina()));
            ox = mul(r, p.cosa()), oy = mul(r, p.sina());
        });
    case v_cosine:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(p.tx, k(pi)), s, co);
            ox = mul(W, mul(co, cosh_of(p.ty))), oy = mul(W, mul(neg(s), sinh_of(p.ty)));
        });
    case v_rings:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const double dxs = c.c(4) * c.c(4) + eps;
            const VD dx = k(dxs);
            const VD r = mul(W, add(sub(fmod_of(add(p.r, dx), k(2 * dxs)), dx), mul(p.r, k(1 - dxs))));
            ox = mul(r, p.cosa()), oy = mul(r, p.sina());
        });
    case v_fan:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const double dx = pi * (c.c(4) * c.c(4) + eps), dy = c.c(5), dx2 = 0.5 * dx;
            VD a = p.atan();
            a = add(a, sel(hn::Gt(fmod_of(add(a, k(dy)), k(dx)), k(dx2)), k(-dx2), k(dx2)));
            const VD r = mul(W, p.r);
            VD s, co;
            sincos(a, s, co);
            ox = mul(r, co), oy = mul(r, s);
        });
    case v_blob:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const double lo = c.x.prm[p_blob_low], diff = c.x.prm[p_blob_high] - lo;
            const VD wave = add(k(0.5), mul(k(0.5), sin_of(mul(c.P(p_blob_waves), p.atan()))));
            const VD r = mul(p.r, add(k(lo), mul(k(diff), wave)));
            ox = mul(mul(W, p.sina()), r), oy = mul(mul(W, p.cosa()), r);
        });
    case v_pdj:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD nx1 = cos_of(mul(c.P(p_pdj_b), p.tx)), nx2 = sin_of(mul(c.P(p_pdj_c), p.tx));
            const VD ny1 = sin_of(mul(c.P(p_pdj_a), p.ty)), ny2 = cos_of(mul(c.P(p_pdj_d), p.ty));
            ox = mul(W, sub(ny1, nx1)), oy = mul(W, sub(nx2, ny2));
        });
    case v_fan2:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const double dy = c.x.prm[p_fan2_y], fx = c.x.prm[p_fan2_x];
            const double dx = pi * (fx * fx + eps), dx2 = 0.5 * dx;
            const VD a = p.atan();
            const VD t = sub(add(a, k(dy)), mul(k(dx), trunc_of(quo(add(a, k(dy)), k(dx)))));
            const VD a2 = sel(hn::Gt(t, k(dx2)), sub(a, k(dx2)), add(a, k(dx2)));
            const VD r = mul(W, p.r);
            VD s, co;
            sincos(a2, s, co);
            ox = mul(r, s), oy = mul(r, co);
        });
    case v_rings2:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const double val = c.x.prm[p_rings2_val], dxs = val * val + eps;
            const VD t = trunc_of(quo(add(p.r, k(dxs)), k(2.0 * dxs)));
            const VD r = add(p.r, add(mul(k(-2.0 * dxs), t), mul(p.r, k(1.0 - dxs))));
            ox = mul(mul(W, p.sina()), r), oy = mul(mul(W, p.cosa()), r);
        });
    case v_eyefish:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD r = quo(mul(W, k(2.0)), add(p.r, k(1.0)));
            ox = mul(r, p.tx), oy = mul(r, p.ty);
        });
    case v_bubble:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD r = quo(W, add(mul(k(0.25), p.r2), k(1.0)));
            ox = mul(r, p.tx), oy = mul(r, p.ty);
        });
    case v_cylinder:
        return each(c, ro,
                    [&](const In& p, VD& ox, VD& oy) { ox = mul(W, sin_of(p.tx)), oy = mul(W, p.ty); });
    case v_perspective:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD dist = c.P(p_perspective_dist);
            const VD t = quo(k(1.0), sub(dist, mul(p.ty, c.R(d_persp_vsin))));
            ox = mul(mul(mul(W, dist), p.tx), t);
            oy = mul(mul(mul(W, c.R(d_persp_vfcos)), p.ty), t);
        });
    case v_noise:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(mul(p.u(0), k(2.0)), k(pi)), s, co);
            const VD r = mul(W, p.u(1));
            ox = mul(mul(p.tx, r), co), oy = mul(mul(p.ty, r), s);
        });
    case v_julian:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD t = trunc_of(mul(c.R(d_julian_rn), p.u(0)));
            const VD a = quo(add(p.atanyx(), mul(k(2 * pi), t)), c.P(p_julian_power));
            const VD r = mul(W, pow_of(p.r2, c.R(d_julian_cn)));
            VD s, co;
            sincos(a, s, co);
            ox = mul(r, co), oy = mul(r, s);
        });
    case v_juliascope:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD t = trunc_of(mul(c.R(d_juliascope_rn), p.u(0)));
            const auto even = hn::Eq(sub(t, mul(k(2.0), floor_of(mul(t, k(0.5))))), k(0.0));
            const VD base = mul(k(2 * pi), t);
            const VD a =
                quo(sel(even, add(base, p.atanyx()), sub(base, p.atanyx())), c.P(p_juliascope_power));
            VD s, co;
            sincos(a, s, co);
            const VD r = mul(W, pow_of(p.r2, c.R(d_juliascope_cn)));
            ox = mul(r, co), oy = mul(r, s);
        });
    case v_blur:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(mul(p.u(0), k(2.0)), k(pi)), s, co);
            const VD r = mul(W, p.u(1));
            ox = mul(r, co), oy = mul(r, s);
        });
    case v_gaussian_blur:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(mul(p.u(0), k(2.0)), k(pi)), s, co);
            const VD r = mul(W, sub(add(add(add(p.u(1), p.u(2)), p.u(3)), p.u(4)), k(2.0)));
            ox = mul(r, co), oy = mul(r, s);
        });
    case v_radial_blur:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD g = mul(W, sub(add(add(add(p.u(0), p.u(1)), p.u(2)), p.u(3)), k(2.0)));
            VD s, co;
            sincos(add(p.atanyx(), mul(c.R(d_radial_spin), g)), s, co);
            const VD rz = sub(mul(c.R(d_radial_zoom), g), k(1.0));
            ox = add(mul(p.r, co), mul(rz, p.tx)), oy = add(mul(p.r, s), mul(rz, p.ty));
        });
    case v_pie:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD slices = c.P(p_pie_slices);
            const VD sl = trunc_of(add(mul(p.u(0), slices), k(0.5)));
            const VD a = add(c.P(p_pie_rotation),
                             quo(mul(k(2.0 * pi), add(sl, mul(p.u(1), c.P(p_pie_thickness)))), slices));
            const VD r = mul(W, p.u(2));
            VD s, co;
            sincos(a, s, co);
            ox = mul(r, co), oy = mul(r, s);
        });
    case v_ngon:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD rf = pow_of(p.r2, k(c.x.prm[p_ngon_power] / 2.0));
            const VD th = p.atanyx();
            const double b = 2 * pi / c.x.prm[p_ngon_sides];
            VD phi = sub(th, mul(k(b), floor_of(quo(th, k(b)))));
            phi = sel(hn::Gt(phi, k(b / 2)), sub(phi, k(b)), phi);
            VD amp = add(mul(c.P(p_ngon_corners), sub(quo(k(1.0), add(cos_of(phi), k(eps))), k(1.0))),
                         c.P(p_ngon_circle));
            amp = quo(amp, add(rf, k(eps)));
            ox = mul(mul(W, p.tx), amp), oy = mul(mul(W, p.ty), amp);
        });
    case v_curl:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD c1 = c.P(p_curl_c1), c2 = c.P(p_curl_c2);
            const VD re = add(add(k(1.0), mul(c1, p.tx)), mul(c2, sub(mul(p.tx, p.tx), mul(p.ty, p.ty))));
            const VD im = add(mul(c1, p.ty), mul(mul(mul(k(2.0), c2), p.tx), p.ty));
            const VD r = quo(W, add(mul(re, re), mul(im, im)));
            ox = mul(add(mul(p.tx, re), mul(p.ty, im)), r);
            oy = mul(sub(mul(p.ty, re), mul(p.tx, im)), r);
        });
    case v_rectangles:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const double rx = c.x.prm[p_rectangles_x], ry = c.x.prm[p_rectangles_y];
            ox = rx == 0
                     ? mul(W, p.tx)
                     : mul(W, sub(mul(add(mul(k(2.0), floor_of(quo(p.tx, k(rx)))), k(1.0)), k(rx)), p.tx));
            oy = ry == 0
                     ? mul(W, p.ty)
                     : mul(W, sub(mul(add(mul(k(2.0), floor_of(quo(p.ty, k(ry)))), k(1.0)), k(ry)), p.ty));
        });
    default: return false;
    }
}
