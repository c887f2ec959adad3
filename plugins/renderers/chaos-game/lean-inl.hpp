// chaos-game's lean runs on the SIMD layer: blocks of few chains counting hits only (the papers'
// single orbit), several fused steps per call, each step's bins deposited right after it, so that
// the renderer's per-step work (its calls, polls and the lagged deposit) is paid once per run.
//
// A part of kernels-inl.hpp, which includes it inside fp_chaos::HWY_NAMESPACE once per target
// (its includes, namespace and per-target guard are kernels-inl.hpp's): not a header of its own.

/// The lean path of a block of few chains counting hits only (the papers' single orbit): up to
/// `steps` fused steps in one call, each step's bins deposited right after it, so that the
/// renderer's per-step work (its calls, polls and the lagged deposit) is paid once per run.
/// Stops after a step that restarted a chain, or (outside a steady run) left none active.
template <class T, bool Narrow>
HWY_INLINE fp_chaos::RunCounts fused_run_t(const fp_chaos::FusedArgs<T>& args, uint64_t steps) {
    const fp_chaos::FusedArgs<T> f = args;
    fp_chaos::RunCounts out;
    // Each step's bins are prefetched when known and incremented one step later: an
    // increment that misses the cache would otherwise hold up the steps behind it (a few
    // orbits have little else to overlap with).
    uint32_t lag[fp_chaos::lean_max] = {}; // (zeroed: GCC cannot see that pending guards it)
    const size_t nb = f.book.nb;
    size_t pending = 0;
    for (uint64_t s = 0; s < steps; ++s) {
        const fp_chaos::Counts c = fused_any<T, Narrow>(f);
        for (size_t i = 0; i < nb; ++i) hwy::Prefetch(f.hits + f.book.idx[i]);
        for (size_t i = 0; i < pending; ++i) ++f.hits[lag[i]];
        for (size_t i = 0; i < nb; ++i) lag[i] = f.book.idx[i];
        pending = nb;
        out.plotted += c.plotted;
        ++out.steps;
        out.last = c;
        if (c.restarts || (!f.steady && c.still == 0)) break;
    }
    for (size_t i = 0; i < pending; ++i) ++f.hits[lag[i]];
    return out;
}

/// The lean path of one chain of one map in a steady run (the papers' single orbit): the point,
/// its random stream and its pending bin stay in registers from step to step, and the map's
/// parameters are set once. Each step is fused_t's steady step for that chain in the same
/// operations (the map, the finite test, the bin, the deposit one step later; the stream moves
/// on at the steady run's end), so the bytes are the general path's (test_chaos_kernel). Stops after a step
/// that gave a non-finite point, as fused_run_t does on a restart.
template <class T, fp_chaos::LaneKind K>
HWY_NOINLINE fp_chaos::RunCounts orbit_run_t(const fp_chaos::FusedArgs<T>& args, uint64_t steps) {
    namespace fs = fp::simd::HWY_NAMESPACE;
    const fp_chaos::FusedArgs<T> f = args; // a local copy: see fused_t
    const hn::CappedTag<T, 1> d;
    const fp_chaos::BookArgs<T> bk = f.book;
    constexpr int np = K == fp_chaos::LaneKind::affine ? 6 : 3;
    hn::Vec<decltype(d)> p[6];
    for (int j = 0; j < 6; ++j) p[j] = hn::Set(d, j < np ? f.tables->p[j][0] : T(0));
    auto x = hn::LoadU(d, bk.x), y = hn::LoadU(d, bk.y);
    uint32_t* const hits = f.hits;
    uint32_t idx = 0, pending = 0;
    fp_chaos::RunCounts out;
    bool bad = false;
    // Gumowski-Mira: f(x_{n+1}), computed for y_{n+1}, is the next step's f(x_n) (the same
    // function of the same value), carried rather than computed again. With alpha = +0 the
    // damping term alpha (1 - 0.05 y^2) y is a zero of y's sign (or of the opposite one
    // beyond |y| = sqrt(20)), so y + it is y itself: the step skips it, which shortens the
    // chain of dependent operations, while |y| is small enough for the term to be finite
    // (a NaN term would make the point NaN: beyond that bound the term is computed).
    const auto gm_f = [&](hn::Vec<decltype(d)> u) { return fk::gm_f(p[1], p[2], u); };
    const T alpha = f.tables->p[0][0];
    const bool undamped = K == fp_chaos::LaneKind::gumowski_mira && alpha == T(0) && !std::signbit(alpha);
    const auto small = hn::Set(d, sizeof(T) == 8 ? T(1e100) : T(1e12)); // 0.05 y^2 far from overflow
    auto fx = K == fp_chaos::LaneKind::gumowski_mira ? gm_f(x) : x;
    for (uint64_t s = 0; s < steps && !bad; ++s) {
        if constexpr (K == fp_chaos::LaneKind::gumowski_mira) {
            hn::Vec<decltype(d)> nx;
            if (undamped && hn::AllTrue(d, hn::Lt(hn::Abs(y), small))) {
                nx = hn::Add(y, fx);
            } else {
                nx = hn::Add(hn::Add(y, fk::gm_damping(p[0], y)), fx);
            }
            fx = gm_f(nx);
            y = hn::Add(hn::Neg(x), fx);
            x = nx;
        } else {
            apply_kind<K>(d, p, x, y);
        }
        const auto fin = hn::And(fs::finite(x), fs::finite(y));
        idx = uint32_t(hn::GetLane(bin_index(d, bk, x, y, fin)));
        hwy::Prefetch(hits + idx);
        if (s > 0) ++hits[pending];
        pending = idx;
        bad = hn::AllFalse(d, fin);
        ++out.steps;
    }
    if (out.steps > 0) ++hits[pending];
    hn::StoreU(x, d, bk.x);
    hn::StoreU(y, d, bk.y);
    bk.prev[0] = 0;
    f.draw.restart[0] = bad ? 2 : 0;
    bk.idx[0] = idx;
    out.last.bad = out.last.restarts = bad ? 1 : 0;
    return out;
}

/// One chain of one map without the rules, in a steady run, takes orbit_run_t; one or two
/// chains take the narrow vectors (see FusedTag).
template <class T>
HWY_INLINE fp_chaos::RunCounts fused_run_any(const fp_chaos::FusedArgs<T>& f, uint64_t steps) {
    using K = fp_chaos::LaneKind;
    if (f.book.nb == 1 && f.steady && !f.program && f.tables->k == 1 && !f.tables->rules &&
        f.draw.active[0] != 0) {
        switch (f.tables->kind) {
        case K::affine: return orbit_run_t<T, K::affine>(f, steps);
        case K::gumowski_mira: return orbit_run_t<T, K::gumowski_mira>(f, steps);
        default: return orbit_run_t<T, K::circle>(f, steps);
        }
    }
    if (f.book.nb <= 2) return fused_run_t<T, true>(f, steps);
    return fused_run_t<T, false>(f, steps);
}
