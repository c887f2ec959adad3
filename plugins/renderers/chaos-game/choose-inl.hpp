// chaos-game's choice of maps and grouping by map on the SIMD layer (steps 1-3 of a block step:
// chaos-game.cpp's header): paper 01's draw under the inversion rules, Walker's alias table
// without them, and the grouping of a block's chains by the map they drew.
//
// A part of kernels-inl.hpp, which includes it inside fp_chaos::HWY_NAMESPACE once per target
// (its includes, namespace and per-target guard are kernels-inl.hpp's): not a header of its own.

// ---------------------------------------------------------------- the draw
/// v, hidden from the compiler's constant folding. A vector that counts up (j in every lane)
/// costs one addition a map; once a loop over the maps is unrolled, GCC would fold each count
/// into a constant and build it anew from a general register (three instructions a map on
/// x86). An empty asm statement with the vector as operand, where GCC takes one: no
/// instruction.
template <class V>
HWY_INLINE V opaque(V v) {
// (x86 vector registers, and NEON's; SVE's vectors are sizeless types without `raw`, and the
// emulated targets keep theirs in memory: those go without.)
#if defined(__GNUC__) && HWY_ARCH_X86 && HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128
    asm("" : "+v"(v.raw));
#elif defined(__GNUC__) && HWY_ARCH_ARM && HWY_TARGET == HWY_NEON
    asm("" : "+w"(v.raw));
#endif
    return v;
}

/// Rules on: the total allowed weight t, then u = high 32 bits of r * t and chosen = #{j :
/// cum_j <= u}, cum_j the allowed weight of maps 0..j; `excluded(j, vj)` is the mask of the
/// chains for which map j is not allowed (vj: j in every lane, kept as a vector that counts up,
/// not broadcast anew for each map). KMax bounds k at compile time, so that the loops over the maps
/// unroll (k <= 16 in practice). The running sums of the first loop are the cum_j: kept in
/// memory between the loops (one store and one load a map, where keeping the masks as bits
/// took a mask-to-bits and a bits-to-mask conversion, each several instructions on targets
/// without mask registers).
/// The sums are kept biased so that a signed comparison orders them (targets without unsigned
/// comparisons, AVX2 among them, pay two more operations for each): 32-bit lanes carry
/// cum_j + 2^31 (mod 2^32, which maps [0, 2^32) onto the signed range in order); 64-bit lanes
/// need no bias, the sums being below 2^32. The last map is not compared: cum_{k-1} = t > u
/// whenever t > 0, and with t = 0 (no map allowed) the choice is not used.
/// `wq`, when not null: the weights of the first wide_maps maps repeated over whole vectors, with a
/// stride of `ws` lanes (LaneTables::wq).
template <size_t KMax, class DU, class Excluded>
HWY_INLINE hn::Vec<DU> draw_allowed(DU du, const uint32_t* q, const hn::TFromD<DU>* wq, size_t ws, uint32_t k,
                                    hn::Vec<DU> r, hn::Vec<DU>& tot, Excluded&& excluded) {
    using U = hn::TFromD<DU>;
    const hn::RebindToSigned<DU> di;
    constexpr size_t L = fp::simd::HWY_NAMESPACE::max_lanes<U>;
    alignas(HWY_MAX_BYTES) U cum[KMax * L];
    const auto bias = hn::Set(du, sizeof(U) == 4 ? U(U(1) << (8 * sizeof(U) - 1)) : U(0));
    // (IfThenElse(m, a, Add(a, b)): one masked add where the target has them.)
    auto biased = bias;
    auto vj = hn::Zero(du);
    const auto one = hn::Set(du, U(1));
#pragma GCC unroll 16
    for (size_t j = 0; j < KMax; ++j) {
        if (j == k) break;
        const auto qj = wq && j < fp_chaos::LaneTables<float>::wide_maps ? hn::Load(du, wq + j * ws)
                                                                         : hn::Set(du, U(q[j]));
        biased = hn::IfThenElse(excluded(uint32_t(j), vj), biased, hn::Add(biased, qj));
        hn::Store(biased, du, cum + j * L);
        vj = opaque(hn::Add(vj, one));
    }
    tot = hn::Sub(biased, bias);
    // cum_j <= u as v > cum_j with v = u + 1 (biased, still below the signed maximum: u < t <
    // 2^32), so that each comparison reads its sum straight from memory.
    const auto v = hn::BitCast(di, hn::Add(hn::Add(mul_high32(du, r, tot), bias), one));
    auto c = hn::Zero(du);
    for (size_t j = 0; j + 1 < KMax; ++j) {
        if (j + 1 == k) break;
        c = hn::IfThenElse(hn::RebindMask(du, hn::Gt(v, hn::BitCast(di, hn::Load(du, cum + j * L)))),
                           hn::Add(c, one), c);
    }
    return c;
}

/// draw_allowed with the loops unrolled for up to 16 maps.
template <class DU, class Excluded>
HWY_INLINE hn::Vec<DU> draw_any(DU du, const uint32_t* q, const hn::TFromD<DU>* wq, size_t ws, uint32_t k,
                                hn::Vec<DU> r, hn::Vec<DU>& tot, Excluded&& excluded) {
    if (k <= 16) return draw_allowed<16>(du, q, wq, ws, k, r, tot, excluded);
    return draw_allowed<fp_chaos::table_size>(du, q, wq, ws, k, r, tot, excluded);
}

/// Rules off: Walker's alias table in lanes. m = r * k; column m >> 32, kept when the low 32
/// bits are below its threshold, else its alias (draw_alias's arithmetic).
template <class DU>
HWY_INLINE hn::Vec<DU> alias_lanes(DU du, hn::Vec<DU> r, uint32_t k, const hn::TFromD<DU>* thr,
                                   const hn::TFromD<DU>* alias) {
    using U = hn::TFromD<DU>;
    const auto vk = hn::Set(du, U(k));
    const auto col = mul_high32(du, r, vk);
    hn::Vec<DU> frac;
    if constexpr (sizeof(U) == 4)
        frac = hn::Mul(r, vk);
    else
        frac = hn::And(mul_small(du, r, vk), hn::Set(du, U(0xffffffffu)));
    hn::Vec<DU> ta[2];
    per_maps(
        du, [&](size_t j) { return j == 0 ? thr : alias; }, k, col, ta);
    return hn::IfThenElse(hn::Lt(frac, ta[0]), col, ta[1]);
}

/// One draw of paper 01's loop from r: with every weight the same, a map other than the
/// previous one p, c = (p + 1 + floor(r (k - 1) / 2^32)) mod k (p = k, no previous map:
/// floor(r k / 2^32)); else a map by weight from Walker's alias table (thr, alias), which
/// may be p (the loop rejects it, as the paper's does).
template <class DU>
HWY_INLINE hn::Vec<DU> draw_other(DU du, hn::Vec<DU> r, hn::Vec<DU> p, uint32_t k, bool uniform,
                                  const hn::TFromD<DU>* thr, const hn::TFromD<DU>* alias) {
    using U = hn::TFromD<DU>;
    if (!uniform) return alias_lanes(du, r, k, thr, alias);
    const auto vk = hn::Set(du, U(k));
    const auto first = hn::Eq(p, vk);
    const auto m = hn::IfThenElse(first, vk, hn::Set(du, U(k - 1)));
    const auto c = hn::Add(hn::IfThenZeroElse(first, hn::Add(p, hn::Set(du, U(1)))), mul_high32(du, r, m));
    return hn::IfThenElse(hn::Lt(c, vk), c, hn::Sub(c, vk));
}

/// Paper 01's Algorithm 1 for a vector of chains: "l = random number; while j = l or
/// inSet(S_l, p): l = random number". Each chain draws (c: draw_other's draw from one output
/// of its stream, every lane, as every step takes; made by the caller) and draws again while
/// the map drawn is its previous one or `inside(c)` (the mask of the chains whose point lies in
/// map c's set), up to rejection_draws draws, each again from the streams of the rejected chains only. The
/// few still rejected then take the direct draw among the allowed maps (draw_any with `excluded`, from one
/// more output of their streams), which also finds the chains with no allowed map
/// (`some` false: the loop would not end). Each accepted draw is one of the allowed maps with
/// probability proportional to its weight (Walker's table and q both hold the weights to 2^-31),
/// so the rules' distribution is the direct draw's; a draw costs one test of one set where the
/// direct draw tests every map's. `direct` says whether the direct draw ran: if not, the last
/// `inside` tested the maps returned.
template <class DU, class Inside, class Excluded>
HWY_INLINE hn::Vec<DU> draw_paper(DU du, hn::Vec<DU> c, uint64_t* rs, const uint64_t* ri, hn::Vec<DU> p,
                                  hn::Mask<DU> act, uint32_t k, bool uniform, const hn::TFromD<DU>* thr,
                                  const hn::TFromD<DU>* alias, const uint32_t* q, const hn::TFromD<DU>* wq,
                                  size_t ws, Inside&& inside, Excluded&& excluded, hn::Mask<DU>& some,
                                  bool& direct) {
    const auto rejected = [&](hn::Vec<DU> c) { return hn::Or(hn::Eq(c, p), inside(c)); };
    direct = false;
    auto bad = hn::And(act, rejected(c));
    some = hn::Eq(p, p);
    if (HWY_LIKELY(hn::AllFalse(du, bad))) return c;
    for (int t = 1; t < fp_chaos::rejection_draws; ++t) {
        c = hn::IfThenElse(bad, draw_other(du, pcg_next_masked(du, rs, ri, bad), p, k, uniform, thr, alias),
                           c);
        bad = hn::And(bad, rejected(c));
        if (hn::AllFalse(du, bad)) return c;
    }
    auto tot = hn::Zero(du);
    direct = true;
    const auto drawn = draw_any(du, q, wq, ws, k, pcg_next_masked(du, rs, ri, bad), tot, excluded);
    some = hn::Not(hn::And(bad, hn::Eq(tot, hn::Zero(du))));
    return hn::IfThenElse(bad, drawn, c);
}

template <class DU>
HWY_INLINE void draw_rules_t(DU du, const fp_chaos::DrawArgs& args) {
    const fp_chaos::DrawArgs a = args; // a local copy: see fused_t
    using U = hn::TFromD<DU>;
    constexpr size_t L = fp::simd::HWY_NAMESPACE::max_lanes<U>;
    const size_t N = hn::Lanes(du);
    const auto none = hn::Set(du, U(a.k)), one = hn::Set(du, U(1)), zero = hn::Zero(du);
    for (size_t i = 0; i < a.nb; i += N) {
        const auto p = load32(du, a.prev + i);
        const auto live = hn::FirstN(du, a.nb - i < N ? a.nb - i : N);
        const auto act = hn::And(live, hn::Ne(load32(du, a.active + i), zero));
        // The drawn maps' tests, read from the block's rows of inside bytes.
        const auto inside = [&](hn::Vec<DU> c) {
            alignas(HWY_MAX_BYTES) U cs[L], in[L];
            hn::Store(c, du, cs);
            for (size_t l = 0; l < N; ++l) {
                FP_DCHECK(cs[l] < a.k);
                in[l] = a.inside[size_t(cs[l]) * a.row + i + l];
            }
            return hn::Ne(hn::Load(du, in), zero);
        };
        hn::Mask<DU> some;
        bool direct;
        const auto c = draw_paper(
            du, draw_other(du, pcg_next(du, a.rs + i, a.ri + i), p, a.k, a.uniform, a.thr, a.alias), a.rs + i,
            a.ri + i, p, act, a.k, a.uniform, a.thr, a.alias, a.q, static_cast<const U*>(nullptr), 0, inside,
            [&](uint32_t j, hn::Vec<DU> vj) {
                return hn::Or(hn::Not(zero_bytes(du, a.inside + j * a.row + i)), hn::Eq(p, vj));
            },
            some, direct);
        store32(du, hn::IfThenElse(hn::And(act, some), c, none), a.chosen + i);
        store32(du, hn::IfThenElseZero(hn::AndNot(some, act), one), a.restart + i);
    }
}

/// Rules off: Walker's alias table (alias_lanes), one pcg32 output per chain; the tables
/// padded to whole vectors.
HWY_INLINE void draw_alias_t(const fp_chaos::DrawArgs& args) {
    const fp_chaos::DrawArgs a = args;
    const hn::ScalableTag<uint32_t> du;
    const size_t N = hn::Lanes(du);
    const auto none = hn::Set(du, a.k), zero = hn::Zero(du);
    for (size_t i = 0; i < a.nb; i += N) {
        const auto c = alias_lanes(du, pcg_next(du, a.rs + i, a.ri + i), a.k, a.thr, a.alias);
        hn::StoreU(hn::IfThenElse(hn::Ne(hn::LoadU(du, a.active + i), zero), c, none), du, a.chosen + i);
        hn::StoreU(zero, du, a.restart + i);
    }
}

// ---------------------------------------------------------------- grouping by map
template <class T>
HWY_INLINE void group_t(const fp_chaos::GroupArgs<T>& args) {
    namespace fs = fp::simd::HWY_NAMESPACE;
    const fp_chaos::GroupArgs<T> a = args; // a local copy: see fused_t
    uint32_t counts[fp_chaos::table_size] = {};
    const hn::ScalableTag<T> d;
    const hn::RebindToUnsigned<decltype(d)> du;
    using U = hn::TFromD<decltype(du)>;
    const size_t N = hn::Lanes(d);
    for (size_t i = 0; i < a.nb; i += N) {
        const size_t live = a.nb - i < N ? a.nb - i : N;
        const auto c = hn::IfThenElse(hn::RebindMask(du, hn::FirstN(d, live)), load32(du, a.chosen + i),
                                      hn::Set(du, U(a.k)));
        const auto x = hn::LoadU(d, a.x + i), y = hn::LoadU(d, a.y + i);
        const auto ix = hn::Iota(du, U(i));
        for (uint32_t j = 0; j < a.k; ++j) {
            const auto mu = hn::Eq(c, hn::Set(du, U(j)));
            const auto m = hn::RebindMask(d, mu);
            const size_t at = size_t(j) * a.stride + counts[j];
            // Compress in registers and store whole vectors (the segments have room for one
            // past their end): a compressing store to memory is slow on some CPUs. (The SIMD
            // layer's compress: Highway's copies a table at each call on some targets.)
            const size_t n = hn::CountTrue(d, m);
            const auto order = fs::compress_order(d, m);
            hn::StoreU(fs::compress(d, x, m, order), d, a.gx + at);
            hn::StoreU(fs::compress(d, y, m, order), d, a.gy + at);
            store32(du, fs::compress(du, ix, mu, order), a.gi + at);
            counts[j] += uint32_t(n);
        }
    }
    for (uint32_t j = 0; j < a.k; ++j) {
        FP_DCHECK(counts[j] <= a.nb && counts[j] + hn::Lanes(d) <= a.stride);
        a.counts[j] = counts[j];
    }
}

/// The way back: x[gi[t]] = gx[t] for the n points of one segment.
template <class T>
HWY_INLINE void scatter_t(const T* gx, const T* gy, const uint32_t* gi, size_t n, T* x, T* y) {
    const hn::ScalableTag<T> d;
    const hn::RebindToSigned<decltype(d)> di;
    const size_t N = hn::Lanes(d);
    size_t t = 0;
    for (; t + N <= n; t += N) {
        const auto idx = hn::BitCast(di, load32(hn::RebindToUnsigned<decltype(d)>(), gi + t));
        hn::ScatterIndex(hn::LoadU(d, gx + t), d, x, idx);
        hn::ScatterIndex(hn::LoadU(d, gy + t), d, y, idx);
    }
    for (; t < n; ++t) {
        x[gi[t]] = gx[t];
        y[gi[t]] = gy[t];
    }
}
