// flam3's variations 41-70 (variations.c) on double lanes: included by flam3/eval.cpp inside
// its per-target namespace, once per target (no include guard); vars-a-inl.hpp says what a
// case sees.

HWY_INLINE bool vars_b(const Ctx& c, std::uint32_t v, std::uint32_t ro) {
    const VD W = c.W();
    const double w = c.weight;
    switch (v) {
    case v_arch:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(mul(p.u(0), W), k(pi)), s, co);
            ox = mul(W, s), oy = quo(mul(W, mul(s, s)), co);
        });
    case v_tangent:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            ox = quo(mul(W, sin_of(p.tx)), cos_of(p.ty)), oy = mul(W, tan_of(p.ty));
        });
    case v_square:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            ox = mul(W, sub(p.u(0), k(0.5))), oy = mul(W, sub(p.u(1), k(0.5)));
        });
    case v_rays:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD ang = mul(mul(W, p.u(0)), k(pi));
            const VD r = quo(W, add(p.r2, k(eps)));
            const VD t = mul(mul(W, tan_of(ang)), r);
            ox = mul(t, cos_of(p.tx)), oy = mul(t, sin_of(p.ty));
        });
    case v_blade:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(mul(p.u(0), W), p.r), s, co);
            ox = mul(mul(W, p.tx), add(co, s)), oy = mul(mul(W, p.tx), sub(co, s));
        });
    case v_secant2:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD cr = cos_of(mul(W, p.r)), icr = quo(k(1.0), cr);
            ox = mul(W, p.tx);
            oy = sel(hn::Lt(cr, k(0.0)), mul(W, add(icr, k(1.0))), mul(W, sub(icr, k(1.0))));
        });
    case v_twintrian:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(mul(p.u(0), W), p.r), s, co);
            VD diff = add(mul(log_of(mul(s, s)), k(0.43429448190325182765)), co); // log10
            // flam3's badvalue: NaN or beyond 1e10 in magnitude.
            const auto bad = hn::Or(fs::is_nan(diff), hn::Gt(abs_of(diff), k(1e10)));
            diff = sel(bad, k(-30.0), diff);
            ox = mul(mul(W, p.tx), diff), oy = mul(mul(W, p.tx), sub(diff, mul(s, k(pi))));
        });
    case v_cross:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD s = sub(mul(p.tx, p.tx), mul(p.ty, p.ty));
            const VD r = mul(W, sqrt_of(quo(k(1.0), add(mul(s, s), k(eps)))));
            ox = mul(p.tx, r), oy = mul(p.ty, r);
        });
    case v_disc2:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(c.R(d_disc2_timespi), add(p.tx, p.ty)), s, co);
            const VD r = quo(mul(W, p.atan()), k(pi));
            ox = mul(add(s, c.R(d_disc2_cosadd)), r), oy = mul(add(co, c.R(d_disc2_sinadd)), r);
        });
    case v_super_shape:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD st, ct;
            sincos(add(mul(c.R(d_ss_pm4), p.atanyx()), k(pi / 4)), st, ct);
            const VD t1 = pow_of(abs_of(ct), c.P(p_super_shape_n2));
            const VD t2 = pow_of(abs_of(st), c.P(p_super_shape_n3));
            const double rnd = c.x.prm[p_super_shape_rnd];
            const VD rr = sub(add(mul(k(rnd), p.u(0)), mul(k(1.0 - rnd), p.r)), c.P(p_super_shape_holes));
            const VD r = quo(mul(mul(W, rr), pow_of(add(t1, t2), c.R(d_ss_pneg1_n1))), p.r);
            ox = mul(r, p.tx), oy = mul(r, p.ty);
        });
    case v_flower:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD r = quo(
                mul(mul(W, sub(p.u(0), c.P(p_flower_holes))), cos_of(mul(c.P(p_flower_petals), p.atanyx()))),
                p.r);
            ox = mul(r, p.tx), oy = mul(r, p.ty);
        });
    case v_conic:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD ct = quo(p.tx, p.r), e = c.P(p_conic_eccentricity);
            const VD r =
                quo(quo(mul(mul(W, sub(p.u(0), c.P(p_conic_holes))), e), add(k(1.0), mul(e, ct))), p.r);
            ox = mul(r, p.tx), oy = mul(r, p.ty);
        });
    case v_parabola:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.r, s, co);
            ox = mul(mul(mul(mul(c.P(p_parabola_height), W), s), s), p.u(0));
            oy = mul(mul(mul(c.P(p_parabola_width), W), co), p.u(1));
        });
    case v_bent2:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD nx = sel(hn::Lt(p.tx, k(0.0)), mul(p.tx, c.P(p_bent2_x)), p.tx);
            const VD ny = sel(hn::Lt(p.ty, k(0.0)), mul(p.ty, c.P(p_bent2_y)), p.ty);
            ox = mul(W, nx), oy = mul(W, ny);
        });
    case v_bipolar:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD t = add(p.r2, k(1.0)), x2 = mul(k(2.0), p.tx);
            const double ps = -pi / 2 * c.x.prm[p_bipolar_shift];
            VD y = add(mul(k(0.5), atan2_of(mul(k(2.0), p.ty), sub(p.r2, k(1.0)))), k(ps));
            const VD hi = add(k(-pi / 2), fmod_of(add(y, k(pi / 2)), k(pi)));
            const VD lo = sub(k(pi / 2), fmod_of(sub(k(pi / 2), y), k(pi)));
            y = sel(hn::Gt(y, k(pi / 2)), hi, sel(hn::Lt(y, k(-pi / 2)), lo, y));
            ox = mul(mul(mul(W, k(0.25)), k(2.0 / pi)), log_of(quo(add(t, x2), sub(t, x2))));
            oy = mul(mul(W, k(2.0 / pi)), y);
        });
    case v_boarders:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD rx = hn::Round(p.tx), ry = hn::Round(p.ty);
            const VD fx = sub(p.tx, rx), fy = sub(p.ty, ry);
            const VD hx = add(mul(fx, k(0.5)), rx), hy = add(mul(fy, k(0.5)), ry);
            // The four borders: x's sides (|fx| >= |fy|) and y's, each by its sign.
            const auto xside = hn::Ge(abs_of(fx), abs_of(fy));
            const auto xpos = hn::Ge(fx, k(0.0)), ypos = hn::Ge(fy, k(0.0));
            const VD bx_x = sel(xpos, add(hx, k(0.25)), sub(hx, k(0.25)));
            const VD by_x = sel(xpos, add(hy, mul(k(0.25), quo(fy, fx))), sub(hy, mul(k(0.25), quo(fy, fx))));
            const VD by_y = sel(ypos, add(hy, k(0.25)), sub(hy, k(0.25)));
            const VD bx_y = sel(ypos, add(hx, mul(quo(fx, fy), k(0.25))), sub(hx, mul(quo(fx, fy), k(0.25))));
            const auto inner = hn::Ge(p.u(0), k(0.75));
            ox = mul(W, sel(inner, hx, sel(xside, bx_x, bx_y)));
            oy = mul(W, sel(inner, hy, sel(xside, by_x, by_y)));
        });
    case v_butterfly:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD wx = mul(W, k(1.3029400317411197908970256609023)), y2 = mul(p.ty, k(2.0));
            const VD r = mul(
                wx, sqrt_of(quo(abs_of(mul(p.ty, p.tx)), add(add(k(eps), mul(p.tx, p.tx)), mul(y2, y2)))));
            ox = mul(r, p.tx), oy = mul(r, y2);
        });
    case v_cell:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const double size = c.x.prm[p_cell_size], inv = 1.0 / size;
            const VD X = floor_of(mul(p.tx, k(inv))), Y = floor_of(mul(p.ty, k(inv)));
            const VD dx = sub(p.tx, mul(X, k(size))), dy = sub(p.ty, mul(Y, k(size)));
            // Interleaved: non-negative cells to even numbers, negative ones to odd.
            const VD X2 = sel(hn::Ge(X, k(0.0)), mul(X, k(2.0)), neg(add(mul(k(2.0), X), k(1.0))));
            const VD Y2 = sel(hn::Ge(Y, k(0.0)), mul(Y, k(2.0)), neg(add(mul(k(2.0), Y), k(1.0))));
            ox = mul(W, add(dx, mul(X2, k(size))));
            oy = neg(mul(W, add(dy, mul(Y2, k(size)))));
        });
    case v_cpow:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD a = p.atanyx(), lnr = mul(k(0.5), log_of(p.r2));
            const double pw = c.x.prm[p_cpow_power];
            const double va = 2.0 * pi / pw, vc = c.x.prm[p_cpow_r] / pw, vd = c.x.prm[p_cpow_i] / pw;
            const VD ang = add(add(mul(k(vc), a), mul(k(vd), lnr)), mul(k(va), floor_of(mul(k(pw), p.u(0)))));
            const VD m = mul(W, exp_of(sub(mul(k(vc), lnr), mul(k(vd), a))));
            VD s, co;
            sincos(ang, s, co);
            ox = mul(m, co), oy = mul(m, s);
        });
    case v_curve:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            double xl = c.x.prm[p_curve_xlength] * c.x.prm[p_curve_xlength];
            double yl = c.x.prm[p_curve_ylength] * c.x.prm[p_curve_ylength];
            if (xl < 1e-20) xl = 1e-20;
            if (yl < 1e-20) yl = 1e-20;
            ox = mul(W, add(p.tx, mul(c.P(p_curve_xamp), exp_of(quo(neg(mul(p.ty, p.ty)), k(xl))))));
            oy = mul(W, add(p.ty, mul(c.P(p_curve_yamp), exp_of(quo(neg(mul(p.tx, p.tx)), k(yl))))));
        });
    case v_edisc:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD tmp = add(p.r2, k(1.0)), tmp2 = mul(k(2.0), p.tx);
            const VD xmax = mul(add(sqrt_of(add(tmp, tmp2)), sqrt_of(sub(tmp, tmp2))), k(0.5));
            const VD a1 = log_of(add(xmax, sqrt_of(sub(xmax, k(1.0)))));
            // acos(q) = atan2(sqrt((1 - q)(1 + q)), q)
            const VD q = quo(p.tx, xmax);
            const VD a2 = neg(atan2_of(sqrt_of(mul(sub(k(1.0), q), add(k(1.0), q))), q));
            const VD ww = quo(W, k(11.57034632));
            VD snv, csv;
            sincos(a1, snv, csv);
            snv = sel(hn::Gt(p.ty, k(0.0)), neg(snv), snv);
            ox = mul(mul(ww, cosh_of(a2)), csv), oy = mul(mul(ww, sinh_of(a2)), snv);
        });
    case v_elliptic:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD tmp = add(p.r2, k(1.0)), x2 = mul(k(2.0), p.tx);
            const VD xmax = mul(k(0.5), add(sqrt_of(add(tmp, x2)), sqrt_of(sub(tmp, x2))));
            const VD a = quo(p.tx, xmax);
            VD b = sub(k(1.0), mul(a, a)), ssx = sub(xmax, k(1.0));
            b = sel(hn::Lt(b, k(0.0)), k(0.0), sqrt_of(b));
            ssx = sel(hn::Lt(ssx, k(0.0)), k(0.0), sqrt_of(ssx));
            const VD ww = quo(W, k(pi / 2));
            ox = mul(ww, atan2_of(a, b));
            const VD l = mul(ww, log_of(add(xmax, ssx)));
            oy = sel(hn::Gt(p.ty, k(0.0)), l, neg(l));
        });
    case v_escher:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD a = p.atanyx(), lnr = mul(k(0.5), log_of(p.r2));
            const double vc = 0.5 * (1.0 + c.x.der[d_escher_ceb]), vd = 0.5 * c.x.der[d_escher_seb];
            const VD m = mul(W, exp_of(sub(mul(k(vc), lnr), mul(k(vd), a))));
            VD s, co;
            sincos(add(mul(k(vc), a), mul(k(vd), lnr)), s, co);
            ox = mul(m, co), oy = mul(m, s);
        });
    case v_foci:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD ex = mul(exp_of(p.tx), k(0.5)), enx = quo(k(0.25), ex);
            VD s, co;
            sincos(p.ty, s, co);
            const VD t = quo(W, sub(add(ex, enx), co));
            ox = mul(t, sub(ex, enx)), oy = mul(t, s);
        });
    case v_lazysusan:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD lx = c.P(p_lazysusan_x), ly = c.P(p_lazysusan_y);
            const VD x = sub(p.tx, lx), y = add(p.ty, ly);
            const VD r = sqrt_of(add(mul(x, x), mul(y, y)));
            VD s, co;
            sincos(add(add(atan2_of(y, x), c.P(p_lazysusan_spin)), mul(c.P(p_lazysusan_twist), sub(W, r))), s,
                   co);
            const VD ri = mul(W, r);
            const VD ro_ = mul(W, add(k(1.0), quo(c.P(p_lazysusan_space), r)));
            const auto in = hn::Lt(r, W);
            ox = sel(in, add(mul(ri, co), lx), add(mul(ro_, x), lx));
            oy = sel(in, sub(mul(ri, s), ly), sub(mul(ro_, y), ly));
        });
    case v_loonie:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD w2 = k(w * w);
            const VD r = mul(W, sqrt_of(sub(quo(w2, p.r2), k(1.0))));
            const auto in = hn::Lt(p.r2, w2);
            ox = sel(in, mul(r, p.tx), mul(W, p.tx)), oy = sel(in, mul(r, p.ty), mul(W, p.ty));
        });
    case v_modulus:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const auto mod = [&](VD t, double m) {
                const VD M = k(m), xr = k(2 * m);
                const VD above = add(neg(M), fmod_of(add(t, M), xr)), below = sub(M, fmod_of(sub(M, t), xr));
                return mul(W, sel(hn::Gt(t, M), above, sel(hn::Lt(t, neg(M)), below, t)));
            };
            ox = mod(p.tx, c.x.prm[p_modulus_x]), oy = mod(p.ty, c.x.prm[p_modulus_y]);
        });
    case v_oscilloscope:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const double tpf = 2 * pi * c.x.prm[p_oscilloscope_frequency];
            const double damp = c.x.prm[p_oscilloscope_damping];
            const VD amp = c.P(p_oscilloscope_amplitude), cs = cos_of(mul(k(tpf), p.tx));
            const VD t = damp == 0.0 ? add(mul(amp, cs), c.P(p_oscilloscope_separation))
                                     : add(mul(mul(amp, exp_of(mul(neg(abs_of(p.tx)), k(damp)))), cs),
                                           c.P(p_oscilloscope_separation));
            ox = mul(W, p.tx);
            oy = sel(hn::Le(abs_of(p.ty), t), neg(mul(W, p.ty)), mul(W, p.ty));
        });
    case v_polar2:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD p2v = quo(W, k(pi));
            ox = mul(p2v, p.atan()), oy = mul(quo(p2v, k(2.0)), log_of(p.r2));
        });
    default: return false;
    }
}
