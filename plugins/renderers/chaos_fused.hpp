// chaos-game's fused step for inversions in circles (fp::KnownKernel::circle_inversion).
//
// The generic step of a block (chaos-game.cpp) makes one Transform::contains call per map,
// draws the maps, groups the chains by map (compress into per-map segments), makes one
// IterationScheme::step call per map and expands the points back: a pass over the block's
// arrays per stage, and the grouping alone was about a quarter of a render. When every map
// describes itself as inversion in a circle (Transform::kernel()), the scheme is a plain
// Picard step (IterationScheme::is_picard) and the rules are on, the same
// step runs here in one pass, 16 float chains per AVX-512 vector:
//   - the k inside tests in registers: d = p - c_j, |d|^2 < R_j^2, one mask per map;
//   - the draw among the allowed maps, the same pcg32 output and the same integer arithmetic
//     as choose_rules (u = high 32 bits of r * total, chosen = #{j : cum_j <= u});
//   - the inversion with the chosen circle's (c, R^2) taken per lane from a 16-entry table
//     (vpermps): d = p - c, s = R^2 / |d|^2, p' = c + s d, the expressions of the circle's
//     inside() / inversion_factor() and of inversion's apply() in the same order (no FMA:
//     the build has -ffp-contract=off, and intrinsics do no contraction anyway).
// With a colourer that needs no colour the same pass also does the step's bookkeeping and bin
// index (bookkeep<false>'s operations on the new points, still in registers), and the
// deposit of the previous step's bins (FusedBook::lag): 16 increments after each vector,
// whose addresses are known from the start, so that their cache misses overlap this step's
// arithmetic. (Depositing a vector's own new bins there instead was slower: those addresses
// come at the end of the vector's dependency chain.)
// So the chosen maps, the points and therefore the image are bit for bit those of the generic
// path (tests/unit/test_chaos_kernel.cpp renders recipes both ways, `kernels: generic`
// switching this off). The bookkeeping and the deposit that follow are shared.
#pragma once

#include <fixpoint/fixpoint.hpp>

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512BW__) && defined(__AVX512DQ__)
#include <immintrin.h>
#define FP_CHAOS_FUSED 1
#else
#define FP_CHAOS_FUSED 0
#endif

namespace fp_chaos {

/// Maps the fused step handles at most (one 16-lane table).
constexpr std::size_t fused_max_maps = 16;

/// The maps' circles in float, 16-entry tables for vpermps, and the integer weights.
struct FusedTables {
    alignas(64) float cx[16] = {};
    alignas(64) float cy[16] = {};
    alignas(64) float r2[16] = {};
    std::uint32_t q[16] = {};
    std::uint32_t j[16] = {}; ///< j itself: compared from memory (a broadcast operand, no shuffle)
    std::uint32_t k = 0;
};

/// The tables for `maps` when every map is a circle inversion and there are at most 16;
/// otherwise false.
inline bool fused_tables(const std::vector<fp::KnownKernel>& maps, const std::vector<std::uint32_t>& q,
                         FusedTables& t) {
    if (maps.empty() || maps.size() > fused_max_maps) return false;
    for (std::size_t j = 0; j < maps.size(); ++j) {
        if (maps[j].kind != fp::KnownKernel::Kind::circle_inversion) return false;
        t.cx[j] = float(maps[j].cx);
        t.cy[j] = float(maps[j].cy);
        t.r2[j] = float(maps[j].r2);
        t.q[j] = q[j];
        t.j[j] = std::uint32_t(j);
    }
    t.k = std::uint32_t(maps.size());
    return true;
}

#if FP_CHAOS_FUSED
// GCC 12's -W(maybe-)uninitialized misfires inside the unmasked AVX-512 shift, multiply and
// convert intrinsics (their _mm512_undefined_* operands).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
/// The block's arrays the fused step reads and writes (see Scratch in chaos_state.hpp).
struct FusedBlock {
    float* x;
    float* y;
    std::uint64_t* rs;
    const std::uint64_t* ri;
    const std::uint32_t* prev;
    const std::uint32_t* active;
    std::uint32_t* chosen;
    std::uint32_t* restart;
    std::size_t nb;
};

/// 16 pcg32 outputs (XSH-RR 64/32, output of the previous state), the states advanced: the
/// vector form of chaos-game's pcg_next.
inline __m512i pcg16(std::uint64_t* rs, const std::uint64_t* ri, __mmask16 live) {
    const __m512i mult = _mm512_set1_epi64(std::int64_t(6364136223846793005ull));
    const __mmask8 l0 = __mmask8(live), l1 = __mmask8(live >> 8);
    const __m512i o0 = _mm512_maskz_loadu_epi64(l0, rs), o1 = _mm512_maskz_loadu_epi64(l1, rs + 8);
    const __m512i i0 = _mm512_maskz_loadu_epi64(l0, ri), i1 = _mm512_maskz_loadu_epi64(l1, ri + 8);
    _mm512_mask_storeu_epi64(rs, l0, _mm512_add_epi64(_mm512_mullo_epi64(o0, mult), i0));
    _mm512_mask_storeu_epi64(rs + 8, l1, _mm512_add_epi64(_mm512_mullo_epi64(o1, mult), i1));
    // x = low 32 bits of ((old >> 18) ^ old) >> 27 and rot = old >> 59 = (high 32 bits) >> 27,
    // the 16 lanes' dwords gathered from the two halves by one permute each.
    const __m512i lo_idx = _mm512_set_epi32(30, 28, 26, 24, 22, 20, 18, 16, 14, 12, 10, 8, 6, 4, 2, 0);
    const __m512i hi_idx = _mm512_set_epi32(31, 29, 27, 25, 23, 21, 19, 17, 15, 13, 11, 9, 7, 5, 3, 1);
    auto xs = [](__m512i o) { return _mm512_srli_epi64(_mm512_xor_si512(_mm512_srli_epi64(o, 18), o), 27); };
    const __m512i x = _mm512_permutex2var_epi32(xs(o0), lo_idx, xs(o1));
    const __m512i r = _mm512_srli_epi32(_mm512_permutex2var_epi32(o0, hi_idx, o1), 27);
    return _mm512_rorv_epi32(x, r);
}

/// The bookkeeping of chaos-game.cpp's bookkeep<false> (hits only), for the fused step to do
/// in the same pass: its constants and the arrays it updates.
struct FusedBook {
    float xmin, xmax, ymin, ymax, scx, scy;
    std::uint32_t W, H, dummy, skip;
    std::uint32_t* age;
    std::uint32_t* idle;
    std::uint64_t* left;
    std::uint32_t* active;
    std::uint32_t* idx;
    std::uint32_t* prev;      ///< written (FusedBlock::prev is the same array, read first)
    std::uint32_t* hits;      ///< the worker's hit counters
    const std::uint32_t* lag; ///< the previous step's bins, deposited during this pass (or null)
};

struct FusedCounts {
    std::uint32_t plotted = 0, bad = 0, restarts = 0, still = 0;
};

/// One step of a block of float chains with the rules on: chosen[i] and restart[i] exactly as
/// choose_rules sets them, and the points of the chains that move inverted in place. With
/// Book (a colourer that needs no colour), also bookkeep<false>'s work on the new points in
/// registers (the same operations in the same order: see bookkeep in chaos_bookkeep.hpp), whose
/// counts it returns.
///
/// Steady (with Book) is the same step for a block in its steady state, which the caller
/// vouches for: every active chain past its `skip` and with more points left than the steps
/// it will run this way. Then a chain that moves to a finite point plots it, and none runs
/// out of points: age, idle, left and active are left alone (the caller settles left and idle
/// when the steady run ends, from the number of steps and the last step's restart flags) and
/// plotted and still are not counted. That is about a tenth of the pass's vector operations.
template <bool Book, bool Steady = false>
FusedCounts fused_rules_step(const FusedTables& tables, const FusedBlock& block,
                             const FusedBook* book = nullptr) {
    // Local copies: the stores through the arrays cannot alias them, so nothing is reloaded.
    const FusedTables t = tables;
    const FusedBlock b = block;
    FusedBook bkv{};
    if (Book) bkv = *book;
    const FusedBook* const bk = &bkv;
    const std::uint32_t k = t.k;
    const __m512 tcx = _mm512_load_ps(t.cx), tcy = _mm512_load_ps(t.cy), tr2 = _mm512_load_ps(t.r2);
    const __m512i one = _mm512_set1_epi32(1), vnone = _mm512_set1_epi32(int(k)),
                  zero = _mm512_setzero_si512();
    __mmask16 okm[fused_max_maps];
    FusedCounts n;
    __m512i vplotted = zero, vstill = zero; // per-lane counts (hits only)
    std::uint32_t* const hits = Book ? bkv.hits : nullptr;
    const std::uint32_t* const lag = Book ? bkv.lag : nullptr;
    for (std::size_t i = 0; i < b.nb; i += 16) {
        const __mmask16 live = b.nb - i >= 16 ? __mmask16(0xffff) : __mmask16((1u << (b.nb - i)) - 1u);
        const __m512 x = _mm512_maskz_loadu_ps(live, b.x + i), y = _mm512_maskz_loadu_ps(live, b.y + i);
        const __m512i p = _mm512_maskz_loadu_epi32(live, b.prev + i);
        // Inside tests and the total allowed weight (Circle::inside: dx * dx + dy * dy < r2).
        __m512i tot = zero;
        for (std::uint32_t j = 0; j < k; ++j) {
            const __m512 dx = _mm512_sub_ps(x, _mm512_set1_ps(t.cx[j]));
            const __m512 dy = _mm512_sub_ps(y, _mm512_set1_ps(t.cy[j]));
            const __m512 d2 = _mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy));
            // ok = not inside (!(d2 < r2), NaN included: NLT_UQ) and not the previous map.
            const __mmask16 ok =
                _mm512_mask_cmp_ps_mask(_mm512_cmpneq_epi32_mask(p, _mm512_set1_epi32(int(t.j[j]))), d2,
                                        _mm512_set1_ps(t.r2[j]), _CMP_NLT_UQ);
            okm[j] = ok;
            tot = _mm512_mask_add_epi32(tot, ok, tot, _mm512_set1_epi32(int(t.q[j])));
        }
        // The draw (choose_rules' AVX-512 loop, the same operations).
        const __m512i r = pcg16(b.rs + i, b.ri + i, live);
        const __m512i lo = _mm512_srli_epi64(_mm512_mul_epu32(r, tot), 32);
        const __m512i hi = _mm512_mul_epu32(_mm512_srli_epi64(r, 32), _mm512_srli_epi64(tot, 32));
        const __m512i u = _mm512_mask_blend_epi32(__mmask16(0xaaaa), lo, hi);
        __m512i cum = zero, c = zero;
        for (std::uint32_t j = 0; j < k; ++j) {
            cum = _mm512_mask_add_epi32(cum, okm[j], cum, _mm512_set1_epi32(int(t.q[j])));
            c = _mm512_mask_add_epi32(c, _mm512_cmple_epu32_mask(cum, u), c, one);
        }
        const __mmask16 act =
            _mm512_mask_cmpneq_epi32_mask(live, _mm512_maskz_loadu_epi32(live, b.active + i), zero);
        const __mmask16 some = _mm512_cmpneq_epi32_mask(tot, zero);
        const __mmask16 mv = act & some;
        const __m512i rst = _mm512_maskz_mov_epi32(act & __mmask16(~some), one);
        if (!Book) {
            _mm512_mask_storeu_epi32(b.chosen + i, live, _mm512_mask_blend_epi32(mv, vnone, c));
            _mm512_mask_storeu_epi32(b.restart + i, live, rst);
        }
        // The inversion in the chosen circle (Inversion::run with Circle::inversion_factor).
        const __m512 ox = _mm512_permutexvar_ps(c, tcx), oy = _mm512_permutexvar_ps(c, tcy);
        const __m512 r2 = _mm512_permutexvar_ps(c, tr2);
        const __m512 dx = _mm512_sub_ps(x, ox), dy = _mm512_sub_ps(y, oy);
        const __m512 s = _mm512_div_ps(r2, _mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)));
        const __m512 nx = _mm512_mask_add_ps(x, mv, ox, _mm512_mul_ps(s, dx));
        const __m512 ny = _mm512_mask_add_ps(y, mv, oy, _mm512_mul_ps(s, dy));
        _mm512_mask_storeu_ps(b.x + i, mv, nx);
        _mm512_mask_storeu_ps(b.y + i, mv, ny);
        if constexpr (Book) {
            // bookkeep<false> on (nx, ny), lane for lane.
            constexpr __mmask16 all = 0xffff;
            // finite (x - x == 0 in bookkeep): neither NaN nor infinite (fpclass 0x99).
            const __mmask16 fin =
                __mmask16(~(_mm512_fpclass_ps_mask(nx, 0x99) | _mm512_fpclass_ps_mask(ny, 0x99)));
            const __mmask16 isbad = mv & __mmask16(~fin);
            __mmask16 plot = mv & fin;
            if constexpr (!Steady) {
                __m512i a = _mm512_maskz_loadu_epi32(live, bk->age + i);
                const __mmask16 old = _mm512_cmpge_epu32_mask(a, _mm512_set1_epi32(int(bk->skip)));
                plot &= old;
                a = _mm512_mask_add_epi32(a, mv & __mmask16(~old), a, one);
                _mm512_mask_storeu_epi32(bk->age + i, live, a);
                _mm512_mask_storeu_epi32(bk->idle + i, plot, zero);
                vplotted = _mm512_mask_add_epi32(vplotted, plot, vplotted, one);
            }
            _mm512_mask_storeu_epi32(bk->prev + i, mv, c);
            const __m512i rs = _mm512_mask_or_epi32(rst, isbad, rst, _mm512_set1_epi32(2));
            _mm512_mask_storeu_epi32(b.restart + i, live, rs);
            const __mmask16 restarts = _mm512_mask_cmpneq_epi32_mask(live, rs, zero);
            if (__builtin_expect(restarts != 0, 0)) { // rare
                n.bad += unsigned(__builtin_popcount(unsigned(isbad)));
                n.restarts += unsigned(__builtin_popcount(unsigned(restarts)));
            }
            // bin index
            const __m512 xmin = _mm512_set1_ps(bk->xmin), ymax = _mm512_set1_ps(bk->ymax);
            const __mmask16 in = plot & _mm512_cmp_ps_mask(nx, xmin, _CMP_GE_OQ) &
                                 _mm512_cmp_ps_mask(nx, _mm512_set1_ps(bk->xmax), _CMP_LT_OQ) &
                                 _mm512_cmp_ps_mask(ny, _mm512_set1_ps(bk->ymin), _CMP_GT_OQ) &
                                 _mm512_cmp_ps_mask(ny, ymax, _CMP_LE_OQ);
            const __m512 fx = _mm512_maskz_mul_ps(in, _mm512_sub_ps(nx, xmin), _mm512_set1_ps(bk->scx));
            const __m512 fy = _mm512_maskz_mul_ps(in, _mm512_sub_ps(ymax, ny), _mm512_set1_ps(bk->scy));
            const __m512i ix = _mm512_maskz_min_epu32(all, _mm512_maskz_cvttps_epi32(all, fx),
                                                      _mm512_set1_epi32(int(bk->W - 1)));
            const __m512i iy = _mm512_maskz_min_epu32(all, _mm512_maskz_cvttps_epi32(all, fy),
                                                      _mm512_set1_epi32(int(bk->H - 1)));
            const __m512i id = _mm512_mask_blend_epi32(
                in, _mm512_set1_epi32(int(bk->dummy)),
                _mm512_add_epi32(_mm512_mullo_epi32(iy, _mm512_set1_epi32(int(bk->W))), ix));
            _mm512_mask_storeu_epi32(bk->idx + i, live, id);
            // points left (64-bit), activity
            if constexpr (!Steady) {
                const __mmask8 live0 = __mmask8(live), live1 = __mmask8(live >> 8);
                const __m512i one64 = _mm512_set1_epi64(1);
                __m512i l0 = _mm512_maskz_loadu_epi64(live0, bk->left + i);
                __m512i l1 = _mm512_maskz_loadu_epi64(live1, bk->left + i + 8);
                l0 = _mm512_mask_sub_epi64(l0, __mmask8(plot), l0, one64);
                l1 = _mm512_mask_sub_epi64(l1, __mmask8(plot >> 8), l1, one64);
                _mm512_mask_storeu_epi64(bk->left + i, __mmask8(plot), l0);
                _mm512_mask_storeu_epi64(bk->left + i + 8, __mmask8(plot >> 8), l1);
                const __mmask16 nz = __mmask16(_mm512_cmpneq_epi64_mask(l0, zero)) |
                                     __mmask16(__mmask16(_mm512_cmpneq_epi64_mask(l1, zero)) << 8);
                const __mmask16 still = nz & act;
                _mm512_mask_storeu_epi32(bk->active + i, live, _mm512_maskz_mov_epi32(still, one));
                vstill = _mm512_mask_add_epi32(vstill, still, vstill, one);
            }
            if (lag) {
                // A whole vector's 16 without a bound test per increment (those branches
                // would take issue slots on the vector ports).
                if (live == 0xffff)
                    for (std::size_t l = 0; l < 16; ++l) ++hits[lag[i + l]];
                else
                    for (std::size_t l = 0; l < b.nb - i; ++l) ++hits[lag[i + l]];
            }
        }
    }
    if constexpr (Book && !Steady) {
        n.plotted = std::uint32_t(_mm512_reduce_add_epi32(vplotted));
        n.still = std::uint32_t(_mm512_reduce_add_epi32(vstill));
    }
    return n;
}
#pragma GCC diagnostic pop
#endif

} // namespace fp_chaos
