// chaos-game's fused step on the SIMD layer (steps 1-5 of a block step in one pass, when every
// map is a known kernel of one kind: chaos-game.cpp's header): a vector of chains at a time, the
// draw, the map by the SDK's formulas (fixpoint/kernels-inl.hpp), the colour and the bookkeeping in
// registers, the previous step's deposits interleaved.
//
// It computes the generic path's draws and operations in the same order, so the image is the
// same bytes (tests/unit/test_chaos_kernel.cpp).
//
// A part of kernels-inl.hpp, which includes it inside fp_chaos::HWY_NAMESPACE once per target
// (its includes, namespace and per-target guard are kernels-inl.hpp's): not a header of its own.

/// The map of kind K applied to (x, y), with its parameters in lanes: p[0..5] in the order of
/// fp::KnownKernel's expressions (circle: ox, oy, r2; affine: a .. f; Gumowski-Mira: alpha,
/// mu, 2 (1 - mu)), by the SDK's formulas (fixpoint/kernels-inl.hpp), those of the transform plugins.
template <fp_chaos::LaneKind K, class D>
HWY_INLINE void apply_kind(D, const hn::Vec<D> (&p)[6], hn::Vec<D>& x, hn::Vec<D>& y) {
    if constexpr (K == fp_chaos::LaneKind::circle)
        fk::invert_in_circle(p[0], p[1], p[2], x, y);
    else if constexpr (K == fp_chaos::LaneKind::affine)
        fk::affine(p, x, y);
    else
        fk::gumowski_mira(p[0], p[1], p[2], x, y);
}

/// The parameters of K the chosen maps c have (per_map), for apply_kind.
template <fp_chaos::LaneKind K, class D>
HWY_INLINE void gather_kind(D d, const fp_chaos::LaneTables<hn::TFromD<D>>& t,
                            hn::Vec<hn::RebindToUnsigned<D>> c, hn::Vec<D> (&p)[6]) {
    if constexpr (K == fp_chaos::LaneKind::affine) {
        per_maps(
            d, [&](size_t j) { return t.p[j]; }, t.k, c, p);
    } else {
        hn::Vec<D> q[3];
        per_maps(
            d, [&](size_t j) { return t.p[j]; }, t.k, c, q);
        for (int j = 0; j < 6; ++j) p[j] = j < 3 ? q[j] : hn::Zero(d);
    }
}

/// The Picard step: (x, y) <- T(x, y), T the chosen map of each lane.
template <fp_chaos::LaneKind K, class D>
HWY_INLINE void apply_lanes(D d, const fp_chaos::LaneTables<hn::TFromD<D>>& t,
                            hn::Vec<hn::RebindToUnsigned<D>> c, hn::Vec<D>& x, hn::Vec<D>& y) {
    hn::Vec<D> p[6];
    gather_kind<K>(d, t, c, p);
    apply_kind<K>(d, p, x, y);
}

/// A scheme's step (LaneProgram; fp::run_program's meaning, in the same operations): the
/// registers in memory, a vector each (a few loads and stores an instruction, which stay in the
/// store buffer and L1), the maps' parameters gathered once for all the map instructions.
template <fp_chaos::LaneKind K, class D>
HWY_INLINE void program_lanes(D d, const fp_chaos::LaneTables<hn::TFromD<D>>& t,
                              const fp_chaos::LaneProgram<hn::TFromD<D>>& pr,
                              hn::Vec<hn::RebindToUnsigned<D>> c, hn::Vec<D>& x, hn::Vec<D>& y) {
    using T = hn::TFromD<D>;
    using Op = fp_chaos::ProgOp;
    constexpr size_t L = fp::simd::HWY_NAMESPACE::max_lanes<T>;
    alignas(HWY_MAX_BYTES) T rx[fp_chaos::LaneProgram<T>::max_regs * L];
    alignas(HWY_MAX_BYTES) T ry[fp_chaos::LaneProgram<T>::max_regs * L];
    hn::Vec<D> p[6];
    gather_kind<K>(d, t, c, p);
    hn::Store(x, d, rx);
    hn::Store(y, d, ry);
    for (uint32_t s = 0; s < pr.size; ++s) {
        const auto& in = pr.code[s];
        auto ux = hn::Load(d, rx + in.u * L), uy = hn::Load(d, ry + in.u * L);
        if (in.op == Op::map) {
            apply_kind<K>(d, p, ux, uy);
        } else if (in.op != Op::copy) {
            const auto k = [&](int j) { return hn::Set(d, in.k[j]); };
            const auto vx = hn::Load(d, rx + in.v * L), vy = hn::Load(d, ry + in.v * L);
            auto nx = hn::Add(hn::Add(hn::Mul(k(0), ux), hn::Mul(k(1), uy)),
                              hn::Add(hn::Mul(k(4), vx), hn::Mul(k(5), vy)));
            auto ny = hn::Add(hn::Add(hn::Mul(k(2), ux), hn::Mul(k(3), uy)),
                              hn::Add(hn::Mul(k(6), vx), hn::Mul(k(7), vy)));
            if (in.op == Op::lin3) {
                const auto wx = hn::Load(d, rx + in.w * L), wy = hn::Load(d, ry + in.w * L);
                nx = hn::Add(nx, hn::Add(hn::Mul(k(8), wx), hn::Mul(k(9), wy)));
                ny = hn::Add(ny, hn::Add(hn::Mul(k(10), wx), hn::Mul(k(11), wy)));
            }
            ux = nx, uy = ny;
        }
        hn::Store(ux, d, rx + in.dst * L);
        hn::Store(uy, d, ry + in.dst * L);
    }
    x = hn::Load(d, rx);
    y = hn::Load(d, ry);
}

/// The chains' colours updated by the rule with the chosen maps' colours, where they moved;
/// the new colours also in `col`, for the packing (k: t.k, from a local copy, so that its
/// lanes of map indices are the map lookup's own, not made again after the stores).
template <fp_chaos::LaneColour C, class D>
HWY_INLINE void colour_lanes(D, const fp_chaos::LaneTables<hn::TFromD<D>>& t, uint32_t k,
                             hn::Vec<hn::RebindToUnsigned<D>> c, hn::Mask<hn::RebindToUnsigned<D>> mv,
                             const fp_chaos::BookArgs<hn::TFromD<D>>& b, size_t i, ColourVecs<D>& col) {
    const hn::Rebind<float, D> df;
    const hn::RebindToUnsigned<decltype(df)> du32;
    hn::Vec<decltype(du32)> c32;
    hn::Mask<decltype(df)> m;
    if constexpr (sizeof(hn::TFromD<D>) == 4) {
        c32 = c;
        m = hn::RebindMask(df, mv);
    } else {
        c32 = hn::TruncateTo(du32, c);
        m = hn::MaskFromVec(
            hn::BitCast(df, hn::TruncateTo(du32, hn::VecFromMask(hn::RebindToUnsigned<D>(), mv))));
    }
    hn::Vec<decltype(df)> mc[3];
    per_maps(
        df, [&](size_t j) { return j == 0   ? t.cr
                                   : j == 1 ? t.cg
                                            : t.cb; }, k, c32, mc);
    auto one = [&](hn::Vec<decltype(df)> cm, float* chain) {
        const auto old = hn::LoadU(df, chain);
        const auto nc = C == fp_chaos::LaneColour::map ? cm : hn::Mul(hn::Add(old, cm), hn::Set(df, 0.5f));
        const auto v = hn::IfThenElse(m, nc, old);
        hn::StoreU(v, df, chain);
        return v;
    };
    col[0] = one(mc[0], b.cr + i);
    col[1] = one(mc[1], b.cg + i);
    col[2] = one(mc[2], b.cb + i);
}

/// bins[lag[l]] += the widened dep[l] for one chain l; the bin is listed in `full` (its count
/// at *nfull) when its hits reach spill_at. (The pointers by value: read through a reference
/// to the step's arguments, each deposit's store into the bins would make the compiler load
/// them anew, as it might have written them.)
HWY_INLINE void deposit_one(uint32_t* bins, const uint32_t* lag, const uint64_t* dep, uint32_t spill_at,
                            uint32_t* full, uint32_t* nfull, size_t l) {
    uint32_t* b = bins + 4 * size_t(lag[l]);
#if HWY_TARGET == HWY_SCALAR
    const uint64_t v = dep[l];
    b[0] += uint32_t(v & 0xffffu), b[1] += uint32_t((v >> 16) & 0xffffu);
    b[2] += uint32_t((v >> 32) & 0xffffu), b[3] += uint32_t(v >> 48);
    const uint32_t h = b[0];
#else
    const hn::FixedTag<uint32_t, 4> d4;
    const hn::FixedTag<uint16_t, 4> d16;
    const auto v = hn::Add(hn::LoadU(d4, b),
                           hn::PromoteTo(d4, hn::LoadU(d16, reinterpret_cast<const uint16_t*>(dep + l))));
    hn::StoreU(v, d4, b);
    const uint32_t h = hn::GetLane(v);
#endif
    if (HWY_UNLIKELY(h >= spill_at)) full[(*nfull)++] = lag[l];
}

/// Tallies: the 16-bit counter ci[l] (map * plane + bin) incremented for one chain l; its bin
/// lag[l] is listed in `full` when the counter reaches spill_at (state.hpp's
/// WorkerHist::tally, lagged).
HWY_INLINE void tally_one(uint32_t* bins, const uint32_t* lag, const uint32_t* ci, uint16_t spill_at,
                          uint32_t* full, uint32_t* nfull, size_t l) {
    fp_chaos::Tally16* n = reinterpret_cast<fp_chaos::Tally16*>(bins) + ci[l];
    const uint16_t v = uint16_t(*n + 1);
    *n = v;
    if (HWY_UNLIKELY(v >= spill_at)) full[(*nfull)++] = lag[l];
}

/// deposit_one (tally_one with tallies) for the nl chains from i: a whole vector's (MaxLanes,
/// known when compiling) unrolled, without a loop counter per deposit.
template <fp_chaos::LaneColour C, class D, class T>
HWY_INLINE void deposit_lagged(D, const fp_chaos::FusedArgs<T>& f, size_t i, size_t nl) {
    uint32_t* const bins = f.bins;
    const uint32_t* const lag = f.lag + i;
    const uint32_t spill_at = f.spill_at;
    uint32_t* const full = f.full;
    uint32_t* const nfull = f.nfull;
    const auto one = [&](size_t l) HWY_ATTR __attribute__((always_inline)) {
        if constexpr (C == fp_chaos::LaneColour::tally)
            tally_one(bins, lag, reinterpret_cast<const uint32_t*>(f.lag_dep) + i, uint16_t(spill_at), full,
                      nfull, l);
        else
            deposit_one(bins, lag, f.lag_dep + i, spill_at, full, nfull, l);
    };
    if (nl == hn::MaxLanes(D())) {
        // (A fold over the lanes: GCC keeps a loop of these rolled, and ignores an unroll
        // pragma on it.)
        const auto lanes = [&]<size_t... L>(std::index_sequence<L...>) HWY_ATTR
            __attribute__((always_inline)) {
            (one(L), ...);
        };
        lanes(std::make_index_sequence<hn::MaxLanes(D())>());
    } else {
        for (size_t l = 0; l < nl; ++l) one(l);
    }
}

// (Not inlined into its dispatchers: each variant is a function of its own, so that the
// compilers optimise a few dozen functions of ordinary size rather than one huge one.)
template <class D, fp_chaos::LaneKind K, bool Rules, fp_chaos::LaneColour C, bool Steady,
          class T = hn::TFromD<D>>
HWY_NOINLINE fp_chaos::Counts fused_t(const fp_chaos::FusedArgs<T>& args) {
    const D d;
    const hn::RebindToUnsigned<decltype(d)> du;
    using U = hn::TFromD<decltype(du)>;
    const size_t N = hn::Lanes(d);
    // Local copies: the stores through the arrays cannot alias them, so that nothing is
    // reloaded after each store.
    const fp_chaos::FusedArgs<T> f = args;
    const fp_chaos::LaneTables<T>& t = *f.tables;
    const fp_chaos::DrawArgs a = f.draw;
    const fp_chaos::BookArgs<T> bk = f.book;
    const uint32_t k = t.k;
    FP_DCHECK(a.nb <= fp_chaos::block_size && k >= 1 && k <= fp_chaos::table_size);
    // The colours' clamp is needed unless every colour is known in [0, 1] (FusedArgs).
    const bool clamp = !(f.colours_in_range && t.colours_in_range);
    const auto one = hn::Set(du, U(1)), zero = hn::Zero(du);
    fp_chaos::Counts n;
    // Each chain's draw (with the rules its first one) in a pass of its own, into `chosen`: it
    // depends on the streams and the previous maps alone, not on the points. In the main loop
    // its operations (pcg32's 64-bit multiply, the draw's) would head each vector's chain of
    // dependent ones and crowd the window of instructions the core overlaps: out of it, more
    // vectors' points are in flight at once. The streams advance as they did in the loop.
    if (Rules || k > 1) {
        for (size_t i = 0; i < a.nb; i += N) {
            const auto r = pcg_next(du, a.rs + i, a.ri + i);
            if constexpr (Rules)
                store32(du, draw_other(du, r, load32(du, a.prev + i), k, t.uniform, t.thr, t.alias),
                        a.chosen + i);
            else
                store32(du, alias_lanes(du, r, k, t.thr, t.alias), a.chosen + i);
        }
    }
    for (size_t i = 0; i < a.nb; i += N) {
        const size_t nl = a.nb - i < N ? a.nb - i : N;
        auto x = hn::LoadU(d, bk.x + i), y = hn::LoadU(d, bk.y + i);
        const auto x0 = x, y0 = y;
        const auto p = load32(du, bk.prev + i);
        // (The lanes past the block's last chain are inactive: run_block zeroes them, and every
        // store into `active` keeps them so; no mask of the live lanes is needed.)
        const auto act = hn::Ne(load32(du, bk.active + i), zero);
        // The draw: with the rules, among the maps allowed (not the previous one; for circles
        // not one whose set holds the point: Circle::inside, dx * dx + dy * dy < r2, NaN
        // allowed); else Walker's alias table.
        hn::Vec<decltype(du)> c;
        hn::Mask<decltype(du)> some;
        hn::Vec<D> lq[3];
        fk::Offset<hn::Vec<D>> off;
        bool direct = true;
        if constexpr (Rules) {
            // Paper 01's loop: for circles, the drawn circle's set (Circle::inside, dx * dx +
            // dy * dy < r2, NaN allowed) tested with its parameters in lanes; the direct draw's
            // `excluded` tests every circle (the same values as broadcasts of t.p[.][j]: see
            // LaneTables::wp).
            // The last test keeps its circles (ox, oy, r2) and its offset (dx, dy, dx * dx + dy *
            // dy): the inversion's own first operations on the same values, not done again below.
            const auto inside = [&](hn::Vec<decltype(du)> cc) {
                if constexpr (K != fp_chaos::LaneKind::circle) {
                    return hn::Ne(cc, cc);
                } else {
                    per_maps(
                        d, [&](size_t j) { return t.p[j]; }, k, cc, lq);
                    off = fk::offset(x, y, lq[0], lq[1]);
                    return hn::RebindMask(du, fk::in_circle(off, lq[2]));
                }
            };
            c = draw_paper(
                du, load32(du, bk.chosen + i), a.rs + i, a.ri + i, p, act, k, t.uniform, t.thr, t.alias, t.q,
                &t.wq[0][0], t.wide_lanes, inside,
                [&](uint32_t j, hn::Vec<decltype(du)> vj) {
                    const auto previous = hn::Eq(p, vj);
                    if constexpr (K != fp_chaos::LaneKind::circle) return previous;
                    const auto par = [&](int n) {
                        return j < t.wide_maps ? hn::Load(d, t.wp[n][j]) : hn::Set(d, t.p[n][j]);
                    };
                    return hn::Or(hn::RebindMask(du, fk::in_circle(x, y, par(0), par(1), par(2))), previous);
                },
                some, direct);
        } else if (k == 1) {
            // One map: the draw's output is not needed, but the stream moves on as it would
            // (start points after restarts come from it): here, or in a steady run at its end,
            // by the run's length at once (state.hpp's pcg_jump, by the renderer).
            if constexpr (!Steady) pcg_skip(du, a.rs + i, a.ri + i);
            c = zero;
            some = hn::Eq(zero, zero);
        } else {
            c = load32(du, bk.chosen + i);
            some = hn::Eq(zero, zero);
        }
        const auto mv = hn::And(act, some);
        FP_DCHECK(hn::AllTrue(du, hn::Or(hn::Not(mv), hn::Lt(c, hn::Set(du, U(k))))));
        const auto none_allowed = hn::AndNot(some, act);
        const auto rst = hn::IfThenElseZero(none_allowed, one);
        if (f.program) {
            program_lanes<K>(d, t, *f.program, c, x, y);
        } else if (K == fp_chaos::LaneKind::circle && Rules && !direct) {
            // apply_kind's inversion from the test's offset (p - o and |p - o|^2).
            fk::invert_in_circle(off, lq[0], lq[1], lq[2], x, y);
        } else {
            apply_lanes<K>(d, t, c, x, y);
        }
        const auto mvf = hn::RebindMask(d, mv);
        x = hn::IfThenElse(mvf, x, x0);
        y = hn::IfThenElse(mvf, y, y0);
        hn::StoreU(x, d, bk.x + i);
        hn::StoreU(y, d, bk.y + i);
        ColourVecs<D> col;
        if constexpr (C == fp_chaos::LaneColour::map || C == fp_chaos::LaneColour::average)
            colour_lanes<C>(d, t, k, c, mv, bk, i, col);
        // The bookkeeping of bookkeep_t on the new points, in registers.
        const auto fin = hn::RebindMask(
            du, hn::And(fp::simd::HWY_NAMESPACE::finite(x), fp::simd::HWY_NAMESPACE::finite(y)));
        const auto isbad = hn::AndNot(fin, mv);
        auto plot = hn::And(mv, fin);
        if constexpr (!Steady) {
            const auto age = load32(du, bk.age + i);
            const auto old = hn::Not(hn::Lt(age, hn::Set(du, U(bk.skip))));
            plot = hn::And(plot, old);
            store32(du, hn::Add(age, hn::IfThenElseZero(hn::AndNot(old, mv), one)), bk.age + i);
            store32(du, hn::IfThenZeroElse(plot, load32(du, bk.idle + i)), bk.idle + i);
            n.plotted += hn::CountTrue(du, plot);
        }
        store32(du, hn::IfThenElse(mv, c, p), bk.prev + i);
        const auto rs = hn::Or(rst, hn::IfThenElseZero(isbad, hn::Set(du, U(2))));
        store32(du, rs, bk.restart + i);
        const auto restarts = hn::Or(none_allowed, isbad); // (the lanes of rs not 0)
        if (HWY_UNLIKELY(!hn::AllFalse(du, restarts))) {
            n.bad += uint32_t(hn::CountTrue(du, isbad));
            n.restarts += uint32_t(hn::CountTrue(du, restarts));
        }
        const auto bin = bin_index(d, bk, x, y, hn::RebindMask(d, plot));
        FP_DCHECK(hn::AllTrue(du, hn::Lt(bin, hn::Set(du, U(bk.dummy + 1u)))));
        store32(du, bin, bk.idx + i);
        if constexpr (!Steady) {
            const auto still = hn::And(count_down(du, bk.left + i, plot), act);
            store32(du, hn::IfThenElseZero(still, one), bk.active + i);
            n.still += uint32_t(hn::CountTrue(du, still));
        }
        if constexpr (C == fp_chaos::LaneColour::tally) {
            // Each point's counter: map * plane + bin (the map of a point not plotted, in the
            // dummy bin, may be k, "none": taken as k - 1, a counter of that bin). Planes by map
            // rather than a bin's counters side by side: a map's points fill a region of their
            // own (the image of its set), so far fewer cache lines hold the counters a render
            // touches (bench/circles.yaml with map-colour: 1.13x on AVX-512, 1.18x on AVX2).
            const auto map = hn::Min(c, hn::Set(du, U(k - 1)));
            store32(du, hn::Add(bin, mul_small(du, map, hn::Set(du, U(f.plane)))),
                    reinterpret_cast<uint32_t*>(bk.dep) + i);
        } else if constexpr (C != fp_chaos::LaneColour::none) {
            pack_colours(d, bk, i, col, clamp);
        }
        if constexpr (C != fp_chaos::LaneColour::none) {
            // The previous step's points, whose bins are known from the start: their
            // read-modify-writes overlap this vector's arithmetic.
            if (f.lag) deposit_lagged<C>(d, f, i, nl);
        }
        if (C == fp_chaos::LaneColour::none && f.lag) {
            // The previous step's bins, whose addresses are known from the start: their
            // cache misses overlap this vector's arithmetic. A whole vector's without a
            // bound test per increment (those branches would take issue slots).
            if (nl == N)
                for (size_t l = 0; l < hn::MaxLanes(d); ++l) ++f.hits[f.lag[i + l]];
            else
                for (size_t l = 0; l < nl; ++l) ++f.hits[f.lag[i + l]];
        }
    }
    return n;
}

/// The vectors of the fused step: whole ones, or (Narrow) the fewest lanes a target offers for
/// a lean run of one or two orbits, whose steps wait on their divisions: the narrow forms of
/// the instructions have the shorter latencies.
template <class T, bool Narrow>
using FusedTag = std::conditional_t<Narrow, hn::CappedTag<T, sizeof(T) == 8 ? 1 : 2>, hn::ScalableTag<T>>;

template <class T, fp_chaos::LaneKind K, bool Rules, bool Narrow>
HWY_INLINE fp_chaos::Counts fused_colour(const fp_chaos::FusedArgs<T>& f) {
    using C = fp_chaos::LaneColour;
    using D = FusedTag<T, Narrow>;
    if constexpr (!Narrow) {
        if (f.tables->colour == C::map)
            return f.steady ? fused_t<D, K, Rules, C::map, true>(f) : fused_t<D, K, Rules, C::map, false>(f);
        if (f.tables->colour == C::average)
            return f.steady ? fused_t<D, K, Rules, C::average, true>(f)
                            : fused_t<D, K, Rules, C::average, false>(f);
        if (f.tables->colour == C::tally)
            return f.steady ? fused_t<D, K, Rules, C::tally, true>(f)
                            : fused_t<D, K, Rules, C::tally, false>(f);
    }
    return f.steady ? fused_t<D, K, Rules, C::none, true>(f) : fused_t<D, K, Rules, C::none, false>(f);
}

/// The rules (or the alias table) as a compile-time choice: circles come with the rules,
/// maps without sets with the alias table, unless a recipe says otherwise.
template <class T, fp_chaos::LaneKind K, bool Narrow>
HWY_INLINE fp_chaos::Counts fused_rules(const fp_chaos::FusedArgs<T>& f) {
    return f.tables->rules ? fused_colour<T, K, true, Narrow>(f) : fused_colour<T, K, false, Narrow>(f);
}

template <class T, bool Narrow = false>
HWY_INLINE fp_chaos::Counts fused_any(const fp_chaos::FusedArgs<T>& f) {
    using K = fp_chaos::LaneKind;
    switch (f.tables->kind) {
    case K::affine: return fused_rules<T, K::affine, Narrow>(f);
    case K::gumowski_mira: return fused_rules<T, K::gumowski_mira, Narrow>(f);
    default: return fused_rules<T, K::circle, Narrow>(f);
    }
}
