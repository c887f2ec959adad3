// flam3's variations 71-98 (variations.c) on double lanes: included by flam3/eval.cpp inside
// its per-target namespace, once per target (no include guard); vars-a-inl.hpp says what a
// case sees. The complex functions (82-95, by cothe) keep flam3's signs: cos, csc, sech and
// csch come out conjugated.

HWY_INLINE bool vars_c(const Ctx& c, std::uint32_t v, std::uint32_t ro) {
    const VD W = c.W();
    switch (v) {
    case v_popcorn2:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD pc = c.P(p_popcorn2_c);
            ox = mul(W, add(p.tx, mul(c.P(p_popcorn2_x), sin_of(tan_of(mul(p.ty, pc))))));
            oy = mul(W, add(p.ty, mul(c.P(p_popcorn2_y), sin_of(tan_of(mul(p.tx, pc))))));
        });
    case v_scry:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD r = quo(k(1.0), mul(p.r, add(p.r2, quo(k(1.0), add(W, k(eps))))));
            ox = mul(p.tx, r), oy = mul(p.ty, r);
        });
    case v_separation:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const auto sep = [&](VD t, double s, double inside) {
                const VD h = sqrt_of(add(mul(t, t), k(s * s)));
                return sel(hn::Gt(t, k(0.0)), mul(W, sub(h, mul(t, k(inside)))),
                           neg(mul(W, add(h, mul(t, k(inside))))));
            };
            ox = sep(p.tx, c.x.prm[p_separation_x], c.x.prm[p_separation_xinside]);
            oy = sep(p.ty, c.x.prm[p_separation_y], c.x.prm[p_separation_yinside]);
        });
    case v_split:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD cy = cos_of(mul(mul(p.tx, c.P(p_split_xsize)), k(pi)));
            const VD cx = cos_of(mul(mul(p.ty, c.P(p_split_ysize)), k(pi)));
            oy = sel(hn::Ge(cy, k(0.0)), mul(W, p.ty), neg(mul(W, p.ty)));
            ox = sel(hn::Ge(cx, k(0.0)), mul(W, p.tx), neg(mul(W, p.tx)));
        });
    case v_splits:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD sx = c.P(p_splits_x), sy = c.P(p_splits_y);
            ox = mul(W, sel(hn::Ge(p.tx, k(0.0)), add(p.tx, sx), sub(p.tx, sx)));
            oy = mul(W, sel(hn::Ge(p.ty, k(0.0)), add(p.ty, sy), sub(p.ty, sy)));
        });
    case v_stripes:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD rx = floor_of(add(p.tx, k(0.5))), fx = sub(p.tx, rx);
            ox = mul(W, add(mul(fx, k(1.0 - c.x.prm[p_stripes_space])), rx));
            oy = mul(W, add(p.ty, mul(mul(fx, fx), c.P(p_stripes_warp))));
        });
    case v_wedge:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const double angle = c.x.prm[p_wedge_angle], count = c.x.prm[p_wedge_count];
            VD a = add(p.atanyx(), mul(c.P(p_wedge_swirl), p.r));
            const VD cc = floor_of(mul(mul(add(mul(k(count), a), k(pi)), k(1.0 / pi)), k(0.5)));
            const double comp = 1 - angle * count * (1.0 / pi) * 0.5;
            a = add(mul(a, k(comp)), mul(cc, k(angle)));
            const VD r = mul(W, add(p.r, c.P(p_wedge_hole)));
            VD s, co;
            sincos(a, s, co);
            ox = mul(r, co), oy = mul(r, s);
        });
    case v_wedge_julia:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD r = mul(W, pow_of(p.r2, c.R(d_wj_cn)));
            const VD t = trunc_of(mul(c.R(d_wj_rn), p.u(0)));
            VD a = quo(add(p.atanyx(), mul(k(2 * pi), t)), c.P(p_wedge_julia_power));
            const VD cc =
                floor_of(mul(mul(add(mul(c.P(p_wedge_julia_count), a), k(pi)), k(1.0 / pi)), k(0.5)));
            a = add(mul(a, c.R(d_wj_cf)), mul(cc, c.P(p_wedge_julia_angle)));
            VD s, co;
            sincos(a, s, co);
            ox = mul(r, co), oy = mul(r, s);
        });
    case v_wedge_sph:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const double angle = c.x.prm[p_wedge_sph_angle], count = c.x.prm[p_wedge_sph_count];
            VD r = quo(k(1.0), add(p.r, k(eps)));
            VD a = add(p.atanyx(), mul(c.P(p_wedge_sph_swirl), r));
            const VD cc = floor_of(mul(mul(add(mul(k(count), a), k(pi)), k(1.0 / pi)), k(0.5)));
            const double comp = 1 - angle * count * (1.0 / pi) * 0.5;
            a = add(mul(a, k(comp)), mul(cc, k(angle)));
            r = mul(W, add(r, c.P(p_wedge_sph_hole)));
            VD s, co;
            sincos(a, s, co);
            ox = mul(r, co), oy = mul(r, s);
        });
    case v_whorl:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD d = sub(W, p.r);
            const VD a = add(p.atanyx(),
                             sel(hn::Lt(p.r, W), quo(c.P(p_whorl_inside), d), quo(c.P(p_whorl_outside), d)));
            VD s, co;
            sincos(a, s, co);
            ox = mul(mul(W, p.r), co), oy = mul(mul(W, p.r), s);
        });
    case v_waves2:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            ox = mul(W, add(p.tx, mul(c.P(p_waves2_scalex), sin_of(mul(p.ty, c.P(p_waves2_freqx))))));
            oy = mul(W, add(p.ty, mul(c.P(p_waves2_scaley), sin_of(mul(p.tx, c.P(p_waves2_freqy))))));
        });
    case v_exp:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD e = exp_of(p.tx);
            VD s, co;
            sincos(p.ty, s, co);
            ox = mul(mul(W, e), co), oy = mul(mul(W, e), s);
        });
    case v_log:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            ox = mul(mul(W, k(0.5)), log_of(p.r2)), oy = mul(W, p.atanyx());
        });
    case v_sin:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.tx, s, co);
            ox = mul(mul(W, s), cosh_of(p.ty)), oy = mul(mul(W, co), sinh_of(p.ty));
        });
    case v_cos:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.tx, s, co);
            ox = mul(mul(W, co), cosh_of(p.ty)), oy = neg(mul(mul(W, s), sinh_of(p.ty)));
        });
    case v_tan:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(k(2.0), p.tx), s, co);
            const VD y2 = mul(k(2.0), p.ty);
            const VD den = quo(k(1.0), add(co, cosh_of(y2)));
            ox = mul(mul(W, den), s), oy = mul(mul(W, den), sinh_of(y2));
        });
    case v_sec:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.tx, s, co);
            const VD den = quo(k(2.0), add(cos_of(mul(k(2.0), p.tx)), cosh_of(mul(k(2.0), p.ty))));
            ox = mul(mul(mul(W, den), co), cosh_of(p.ty)), oy = mul(mul(mul(W, den), s), sinh_of(p.ty));
        });
    case v_csc:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.tx, s, co);
            const VD den = quo(k(2.0), sub(cosh_of(mul(k(2.0), p.ty)), cos_of(mul(k(2.0), p.tx))));
            ox = mul(mul(mul(W, den), s), cosh_of(p.ty)), oy = neg(mul(mul(mul(W, den), co), sinh_of(p.ty)));
        });
    case v_cot:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(k(2.0), p.tx), s, co);
            const VD y2 = mul(k(2.0), p.ty);
            const VD den = quo(k(1.0), sub(cosh_of(y2), co));
            ox = mul(mul(W, den), s), oy = mul(mul(mul(W, den), k(-1.0)), sinh_of(y2));
        });
    case v_sinh:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.ty, s, co);
            ox = mul(mul(W, sinh_of(p.tx)), co), oy = mul(mul(W, cosh_of(p.tx)), s);
        });
    case v_cosh:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.ty, s, co);
            ox = mul(mul(W, cosh_of(p.tx)), co), oy = mul(mul(W, sinh_of(p.tx)), s);
        });
    case v_tanh:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(k(2.0), p.ty), s, co);
            const VD x2 = mul(k(2.0), p.tx);
            const VD den = quo(k(1.0), add(co, cosh_of(x2)));
            ox = mul(mul(W, den), sinh_of(x2)), oy = mul(mul(W, den), s);
        });
    case v_sech:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.ty, s, co);
            const VD den = quo(k(2.0), add(cos_of(mul(k(2.0), p.ty)), cosh_of(mul(k(2.0), p.tx))));
            ox = mul(mul(mul(W, den), co), cosh_of(p.tx)), oy = neg(mul(mul(mul(W, den), s), sinh_of(p.tx)));
        });
    case v_csch:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(p.ty, s, co);
            const VD den = quo(k(2.0), sub(cosh_of(mul(k(2.0), p.tx)), cos_of(mul(k(2.0), p.ty))));
            ox = mul(mul(mul(W, den), sinh_of(p.tx)), co), oy = neg(mul(mul(mul(W, den), cosh_of(p.tx)), s));
        });
    case v_coth:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            VD s, co;
            sincos(mul(k(2.0), p.ty), s, co);
            const VD x2 = mul(k(2.0), p.tx);
            const VD den = quo(k(1.0), sub(cosh_of(x2), co));
            ox = mul(mul(W, den), sinh_of(x2)), oy = mul(mul(W, den), s);
        });
    case v_auger:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD f = c.P(p_auger_freq), aw = c.P(p_auger_weight), sc = c.P(p_auger_scale);
            const VD s = sin_of(mul(f, p.tx)), t = sin_of(mul(f, p.ty));
            const VD dy = add(p.ty, mul(aw, add(quo(mul(sc, s), k(2.0)), mul(abs_of(p.ty), s))));
            const VD dx = add(p.tx, mul(aw, add(quo(mul(sc, t), k(2.0)), mul(abs_of(p.tx), t))));
            ox = mul(W, add(p.tx, mul(c.P(p_auger_sym), sub(dx, p.tx)))), oy = mul(W, dy);
        });
    case v_flux:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD xpw = add(p.tx, W), xmw = sub(p.tx, W), y2 = mul(p.ty, p.ty);
            const VD avgr =
                mul(mul(W, add(k(2.0), c.P(p_flux_spread))),
                    sqrt_of(quo(sqrt_of(add(y2, mul(xpw, xpw))), sqrt_of(add(y2, mul(xmw, xmw))))));
            const VD avga = mul(sub(atan2_of(p.ty, xmw), atan2_of(p.ty, xpw)), k(0.5));
            VD s, co;
            sincos(avga, s, co);
            ox = mul(avgr, co), oy = mul(avgr, s);
        });
    case v_mobius:
        return each(c, ro, [&](const In& p, VD& ox, VD& oy) {
            const VD ra = c.P(p_mobius_re_a), ia = c.P(p_mobius_im_a), rb = c.P(p_mobius_re_b),
                     ib = c.P(p_mobius_im_b), rc = c.P(p_mobius_re_c), ic = c.P(p_mobius_im_c),
                     rd = c.P(p_mobius_re_d), id = c.P(p_mobius_im_d);
            const VD reu = add(sub(mul(ra, p.tx), mul(ia, p.ty)), rb);
            const VD imu = add(add(mul(ra, p.ty), mul(ia, p.tx)), ib);
            const VD rev = add(sub(mul(rc, p.tx), mul(ic, p.ty)), rd);
            const VD imv = add(add(mul(rc, p.ty), mul(ic, p.tx)), id);
            const VD rad = quo(W, add(mul(rev, rev), mul(imv, imv)));
            ox = mul(rad, add(mul(reu, rev), mul(imu, imv)));
            oy = mul(rad, sub(mul(imu, rev), mul(reu, imv)));
        });
    default: return false;
    }
}
