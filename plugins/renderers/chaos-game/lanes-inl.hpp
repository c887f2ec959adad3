// chaos-game's lane helpers on the SIMD layer, for every stage of a step (choose-inl.hpp,
// book-inl.hpp, fused-inl.hpp): a block's 32-bit arrays as lanes of the chains' width, pcg32 on
// lanes, the points left, and the maps' parameters per lane.
//
// A part of kernels-inl.hpp, which includes it inside fp_chaos::HWY_NAMESPACE once per target
// (its includes, namespace and per-target guard are kernels-inl.hpp's): not a header of its own.

constexpr uint64_t pcg_mult_v = 6364136223846793005ull;

// ---------------------------------------------------------------- lanes of 32-bit data
/// The 32-bit array p as integer lanes of DU (widened for 64-bit lanes).
template <class DU>
HWY_INLINE hn::Vec<DU> load32(DU du, const uint32_t* p) {
    if constexpr (sizeof(hn::TFromD<DU>) == 4) {
        return hn::LoadU(du, p);
    } else {
        const hn::Rebind<uint32_t, DU> d32;
        return hn::PromoteTo(du, hn::LoadU(d32, p));
    }
}

template <class DU>
HWY_INLINE void store32(DU du, hn::Vec<DU> v, uint32_t* p) {
    if constexpr (sizeof(hn::TFromD<DU>) == 4) {
        hn::StoreU(v, du, p);
    } else {
        const hn::Rebind<uint32_t, DU> d32;
        hn::StoreU(hn::TruncateTo(d32, v), d32, p);
    }
}

/// Bytes (0 / non-zero) as a mask of DU's lanes: set where the byte is 0.
template <class DU>
HWY_INLINE hn::Mask<DU> zero_bytes(DU du, const unsigned char* p) {
    const hn::Rebind<uint8_t, DU> d8;
    if constexpr (sizeof(hn::TFromD<DU>) == 4) {
        return hn::Eq(hn::PromoteTo(du, hn::LoadU(d8, p)), hn::Zero(du));
    } else {
        const hn::Rebind<uint32_t, DU> d32;
        return hn::Eq(hn::PromoteTo(du, hn::PromoteTo(d32, hn::LoadU(d8, p))), hn::Zero(du));
    }
}

/// The high 32 bits of a * b for 32-bit values a, b in DU's lanes.
template <class DU>
HWY_INLINE hn::Vec<DU> mul_high32(DU du, hn::Vec<DU> a, hn::Vec<DU> b) {
#if HWY_TARGET == HWY_SCALAR
    using U = hn::TFromD<DU>;
    return hn::Set(du, U((uint64_t(hn::GetLane(a)) * uint64_t(hn::GetLane(b))) >> 32));
#else
    if constexpr (sizeof(hn::TFromD<DU>) == 4) {
        const hn::Repartition<uint64_t, DU> d64;
        const auto even = hn::MulEven(a, b);
        const auto odd = hn::MulEven(hn::BitCast(du, hn::ShiftRight<32>(hn::BitCast(d64, a))),
                                     hn::BitCast(du, hn::ShiftRight<32>(hn::BitCast(d64, b))));
        return hn::OddEven(hn::BitCast(du, odd), hn::BitCast(du, hn::ShiftRight<32>(even)));
    } else {
        const hn::Repartition<uint32_t, DU> d32;
        return hn::ShiftRight<32>(hn::MulEven(hn::BitCast(d32, a), hn::BitCast(d32, b)));
    }
#endif
}

/// a * b for values whose product is below 2^32 (bin indices).
template <class DU>
HWY_INLINE hn::Vec<DU> mul_small(DU du, hn::Vec<DU> a, hn::Vec<DU> b) {
#if HWY_TARGET == HWY_SCALAR
    return hn::Set(du, hn::TFromD<DU>(hn::GetLane(a) * hn::GetLane(b)));
#else
    if constexpr (sizeof(hn::TFromD<DU>) == 4) {
        (void)du;
        return hn::Mul(a, b);
    } else {
        const hn::Repartition<uint32_t, DU> d32;
        return hn::MulEven(hn::BitCast(d32, a), hn::BitCast(d32, b));
    }
#endif
}

// ---------------------------------------------------------------- pcg32
#if HWY_TARGET != HWY_SCALAR
/// s * pcg_mult + inc, modulo 2^64 (Highway's 64-bit multiply: one instruction where the
/// target has it, 32 x 32 -> 64-bit products elsewhere).
template <class D64>
HWY_INLINE hn::Vec<D64> pcg_advance(D64 d64, hn::Vec<D64> s, hn::Vec<D64> inc) {
    return hn::Add(hn::Mul(s, hn::Set(d64, pcg_mult_v)), inc);
}
#endif

/// One pcg32 output per lane (XSH-RR 64/32, output of the previous state: fp::Rng), the
/// states at rs advanced.
template <class DU>
HWY_INLINE hn::Vec<DU> pcg_next(DU du, uint64_t* rs, const uint64_t* ri) {
#if HWY_TARGET == HWY_SCALAR
    // One lane: fp_chaos::pcg_next's arithmetic (state.hpp).
    const uint64_t old = rs[0];
    rs[0] = old * pcg_mult_v + ri[0];
    const auto x = uint32_t(((old >> 18) ^ old) >> 27);
    const auto rot = uint32_t(old >> 59);
    return hn::Set(du, hn::TFromD<DU>((x >> rot) | (x << ((32u - rot) & 31u))));
#else
    const hn::Repartition<uint64_t, DU> d64;
    if constexpr (sizeof(hn::TFromD<DU>) == 4) {
        const size_t h = hn::Lanes(d64);
        const auto o0 = hn::LoadU(d64, rs), o1 = hn::LoadU(d64, rs + h);
        hn::StoreU(pcg_advance(d64, o0, hn::LoadU(d64, ri)), d64, rs);
        hn::StoreU(pcg_advance(d64, o1, hn::LoadU(d64, ri + h)), d64, rs + h);
        const auto xs = [](auto o) { return hn::ShiftRight<27>(hn::Xor(hn::ShiftRight<18>(o), o)); };
        // The low 32 bits of each 64-bit lane are its even 32-bit lane.
        const auto x = hn::ConcatEven(du, hn::BitCast(du, xs(o1)), hn::BitCast(du, xs(o0)));
        const auto r = hn::ConcatEven(du, hn::BitCast(du, hn::ShiftRight<59>(o1)),
                                      hn::BitCast(du, hn::ShiftRight<59>(o0)));
        return hn::Or(hn::Shr(x, r), hn::Shl(x, hn::And(hn::Sub(hn::Set(du, 32), r), hn::Set(du, 31))));
    } else {
        const auto o = hn::LoadU(du, rs);
        hn::StoreU(pcg_advance(du, o, hn::LoadU(du, ri)), du, rs);
        const auto m32 = hn::Set(du, 0xffffffffull);
        const auto x = hn::And(hn::ShiftRight<27>(hn::Xor(hn::ShiftRight<18>(o), o)), m32);
        const auto r = hn::ShiftRight<59>(o);
        const auto rl = hn::And(hn::Sub(hn::Set(du, 32), r), hn::Set(du, 31));
        return hn::And(hn::Or(hn::Shr(x, r), hn::Shl(x, rl)), m32);
    }
#endif
}

/// The states at rs advanced by one output, the output unused (a draw among one map).
template <class DU>
HWY_INLINE void pcg_skip(DU, uint64_t* rs, const uint64_t* ri) {
#if HWY_TARGET == HWY_SCALAR
    rs[0] = rs[0] * pcg_mult_v + ri[0];
#else
    const hn::Repartition<uint64_t, DU> d64;
    const size_t h = hn::Lanes(d64);
    hn::StoreU(pcg_advance(d64, hn::LoadU(d64, rs), hn::LoadU(d64, ri)), d64, rs);
    if constexpr (sizeof(hn::TFromD<DU>) == 4)
        hn::StoreU(pcg_advance(d64, hn::LoadU(d64, rs + h), hn::LoadU(d64, ri + h)), d64, rs + h);
#endif
}

/// pcg_next for the lanes of m: the other lanes' states stay as they were (their outputs are
/// not to be used). For the draws again of the rejection loop, which only the rejected chains
/// make (a chain's stream must not depend on its neighbours in the vector): rare, so plain.
template <class DU>
HWY_INLINE hn::Vec<DU> pcg_next_masked(DU du, uint64_t* rs, const uint64_t* ri, hn::Mask<DU> m) {
    using U = hn::TFromD<DU>;
    constexpr size_t L = fp::simd::HWY_NAMESPACE::max_lanes<U>;
    const size_t n = hn::Lanes(du);
    uint64_t saved[L];
    alignas(HWY_MAX_BYTES) U keep[L];
    for (size_t l = 0; l < n; ++l) saved[l] = rs[l];
    hn::Store(hn::VecFromMask(du, m), du, keep);
    const auto r = pcg_next(du, rs, ri);
    for (size_t l = 0; l < n; ++l)
        if (keep[l] == 0) rs[l] = saved[l];
    return r;
}

// ---------------------------------------------------------------- points left
/// left[i] -= 1 where `dec`; returns the lanes whose count is still non-zero.
template <class DU>
HWY_INLINE hn::Mask<DU> count_down(DU du, uint64_t* left, hn::Mask<DU> dec) {
#if HWY_TARGET == HWY_SCALAR
    left[0] -= hn::AllTrue(du, dec) ? 1u : 0u;
    return hn::Ne(hn::Set(du, hn::TFromD<DU>(left[0] != 0 ? 1 : 0)), hn::Zero(du));
#else
    if constexpr (sizeof(hn::TFromD<DU>) == 4) {
        const hn::Repartition<uint64_t, DU> d64;
        const hn::RebindToSigned<DU> di;
        const hn::Half<decltype(di)> dh;
        const hn::Rebind<int64_t, decltype(dh)> di64;
        const size_t h = hn::Lanes(d64);
        const auto m = hn::BitCast(di, hn::VecFromMask(du, dec)); // -1 or 0
        const auto l0 =
            hn::Add(hn::LoadU(d64, left), hn::BitCast(d64, hn::PromoteTo(di64, hn::LowerHalf(dh, m))));
        const auto l1 =
            hn::Add(hn::LoadU(d64, left + h), hn::BitCast(d64, hn::PromoteTo(di64, hn::UpperHalf(dh, m))));
        hn::StoreU(l0, d64, left);
        hn::StoreU(l1, d64, left + h);
        const auto z = hn::Zero(d64);
        const auto nz0 = hn::BitCast(du, hn::VecFromMask(d64, hn::Ne(l0, z)));
        const auto nz1 = hn::BitCast(du, hn::VecFromMask(d64, hn::Ne(l1, z)));
        return hn::MaskFromVec(hn::ConcatEven(du, nz1, nz0));
    } else {
        const auto l = hn::Sub(hn::LoadU(du, left), hn::IfThenElseZero(dec, hn::Set(du, 1)));
        hn::StoreU(l, du, left);
        return hn::Ne(l, hn::Zero(du));
    }
#endif
}

// ---------------------------------------------------------------- the fused step
/// The per-lane values of n of the maps' parameters (tables table(0) .. table(n - 1)): table
/// lookups when the maps fit one vector, else a selection per map (the same values). The
/// lookup's indices are made once for all n tables.
template <size_t n, class D, class Table>
HWY_INLINE void per_maps(D d, Table&& table, uint32_t k, hn::Vec<hn::RebindToUnsigned<D>> c,
                         hn::Vec<D> (&out)[n]) {
    const hn::RebindToUnsigned<D> du;
    using U = hn::TFromD<decltype(du)>;
    if (k == 1) { // (a single map: its values in every lane)
        for (size_t j = 0; j < n; ++j) out[j] = hn::Set(d, table(j)[0]);
    } else if (k <= hn::Lanes(d)) {
        const auto idx = hn::IndicesFromVec(d, hn::Min(c, hn::Set(du, U(k - 1))));
        for (size_t j = 0; j < n; ++j) out[j] = hn::TableLookupLanes(hn::LoadU(d, table(j)), idx);
    } else {
        for (size_t j = 0; j < n; ++j) {
            const auto* t = table(j);
            auto v = hn::Set(d, t[0]);
            for (uint32_t m = 1; m < k; ++m)
                v = hn::IfThenElse(hn::RebindMask(d, hn::Eq(c, hn::Set(du, U(m)))), hn::Set(d, t[m]), v);
            out[j] = v;
        }
    }
}
