// chaos-game's step stages on the SIMD layer: compiled once per instruction set of the build
// (Highway's foreach_target, from chaos-game.cpp) and dispatched at run time. The stages and
// what they compute are described in chaos-game.cpp's header; kernels.hpp holds their
// arguments. Each kernel works on whole vectors of chains: the block arrays hold block_size
// entries (a multiple of every target's lane count), so the lanes past the block's last chain
// are computed too (their values are never read) and only the counts are masked to the block.
//
// Integer lanes have the width of the chains' type (U = uint32_t for float, uint64_t for
// double), so that a chain's coordinates and its integer state share one lane layout; the
// 32-bit arrays are widened on load and narrowed on store for double, the 64-bit ones (pcg32
// states, points left) are split in two for float.
//
// Floating point: + - * / and comparisons only, in the order of the scalar descriptions (no
// MulAdd), so every target gives the bits of the others (tests/unit/test_simd_targets.cpp).

#if defined(FP_CHAOS_KERNELS_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef FP_CHAOS_KERNELS_INL_HPP_
#undef FP_CHAOS_KERNELS_INL_HPP_
#else
#define FP_CHAOS_KERNELS_INL_HPP_
#endif

#include "kernels.hpp"

#include <fixpoint/simd-inl.hpp>

#include <hwy/cache_control.h>
#include <hwy/highway.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

HWY_BEFORE_NAMESPACE();
namespace fp_chaos::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using std::size_t;
using std::uint32_t;
using std::uint64_t;

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

template <class DU>
HWY_INLINE hn::Vec<DU> alias_lanes(DU du, hn::Vec<DU> r, uint32_t k, const hn::TFromD<DU>* thr,
                                   const hn::TFromD<DU>* alias);

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
            for (size_t l = 0; l < N; ++l) in[l] = a.inside[size_t(cs[l]) * a.row + i + l];
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

void draw_rules(const fp_chaos::DrawArgs& a) { draw_rules_t(hn::ScalableTag<uint32_t>(), a); }

/// Rules off: Walker's alias table (alias_lanes), one pcg32 output per chain; the tables
/// padded to whole vectors.
void draw_alias(const fp_chaos::DrawArgs& args) {
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
    for (uint32_t j = 0; j < a.k; ++j) a.counts[j] = counts[j];
}

void group_f(const fp_chaos::GroupArgs<float>& a) { group_t(a); }
void group_d(const fp_chaos::GroupArgs<double>& a) { group_t(a); }

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

void scatter_f(const float* gx, const float* gy, const uint32_t* gi, size_t n, float* x, float* y) {
    scatter_t(gx, gy, gi, n, x, y);
}
void scatter_d(const double* gx, const double* gy, const uint32_t* gi, size_t n, double* x, double* y) {
    scatter_t(gx, gy, gi, n, x, y);
}

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
    fp_chaos::Counts n;
    for (size_t i = 0; i < a.nb; i += N) {
        const auto live = hn::RebindMask(du, hn::FirstN(d, a.nb - i < N ? a.nb - i : N));
        const auto x = hn::LoadU(d, a.x + i), y = hn::LoadU(d, a.y + i);
        const auto c = load32(du, a.chosen + i);
        const auto mv = hn::Lt(c, none);
        const auto fin = hn::RebindMask(
            du, hn::And(fp::simd::HWY_NAMESPACE::finite(x), fp::simd::HWY_NAMESPACE::finite(y)));
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
        store32(du, bin_index(d, a, x, y, hn::RebindMask(d, plot)), a.idx + i);
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

fp_chaos::Counts bookkeep_f(const fp_chaos::BookArgs<float>& a, bool colour) { return bookkeep_t(a, colour); }
fp_chaos::Counts bookkeep_d(const fp_chaos::BookArgs<double>& a, bool colour) {
    return bookkeep_t(a, colour);
}

// ---------------------------------------------------------------- the deposit with colour
/// From point `from` on, bins[idx[i]] += {1, r, g, b} (dep[i]'s four 16-bit fields widened to
/// a bin's four 32-bit counters), until a bin's hits reach `spill`: returns that point's
/// index, for the caller to spill the bin before going on from the next one; nb when done.
size_t deposit_colour(uint32_t* bins, const uint32_t* idx, const uint64_t* dep, size_t from, size_t nb,
                      uint32_t spill) {
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

/// Circle::inside in lanes: (x - ox)^2 + (y - oy)^2 < r2, NaN outside.
template <class V>
HWY_INLINE auto in_circle(V x, V y, V ox, V oy, V r2) {
    const auto dx = hn::Sub(x, ox), dy = hn::Sub(y, oy);
    return hn::Lt(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), r2);
}

/// The map of kind K applied to (x, y), with its parameters in lanes: p[0..5] in the order of
/// fp::KnownKernel's expressions (circle: ox, oy, r2; affine: a .. f; Gumowski-Mira: alpha,
/// mu, 2 (1 - mu)).
template <fp_chaos::LaneKind K, class D>
HWY_INLINE void apply_kind(D d, const hn::Vec<D> (&p)[6], hn::Vec<D>& x, hn::Vec<D>& y) {
    using T = hn::TFromD<D>;
    if constexpr (K == fp_chaos::LaneKind::circle) {
        // Inversion with Circle::inversion_factor: d = p - o, s = r2 / |d|^2, p' = o + s d.
        const auto dx = hn::Sub(x, p[0]), dy = hn::Sub(y, p[1]);
        const auto s = hn::Div(p[2], hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)));
        x = hn::Add(p[0], hn::Mul(s, dx));
        y = hn::Add(p[1], hn::Mul(s, dy));
    } else if constexpr (K == fp_chaos::LaneKind::affine) {
        const auto nx = hn::Add(hn::Add(hn::Mul(p[0], x), hn::Mul(p[1], y)), p[4]);
        const auto ny = hn::Add(hn::Add(hn::Mul(p[2], x), hn::Mul(p[3], y)), p[5]);
        x = nx;
        y = ny;
    } else {
        const auto one = hn::Set(d, T(1));
        const auto f = [&](hn::Vec<D> u) {
            const auto u2 = hn::Mul(u, u);
            return hn::Add(hn::Mul(p[1], u), hn::Div(hn::Mul(p[2], u2), hn::Add(one, u2)));
        };
        const auto damp =
            hn::Mul(hn::Mul(p[0], hn::Sub(one, hn::Mul(hn::Mul(hn::Set(d, T(0.05)), y), y))), y);
        const auto nx = hn::Add(hn::Add(y, damp), f(x));
        y = hn::Add(hn::Neg(x), f(nx));
        x = nx;
    }
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
        hn::Vec<D> lq[3], ld[3];
        bool direct = true;
        if constexpr (Rules) {
            // Paper 01's loop: for circles, the drawn circle's set (Circle::inside, dx * dx +
            // dy * dy < r2, NaN allowed) tested with its parameters in lanes; the direct draw's
            // `excluded` tests every circle (the same values as broadcasts of t.p[.][j]: see
            // LaneTables::wp).
            // The last test keeps its circles (ox, oy, r2) and (dx, dy, dx * dx + dy * dy): the
            // inversion's own first operations on the same values, not done again below.
            const auto inside = [&](hn::Vec<decltype(du)> cc) {
                if constexpr (K != fp_chaos::LaneKind::circle) {
                    return hn::Ne(cc, cc);
                } else {
                    per_maps(
                        d, [&](size_t j) { return t.p[j]; }, k, cc, lq);
                    ld[0] = hn::Sub(x, lq[0]), ld[1] = hn::Sub(y, lq[1]);
                    ld[2] = hn::Add(hn::Mul(ld[0], ld[0]), hn::Mul(ld[1], ld[1]));
                    return hn::RebindMask(du, hn::Lt(ld[2], lq[2])); // (in_circle)
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
                    return hn::Or(hn::RebindMask(du, in_circle(x, y, par(0), par(1), par(2))), previous);
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
        const auto none_allowed = hn::AndNot(some, act);
        const auto rst = hn::IfThenElseZero(none_allowed, one);
        if (f.program) {
            program_lanes<K>(d, t, *f.program, c, x, y);
        } else if (K == fp_chaos::LaneKind::circle && Rules && !direct) {
            // apply_kind's inversion from the test's values: s = r2 / |d|^2, p' = o + s d.
            const auto s = hn::Div(lq[2], ld[2]);
            x = hn::Add(lq[0], hn::Mul(s, ld[0]));
            y = hn::Add(lq[1], hn::Mul(s, ld[1]));
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

fp_chaos::Counts fused_f(const fp_chaos::FusedArgs<float>& f) { return fused_any(f); }
fp_chaos::Counts fused_d(const fp_chaos::FusedArgs<double>& f) { return fused_any(f); }

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
    const auto one = hn::Set(d, T(1));
    const auto gm_f = [&](hn::Vec<decltype(d)> u) {
        const auto u2 = hn::Mul(u, u);
        return hn::Add(hn::Mul(p[1], u), hn::Div(hn::Mul(p[2], u2), hn::Add(one, u2)));
    };
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
                const auto damp =
                    hn::Mul(hn::Mul(p[0], hn::Sub(one, hn::Mul(hn::Mul(hn::Set(d, T(0.05)), y), y))), y);
                nx = hn::Add(hn::Add(y, damp), fx);
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

fp_chaos::RunCounts fused_run_f(const fp_chaos::FusedArgs<float>& f, uint64_t steps) {
    return fused_run_any(f, steps);
}
fp_chaos::RunCounts fused_run_d(const fp_chaos::FusedArgs<double>& f, uint64_t steps) {
    return fused_run_any(f, steps);
}

} // namespace fp_chaos::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif // per-target include guard
