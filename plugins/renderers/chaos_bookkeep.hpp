// chaos-game's bookkeeping of a step (after the maps moved the chains: finite?, plotted?,
// age, points left, bin index, colour values) and the steady runs of the fused step, which
// skip the part of it that cannot change and settle it when they end. Only chaos-game.cpp
// includes it.
#pragma once

#include "chaos_state.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace fp_chaos {

// ---------------------------------------------------------------- bookkeeping of a step
template <class T>
struct BinView {
    T xmin, xmax, ymin, ymax, scx, scy;
    uint32_t W, H, dummy, skip, none;
};

struct StepCounts {
    uint64_t plotted = 0; ///< a steady run's settlement counts all its steps' points
    uint32_t bad = 0, restarts = 0, still = 0;
};

constexpr float cscale = float(fp::colour_scale);

// After a step: for each chain, whether it moved, whether its point is finite (else: a bad
// value and a restart), whether it plots (moved, finite, past `skip`); its age, previous map,
// idle count, points left and activity; its bin (the last one, outside the image, when not
// plotted or outside the view: x in [xmin, xmax), y in (ymin, ymax], y = ymax the top row,
// indices clamped in case the products round up to width or height); and its colour packed
// {1, r, g, b} in 16 bits each (round(c * colour_scale), c clamped to [0, 1], NaN to 0).
// The generic loops keep 0/1 integer masks of one width per loop, so that they vectorise.
template <bool Colour, class T>
StepCounts bookkeep_generic(Scratch<T>& s, size_t nb, const BinView<T>& v) {
    const T* __restrict x = s.x.get();
    const T* __restrict y = s.y.get();
    const uint32_t* __restrict chosen = s.chosen.get();
    uint32_t* __restrict prev = s.prev.get();
    uint32_t* __restrict age = s.age.get();
    uint32_t* __restrict idle = s.idle.get();
    uint32_t* __restrict restart = s.restart.get();
    uint32_t* __restrict plotf = s.plotf.get();
    uint32_t* __restrict idx = s.idx.get();
    uint64_t* __restrict left = s.left.get();
    uint32_t* __restrict active = s.active.get();
    const float* __restrict cr = s.cr.get();
    const float* __restrict cg = s.cg.get();
    const float* __restrict cb = s.cb.get();
    uint64_t* __restrict dep = s.dep.get();
    StepCounts n;
    FP_IVDEP
    for (size_t i = 0; i < nb; ++i) {
        const T xi = x[i], yi = y[i];
        const uint32_t mv = chosen[i] < v.none ? 1u : 0u;
        const uint32_t fin = ((xi - xi == T(0)) & (yi - yi == T(0))) ? 1u : 0u; // 0 for NaN, inf
        const uint32_t isbad = mv & (fin ^ 1u);
        const uint32_t plot = mv & fin & (age[i] >= v.skip ? 1u : 0u);
        age[i] += mv & (age[i] < v.skip ? 1u : 0u);
        prev[i] = mv ? chosen[i] : prev[i];
        idle[i] = plot ? 0u : idle[i];
        restart[i] |= isbad << 1; // bit 0: no allowed map, bit 1: bad value
        plotf[i] = plot;
    }
    FP_IVDEP
    for (size_t i = 0; i < nb; ++i) {
        const T xi = x[i], yi = y[i];
        const uint32_t in =
            plotf[i] & (((xi >= v.xmin) & (xi < v.xmax) & (yi > v.ymin) & (yi <= v.ymax)) ? 1u : 0u);
        const T fx = in ? (xi - v.xmin) * v.scx : T(0), fy = in ? (v.ymax - yi) * v.scy : T(0);
        const auto ix = std::min(uint32_t(std::int32_t(fx)), v.W - 1);
        const auto iy = std::min(uint32_t(std::int32_t(fy)), v.H - 1);
        idx[i] = in ? iy * v.W + ix : v.dummy;
    }
    for (size_t i = 0; i < nb; ++i) {
        n.plotted += plotf[i];
        n.bad += restart[i] >> 1;
        n.restarts += restart[i] != 0 ? 1u : 0u;
    }
    FP_IVDEP
    for (size_t i = 0; i < nb; ++i) {
        left[i] -= plotf[i];
        const uint32_t act = active[i] & (left[i] != 0 ? 1u : 0u);
        active[i] = act;
        n.still += act;
    }
    if (!Colour) return n;
    FP_IVDEP
    for (size_t i = 0; i < nb; ++i) {
        const float r0 = cr[i] > 0.0f ? cr[i] : 0.0f, r = r0 < 1.0f ? r0 : 1.0f;
        const float g0 = cg[i] > 0.0f ? cg[i] : 0.0f, g = g0 < 1.0f ? g0 : 1.0f;
        const float b0 = cb[i] > 0.0f ? cb[i] : 0.0f, b = b0 < 1.0f ? b0 : 1.0f;
        const auto qr = uint64_t(std::int32_t(r * cscale + 0.5f));
        const auto qg = uint64_t(std::int32_t(g * cscale + 0.5f));
        const auto qb = uint64_t(std::int32_t(b * cscale + 0.5f));
        dep[i] = 1u | (qr << 16) | (qg << 32) | (qb << 48);
    }
    return n;
}

template <bool Colour, class T>
StepCounts bookkeep(Scratch<T>& s, size_t nb, const BinView<T>& v) {
    return bookkeep_generic<Colour>(s, nb, v);
}

#if FP_CHAOS_AVX512
// The same for float chains, 16 at a time in registers (one pass instead of five); the same
// IEEE operations in the same order, so the same bits.
template <bool Colour>
StepCounts bookkeep(Scratch<float>& s, size_t nb, const BinView<float>& v) {
    StepCounts n;
    // (Masked forms with all lanes on: the unmasked ones trip GCC 12's -Wmaybe-uninitialized.)
    constexpr __mmask16 all = 0xffff;
    const __m512i one = _mm512_set1_epi32(1), two = _mm512_set1_epi32(2), zero = _mm512_setzero_si512();
    const __m512i vnone = _mm512_set1_epi32(int(v.none)), vskip = _mm512_set1_epi32(int(v.skip));
    const __m512i vW = _mm512_set1_epi32(int(v.W)), vW1 = _mm512_set1_epi32(int(v.W - 1));
    const __m512i vH1 = _mm512_set1_epi32(int(v.H - 1)), vdummy = _mm512_set1_epi32(int(v.dummy));
    const __m512 fzero = _mm512_setzero_ps(), fone = _mm512_set1_ps(1.0f);
    const __m512 xmin = _mm512_set1_ps(v.xmin), xmax = _mm512_set1_ps(v.xmax);
    const __m512 ymin = _mm512_set1_ps(v.ymin), ymax = _mm512_set1_ps(v.ymax);
    const __m512 scx = _mm512_set1_ps(v.scx), scy = _mm512_set1_ps(v.scy);
    const __m512 cs = _mm512_set1_ps(cscale), half = _mm512_set1_ps(0.5f);
    const __m512i one64 = _mm512_set1_epi64(1);
    const __m512i lo_idx = _mm512_set_epi32(23, 7, 22, 6, 21, 5, 20, 4, 19, 3, 18, 2, 17, 1, 16, 0);
    const __m512i hi_idx = _mm512_set_epi32(31, 15, 30, 14, 29, 13, 28, 12, 27, 11, 26, 10, 25, 9, 24, 8);
    for (size_t i = 0; i < nb; i += 16) {
        const __mmask16 live = nb - i >= 16 ? __mmask16(0xffff) : __mmask16((1u << (nb - i)) - 1u);
        const __m512i c = _mm512_maskz_loadu_epi32(live, s.chosen.get() + i);
        const __mmask16 mv = _mm512_mask_cmplt_epu32_mask(live, c, vnone);
        const __m512 x = _mm512_maskz_loadu_ps(live, s.x.get() + i);
        const __m512 y = _mm512_maskz_loadu_ps(live, s.y.get() + i);
        const __mmask16 fin = _mm512_cmp_ps_mask(_mm512_sub_ps(x, x), fzero, _CMP_EQ_OQ) &
                              _mm512_cmp_ps_mask(_mm512_sub_ps(y, y), fzero, _CMP_EQ_OQ);
        const __mmask16 isbad = mv & __mmask16(~fin);
        __m512i a = _mm512_maskz_loadu_epi32(live, s.age.get() + i);
        const __mmask16 old = _mm512_cmpge_epu32_mask(a, vskip);
        const __mmask16 plot = mv & fin & old;
        a = _mm512_mask_add_epi32(a, mv & __mmask16(~old), a, one);
        _mm512_mask_storeu_epi32(s.age.get() + i, live, a);
        const __m512i pv = _mm512_maskz_loadu_epi32(live, s.prev.get() + i);
        _mm512_mask_storeu_epi32(s.prev.get() + i, live, _mm512_mask_mov_epi32(pv, mv, c));
        const __m512i idl = _mm512_maskz_loadu_epi32(live, s.idle.get() + i);
        _mm512_mask_storeu_epi32(s.idle.get() + i, live, _mm512_maskz_mov_epi32(__mmask16(~plot), idl));
        __m512i rs = _mm512_maskz_loadu_epi32(live, s.restart.get() + i);
        rs = _mm512_mask_or_epi32(rs, isbad, rs, two);
        _mm512_mask_storeu_epi32(s.restart.get() + i, live, rs);
        n.plotted += unsigned(__builtin_popcount(unsigned(plot)));
        n.bad += unsigned(__builtin_popcount(unsigned(isbad)));
        n.restarts += unsigned(__builtin_popcount(unsigned(_mm512_mask_cmpneq_epi32_mask(live, rs, zero))));

        // bin index
        const __mmask16 in =
            plot & _mm512_cmp_ps_mask(x, xmin, _CMP_GE_OQ) & _mm512_cmp_ps_mask(x, xmax, _CMP_LT_OQ) &
            _mm512_cmp_ps_mask(y, ymin, _CMP_GT_OQ) & _mm512_cmp_ps_mask(y, ymax, _CMP_LE_OQ);
        const __m512 fx = _mm512_maskz_mul_ps(in, _mm512_sub_ps(x, xmin), scx);
        const __m512 fy = _mm512_maskz_mul_ps(in, _mm512_sub_ps(ymax, y), scy);
        const __m512i ix = _mm512_maskz_min_epu32(all, _mm512_maskz_cvttps_epi32(all, fx), vW1);
        const __m512i iy = _mm512_maskz_min_epu32(all, _mm512_maskz_cvttps_epi32(all, fy), vH1);
        const __m512i id =
            _mm512_mask_blend_epi32(in, vdummy, _mm512_add_epi32(_mm512_mullo_epi32(iy, vW), ix));
        _mm512_mask_storeu_epi32(s.idx.get() + i, live, id);

        // points left (64-bit), activity
        const __mmask8 live0 = __mmask8(live), live1 = __mmask8(live >> 8);
        __m512i l0 = _mm512_maskz_loadu_epi64(live0, s.left.get() + i);
        __m512i l1 = _mm512_maskz_loadu_epi64(live1, s.left.get() + i + 8);
        l0 = _mm512_mask_sub_epi64(l0, __mmask8(plot), l0, one64);
        l1 = _mm512_mask_sub_epi64(l1, __mmask8(plot >> 8), l1, one64);
        _mm512_mask_storeu_epi64(s.left.get() + i, live0, l0);
        _mm512_mask_storeu_epi64(s.left.get() + i + 8, live1, l1);
        const __mmask16 nz = __mmask16(_mm512_cmpneq_epi64_mask(l0, zero)) |
                             __mmask16(__mmask16(_mm512_cmpneq_epi64_mask(l1, zero)) << 8);
        const __mmask16 act = nz & _mm512_mask_cmpneq_epi32_mask(
                                       live, _mm512_maskz_loadu_epi32(live, s.active.get() + i), zero);
        _mm512_mask_storeu_epi32(s.active.get() + i, live, _mm512_maskz_mov_epi32(act, one));
        n.still += unsigned(__builtin_popcount(unsigned(act)));
        if (!Colour) continue;

        // colour, packed {1, r, g, b}: max(c, 0) then min(., 1) sends NaN to 0 (maxps returns
        // its second operand when the first is NaN), as the generic loop does.
        auto q = [&](const float* p) {
            const __m512 c0 = _mm512_maskz_min_ps(
                all, _mm512_maskz_max_ps(all, _mm512_maskz_loadu_ps(live, p), fzero), fone);
            return _mm512_maskz_cvttps_epi32(all, _mm512_add_ps(_mm512_mul_ps(c0, cs), half));
        };
        const __m512i qr = q(s.cr.get() + i), qg = q(s.cg.get() + i), qb = q(s.cb.get() + i);
        const __m512i lo = _mm512_or_si512(one, _mm512_maskz_slli_epi32(all, qr, 16));
        const __m512i hi = _mm512_or_si512(qg, _mm512_maskz_slli_epi32(all, qb, 16));
        _mm512_mask_storeu_epi64(s.dep.get() + i, live0, _mm512_permutex2var_epi32(lo, lo_idx, hi));
        _mm512_mask_storeu_epi64(s.dep.get() + i + 8, live1, _mm512_permutex2var_epi32(lo, hi_idx, hi));
    }
    return n;
}
#endif

// ---------------------------------------------------------------- steady runs
/// Whether a block may run steady (fp_chaos::fused_rules_step<true, true>): `budget` steps
/// when every active chain is past its skip, fewer than the fewest points any of them has
/// left (so that none runs out during the run); 0 otherwise. `wait`: steps before asking
/// again can help, when some chain is still young (its age grows by at most one a step), so
/// that a block full of restarting chains is not scanned at every step.
struct SteadyCheck {
    uint64_t budget = 0, wait = 0;
};

template <class T>
SteadyCheck steady_budget(const Scratch<T>& s, size_t nb, uint32_t skip) {
    const uint32_t* age = s.age.get();
    const uint32_t* active = s.active.get();
    const uint64_t* left = s.left.get();
    uint64_t fewest = UINT64_MAX;
    uint32_t youngest = skip; // the smallest age of an active chain, capped at skip
    for (size_t i = 0; i < nb; ++i) {
        const bool a = active[i] != 0;
        youngest = std::min(youngest, a ? age[i] : skip);
        fewest = std::min(fewest, a ? left[i] : UINT64_MAX);
    }
    if (youngest < skip) return {0, skip - youngest - 1};
    return {fewest == UINT64_MAX ? 0 : fewest - 1, 0};
}

/// The end of a steady run of `steps` steps: every active chain plotted at each step but the
/// last when that one restarted it (no allowed map, or a point not finite: restart[i] set),
/// so its points left and idle count become what the step-by-step bookkeeping would have
/// made them. Returns the points plotted.
template <class T>
uint64_t settle_steady(Scratch<T>& s, size_t nb, uint64_t steps) {
    const uint32_t* active = s.active.get();
    const uint32_t* restart = s.restart.get();
    uint64_t* left = s.left.get();
    uint32_t* idle = s.idle.get();
    uint64_t plotted = 0;
    for (size_t i = 0; i < nb; ++i) {
        if (!active[i]) continue;
        const uint64_t p = steps - (restart[i] ? 1 : 0);
        // A run longer than steady_budget allows would have plotted past a chain's last point
        // (and the chain would never finish): say so rather than spin.
        if (p >= left[i]) throw fp::InternalError("chaos-game: a steady run outlived a chain's points");
        left[i] -= p;
        if (p) idle[i] = 0;
        plotted += p;
    }
    return plotted;
}

} // namespace fp_chaos
