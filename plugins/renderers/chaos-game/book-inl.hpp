// chaos-game's bookkeeping and deposit on the SIMD layer (steps 5-6 of a block step:
// chaos-game.cpp's header; what the bookkeeping computes: block.hpp): after a step, each chain's
// finite test, plot, age, previous map, idle count, points left and activity, its bin and its
// packed colour; and the deposit of the packed colours into a worker's bins.
//
// A part of kernels-inl.hpp, which includes it inside fp_chaos::HWY_NAMESPACE once per target
// (its includes, namespace and per-target guard are kernels-inl.hpp's): not a header of its own.

// ---------------------------------------------------------------- bookkeeping
/// round(c * 65535) of a colour clamped to [0, 1] (NaN to 0), as 32-bit integers: the lanes of
/// fp::quantise_colour, in the same operations. Without `clamp` the caller knows the lanes in
/// [0, 1], where the clamp changes nothing.
template <class DF>
HWY_INLINE hn::Vec<hn::RebindToSigned<DF>> quantise(DF df, hn::Vec<DF> c, bool clamp) {
    const hn::RebindToSigned<DF> di;
    auto c1 = c;
    if (clamp) {
        const auto zero = hn::Zero(df), one = hn::Set(df, 1.0f);
        const auto c0 = hn::IfThenElse(hn::Gt(c, zero), c, zero);
        c1 = hn::IfThenElse(hn::Lt(c0, one), c0, one);
    }
    // floor of v = c1 * 65535 + 0.5 in [0.5, 65535.5]: truncated, then 2^23 added, whose sum is
    // exact and holds the integer in its mantissa (as bin_index does): the integers of a
    // converting instruction without the overflow fix-up of Highway's ConvertTo.
    const auto v = hn::Add(hn::Mul(c1, hn::Set(df, 65535.0f)), hn::Set(df, 0.5f));
    const auto big = hn::Set(df, 8388608.0f);
    return hn::Sub(hn::BitCast(di, hn::Add(hn::Trunc(v), big)), hn::BitCast(di, big));
}

/// The chains' colours (r, g, b) in lanes of floats, one per lane of D.
template <class D>
using ColourVecs = hn::Vec<hn::Rebind<float, D>>[3];

/// dep[i] = 1 | r << 16 | g << 32 | b << 48 for the lanes of one vector of chains, of
/// colours col (the values at a.cr + i, a.cg + i, a.cb + i); `clamp` as quantise's.
template <class D>
HWY_INLINE void pack_colours(D, const fp_chaos::BookArgs<hn::TFromD<D>>& a, size_t i,
                             const ColourVecs<D>& col, bool clamp = true) {
    const hn::Rebind<float, D> df;
    const hn::Rebind<uint32_t, D> d32;
    const auto qr = hn::BitCast(d32, quantise(df, col[0], clamp));
    const auto qg = hn::BitCast(d32, quantise(df, col[1], clamp));
    const auto qb = hn::BitCast(d32, quantise(df, col[2], clamp));
    const auto lo = hn::Or(hn::Set(d32, 1u), hn::ShiftLeft<16>(qr));
    const auto hi = hn::Or(qg, hn::ShiftLeft<16>(qb));
#if HWY_TARGET == HWY_SCALAR
    a.dep[i] = uint64_t(hn::GetLane(lo)) | uint64_t(hn::GetLane(hi)) << 32;
#else
    if constexpr (sizeof(hn::TFromD<D>) == 4) {
        // Interleaving lo and hi gives the 64-bit words (lo in the low half: little-endian),
        // but within each 128-bit block: InterleaveLower pairs lanes 0 and 1 of every block,
        // InterleaveUpper lanes 2 and 3. So the lanes are first permuted so that block b holds
        // chains 2b, 2b + 1 (lanes 0, 1) and N/2 + 2b, N/2 + 2b + 1 (lanes 2, 3): the lower
        // interleave is then chains 0 .. N/2 - 1 in order, the upper one the rest. (Two
        // permutes and two interleaves, where widening each half took ten instructions.)
        const hn::Repartition<uint64_t, decltype(d32)> d64;
        const size_t h = hn::Lanes(d64);
        const auto j = hn::Iota(d32, 0);
        const auto m = hn::And(j, hn::Set(d32, 3u));
        const auto src =
            hn::Add(hn::Add(hn::And(m, hn::Set(d32, 1u)), hn::ShiftLeft<1>(hn::ShiftRight<2>(j))),
                    hn::Mul(hn::ShiftRight<1>(m), hn::Set(d32, uint32_t(hn::Lanes(d32) / 2))));
        const auto idx = hn::IndicesFromVec(d32, src);
        const auto plo = hn::TableLookupLanes(lo, idx), phi = hn::TableLookupLanes(hi, idx);
        hn::StoreU(hn::BitCast(d64, hn::InterleaveLower(d32, plo, phi)), d64, a.dep + i);
        hn::StoreU(hn::BitCast(d64, hn::InterleaveUpper(d32, plo, phi)), d64, a.dep + i + h);
    } else {
        const hn::Rebind<uint64_t, D> d64;
        hn::StoreU(hn::Or(hn::PromoteTo(d64, lo), hn::ShiftLeft<32>(hn::PromoteTo(d64, hi))), d64, a.dep + i);
    }
#endif
}

/// The bin index of plotted points (see chaos-game.cpp's "Binning"): dummy when not plotted.
template <class D>
HWY_INLINE hn::Vec<hn::RebindToUnsigned<D>> bin_index(D d, const fp_chaos::BookArgs<hn::TFromD<D>>& a,
                                                      hn::Vec<D> x, hn::Vec<D> y, hn::Mask<D> plot) {
    const hn::RebindToUnsigned<D> du;
    using U = hn::TFromD<decltype(du)>;
    const auto xmin = hn::Set(d, a.xmin), ymax = hn::Set(d, a.ymax);
    const auto in = hn::And(hn::And(plot, hn::And(hn::Ge(x, xmin), hn::Lt(x, hn::Set(d, a.xmax)))),
                            hn::And(hn::Gt(y, hn::Set(d, a.ymin)), hn::Le(y, ymax)));
    const auto fx = hn::Mul(hn::Sub(x, xmin), hn::Set(d, a.scx));
    const auto fy = hn::Mul(hn::Sub(ymax, y), hn::Set(d, a.scy));
    // floor of f in [0, 2^23) (the products are below the image size, 65536): truncated,
    // then 2^23 (2^52) added, whose sum is exact and has the integer in its mantissa. The
    // same integers as a converting instruction, without the overflow fix-up that Highway's
    // ConvertTo adds (values this small never overflow). Lanes outside the window (NaN,
    // negative or huge f) give meaningless integers, but no fault: the dummy replaces them.
    auto trunc = [&](hn::Vec<D> f) {
        constexpr hn::TFromD<D> big =
            sizeof(U) == 4 ? hn::TFromD<D>(8388608.0) : hn::TFromD<D>(4503599627370496.0);
        const auto sum = hn::BitCast(du, hn::Add(hn::Trunc(f), hn::Set(d, big)));
        return hn::Sub(sum, hn::BitCast(du, hn::Set(d, big)));
    };
    const auto ix = hn::Min(trunc(fx), hn::Set(du, U(a.W - 1)));
    const auto iy = hn::Min(trunc(fy), hn::Set(du, U(a.H - 1)));
    // The row within the strip: rows above it wrap to large values, so one unsigned compare
    // keeps [row0, row0 + rows).
    const auto ry = hn::Sub(iy, hn::Set(du, U(a.row0)));
    const auto keep = hn::And(hn::RebindMask(du, in), hn::Lt(ry, hn::Set(du, U(a.rows))));
    return hn::IfThenElse(keep, hn::Add(mul_small(du, ry, hn::Set(du, U(a.W))), ix), hn::Set(du, U(a.dummy)));
}

template <class T>
HWY_INLINE fp_chaos::Counts bookkeep_t(const fp_chaos::BookArgs<T>& args, bool colour) {
    const fp_chaos::BookArgs<T> a = args; // a local copy: see fused_t
    const hn::ScalableTag<T> d;
    const hn::RebindToUnsigned<decltype(d)> du;
    using U = hn::TFromD<decltype(du)>;
    const size_t N = hn::Lanes(d);
    const auto one = hn::Set(du, U(1)), zero = hn::Zero(du);
    const auto none = hn::Set(du, U(a.none)), skip = hn::Set(du, U(a.skip));
    const bool bounded = a.bound > 0;
    const auto bound = hn::Set(d, a.bound);
    FP_DCHECK(a.nb <= fp_chaos::block_size);
    fp_chaos::Counts n;
    for (size_t i = 0; i < a.nb; i += N) {
        const auto live = hn::RebindMask(du, hn::FirstN(d, a.nb - i < N ? a.nb - i : N));
        const auto x = hn::LoadU(d, a.x + i), y = hn::LoadU(d, a.y + i);
        const auto c = load32(du, a.chosen + i);
        const auto mv = hn::Lt(c, none);
        auto fin = hn::RebindMask(
            du, hn::And(fp::simd::HWY_NAMESPACE::finite(x), fp::simd::HWY_NAMESPACE::finite(y)));
        if (bounded)
            fin = hn::And(fin,
                          hn::RebindMask(du, hn::And(hn::Le(hn::Abs(x), bound), hn::Le(hn::Abs(y), bound))));
        const auto isbad = hn::AndNot(fin, mv);
        const auto age = load32(du, a.age + i);
        const auto old = hn::Not(hn::Lt(age, skip));
        const auto plot = hn::And(hn::And(mv, fin), old);
        store32(du, hn::Add(age, hn::IfThenElseZero(hn::AndNot(old, mv), one)), a.age + i);
        store32(du, hn::IfThenElse(mv, c, load32(du, a.prev + i)), a.prev + i);
        store32(du, hn::IfThenZeroElse(plot, load32(du, a.idle + i)), a.idle + i);
        const auto rs = hn::Or(load32(du, a.restart + i), hn::IfThenElseZero(isbad, hn::Set(du, U(2))));
        store32(du, rs, a.restart + i);
        store32(du, hn::IfThenElseZero(plot, one), a.plotf + i);
        const auto bin = bin_index(d, a, x, y, hn::RebindMask(d, plot));
        FP_DCHECK(hn::AllTrue(du, hn::Lt(bin, hn::Set(du, U(a.dummy + 1u)))));
        store32(du, bin, a.idx + i);
        n.plotted += hn::CountTrue(du, hn::And(live, plot));
        n.bad += uint32_t(hn::CountTrue(du, hn::And(live, isbad)));
        n.restarts += uint32_t(hn::CountTrue(du, hn::And(live, hn::Ne(rs, zero))));
        const auto nz = count_down(du, a.left + i, plot);
        const auto act = hn::And(nz, hn::Ne(load32(du, a.active + i), zero));
        store32(du, hn::IfThenElseZero(act, one), a.active + i);
        n.still += uint32_t(hn::CountTrue(du, hn::And(live, act)));
        if (colour) {
            const hn::Rebind<float, decltype(d)> df;
            const ColourVecs<decltype(d)> col = {hn::LoadU(df, a.cr + i), hn::LoadU(df, a.cg + i),
                                                 hn::LoadU(df, a.cb + i)};
            pack_colours(d, a, i, col);
        }
    }
    return n;
}

// ---------------------------------------------------------------- the deposit with colour
/// From point `from` on, bins[idx[i]] += {1, r, g, b} (dep[i]'s four 16-bit fields widened to
/// a bin's four 32-bit counters), until a bin's hits reach `spill`: returns that point's
/// index, for the caller to spill the bin before going on from the next one; nb when done.
HWY_INLINE size_t deposit_colour_t(uint32_t* bins, const uint32_t* idx, const uint64_t* dep, size_t from,
                                   size_t nb, uint32_t spill) {
#if HWY_TARGET == HWY_SCALAR
    for (size_t i = from; i < nb; ++i) {
        uint32_t* b = bins + 4 * size_t(idx[i]);
        const uint64_t v = dep[i];
        b[0] += uint32_t(v & 0xffffu), b[1] += uint32_t((v >> 16) & 0xffffu);
        b[2] += uint32_t((v >> 32) & 0xffffu), b[3] += uint32_t(v >> 48);
        if (HWY_UNLIKELY(b[0] == spill)) return i;
    }
#else
    const hn::FixedTag<uint32_t, 4> d4;
    const hn::FixedTag<uint16_t, 4> d16;
    for (size_t i = from; i < nb; ++i) {
        uint32_t* b = bins + 4 * size_t(idx[i]);
        const auto v = hn::Add(hn::LoadU(d4, b),
                               hn::PromoteTo(d4, hn::LoadU(d16, reinterpret_cast<const uint16_t*>(dep + i))));
        hn::StoreU(v, d4, b);
        if (HWY_UNLIKELY(hn::GetLane(v) == spill)) return i;
    }
#endif
    return nb;
}
