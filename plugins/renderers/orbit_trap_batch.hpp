// orbit-trap's batch of samples and the passes over it after each step: the record of the
// caught samples and the compaction of the survivors (retire), and the fused pass for a trap the
// renderer tests inline (fp::TrapKernel: Euclidean circles), test + record + compaction in one
// pass, 16 float lanes per AVX-512 vector. See orbit-trap.cpp for the algorithm around them.
#pragma once

#include "orbit_trap_reduce.hpp"

#include <fixpoint/fixpoint.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace fp_orbit_trap {

using std::size_t;
using std::uint32_t;
using std::uint64_t;

template <class T>
struct Scratch {
    std::vector<T> x, y, ratio;
    std::vector<uint32_t> id;
    std::vector<std::int32_t> caught;
    // Results per sample of the tile.
    std::vector<std::int32_t> trap;
    std::vector<float> ratio_out;
    std::vector<uint32_t> iteration;
    std::vector<float> rgb;
    std::vector<uint32_t> quant; ///< rgb rounded to 24 fractional bits
    std::vector<uint64_t> sum;   ///< per pixel and channel: the sum of its samples' quant
    std::vector<double> u, v;    ///< per pixel: 2 i - (W - 1), 2 j - (H - 1)

    void resize(size_t n, size_t pixels) {
        sum.resize(3 * pixels), u.resize(pixels), v.resize(pixels);
        // x, y, id padded to whole blocks of the fused pass (which reads whole blocks).
        const size_t padded = (n + 15) / 16 * 16;
        x.resize(padded), y.resize(padded), id.resize(padded), ratio.resize(n), caught.resize(n);
        trap.resize(n), ratio_out.resize(n), iteration.resize(n), rgb.resize(3 * n), quant.resize(3 * n);
    }
};

struct TileStats {
    uint64_t drawn = 0, bad = 0;
};

// After a step: record the samples some trap caught (trap, ratio, iteration) and move the
// others to the front, keeping their order; returns how many are left. With AVX-512 (float
// lanes) 16 lanes at a time: a mask of the caught, the caught recorded bit by bit (a few per
// step), the survivors written with compress stores (in place is safe: a block is loaded before
// anything at or after its start is written). Otherwise a scalar loop without branches for the
// compaction (every lane is copied; the write position advances past survivors only). Both give
// the same result.
template <class T>
size_t retire(Scratch<T>& s, size_t live, uint32_t iteration) {
    T* __restrict x = s.x.data();
    T* __restrict y = s.y.data();
    uint32_t* __restrict ids = s.id.data();
    const std::int32_t* __restrict caught = s.caught.data();
    auto record = [&](size_t i) {
        const uint32_t id = ids[i];
        s.trap[id] = caught[i];
        s.ratio_out[id] = float(s.ratio[i]);
        s.iteration[id] = iteration;
    };
    size_t i = 0, keep = 0;
#if defined(__AVX512F__)
    if constexpr (std::is_same_v<T, float>) {
        const __m512i zero = _mm512_setzero_si512();
        for (; i + 16 <= live; i += 16) {
            const __m512i c = _mm512_loadu_si512(caught + i);
            const __mmask16 out = _mm512_cmpge_epi32_mask(c, zero);
            if (out == 0xffff) {
                for (size_t k = 0; k < 16; ++k) record(i + k);
                continue;
            }
            for (unsigned m = out; m; m &= m - 1) record(i + size_t(__builtin_ctz(m)));
            const __mmask16 stay = __mmask16(~out);
            const __m512 vx = _mm512_loadu_ps(x + i), vy = _mm512_loadu_ps(y + i);
            const __m512i vid = _mm512_loadu_si512(ids + i);
            _mm512_mask_compressstoreu_ps(x + keep, stay, vx);
            _mm512_mask_compressstoreu_ps(y + keep, stay, vy);
            _mm512_mask_compressstoreu_epi32(ids + keep, stay, vid);
            keep += size_t(__builtin_popcount(unsigned(stay)));
        }
    }
#endif
    for (size_t j = i; j < live; ++j)
        if (caught[j] >= 0) record(j);
    for (; i < live; ++i) {
        x[keep] = x[i];
        y[keep] = y[i];
        ids[keep] = ids[i];
        keep += caught[i] < 0 ? 1 : 0;
    }
    return keep;
}

/// A trap the renderer tests inline (fp::TrapKernel::euclidean_circles), in T.
template <class T>
struct KnownCircles {
    std::vector<T> cx, cy, key, r;
};

/// Lanes per block of the fused pass (one AVX-512 vector of floats).
constexpr size_t block = 16;

// The fused pass after a step, for a known trap: the trap test (exactly TrapKernel's formula:
// the circles from last to first, a later hit replacing an earlier one, so the first circle that
// holds the lane is left standing, as circles.cpp does), the record of the caught lanes and the
// compaction of the survivors, 16 lanes at a time, in one pass over the batch: no virtual call,
// no key array written and read back per circle. Lanes beyond `live` in the last block are
// computed on whatever the (padded) arrays hold and ignored. Gives what Trap::test and retire()
// give: tests/unit/test_orbit_trap.cpp compares renders with Algorithm 3 through the plugins'
// interfaces.
//
// With `check`, each block is first checked against the reduction's target range (values in it
// stay as they are under the reduction, exactly); a block with a value outside is reduced in
// place before its test (the same exact reduction as the whole batch's) and `outside` is set.
// NC: the number of circles when it is one of the presets' (the loop over the circles unrolled,
// their constants kept in registers), 0 for any other.
template <size_t NC, class T>
size_t test_retire(const KnownCircles<T>& c, Scratch<T>& s, size_t live, uint32_t iteration, Reduction red,
                   bool check, bool& outside) {
    const fp_orbit_trap::Range<T> range(red);
    auto reduce_block = [&](size_t i, size_t m) {
        fp_orbit_trap::reduce(s.x.data() + i, m, red);
        fp_orbit_trap::reduce(s.y.data() + i, m, red);
        outside = true;
    };
    T* __restrict x = s.x.data();
    T* __restrict y = s.y.data();
    uint32_t* __restrict ids = s.id.data();
    const size_t nc = NC ? NC : c.cx.size();
    const T below_one = std::nextafter(T(1), T(0));
    alignas(64) std::int32_t tr[block];
    alignas(64) T kk[block];
    auto record = [&](size_t i, size_t l) {
        const uint32_t id = ids[i];
        const auto t = size_t(tr[l]);
        s.trap[id] = tr[l];
        s.ratio_out[id] = float(std::min(std::sqrt(kk[l]) / c.r[t], below_one));
        s.iteration[id] = iteration;
    };
    size_t keep = 0;
#if defined(__AVX512F__)
    if constexpr (std::is_same_v<T, float>) {
        const __m512i none = _mm512_set1_epi32(-1);
        const __m512i step = _mm512_set1_epi32(std::int32_t(iteration));
        const __m512 one_minus = _mm512_set1_ps(below_one);
        alignas(64) float rad[16] = {};
        for (size_t j = 0; j < std::min<size_t>(nc, 16); ++j) rad[j] = c.r[j];
        const __m512 radii = _mm512_load_ps(rad);
        const __m512 lo = _mm512_set1_ps(range.lo), hi = _mm512_set1_ps(range.hi);
        // With NC known, the circles' constants broadcast once, into locals the compiler can
        // keep in registers (read through c, they might alias the stores below).
        constexpr size_t ncl = NC ? NC : 1;
        __m512 vcx[ncl], vcy[ncl], vkey[ncl];
        for (size_t j = 0; j < (NC ? NC : 0); ++j)
            vcx[j] = _mm512_set1_ps(c.cx[j]), vcy[j] = _mm512_set1_ps(c.cy[j]),
            vkey[j] = _mm512_set1_ps(c.key[j]);
        for (size_t i = 0; i < live; i += block) {
            const size_t m = std::min(block, live - i);
            const __mmask16 valid = m == block ? __mmask16(0xffff) : __mmask16((1u << m) - 1);
            __m512 vx = _mm512_loadu_ps(x + i), vy = _mm512_loadu_ps(y + i);
            if (check) {
                const __mmask16 in =
                    _mm512_cmp_ps_mask(vx, lo, _CMP_GE_OQ) & _mm512_cmp_ps_mask(vx, hi, _CMP_LT_OQ) &
                    _mm512_cmp_ps_mask(vy, lo, _CMP_GE_OQ) & _mm512_cmp_ps_mask(vy, hi, _CMP_LT_OQ);
                if ((in & valid) != valid) {
                    reduce_block(i, m);
                    vx = _mm512_loadu_ps(x + i), vy = _mm512_loadu_ps(y + i);
                }
            }
            __m512i t = none;
            __m512 k = _mm512_setzero_ps();
            for (size_t j = nc; j-- > 0;) {
                const __m512 dx = _mm512_sub_ps(vx, NC ? vcx[j] : _mm512_set1_ps(c.cx[j]));
                const __m512 dy = _mm512_sub_ps(vy, NC ? vcy[j] : _mm512_set1_ps(c.cy[j]));
                const __m512 kj = _mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy));
                const __m512 keyj = NC ? vkey[j] : _mm512_set1_ps(c.key[j]);
                const __mmask16 hit = _mm512_cmp_ps_mask(kj, keyj, _CMP_LT_OQ);
                t = _mm512_mask_mov_epi32(t, hit, _mm512_set1_epi32(std::int32_t(j)));
                k = _mm512_mask_mov_ps(k, hit, kj);
            }
            const __mmask16 out = __mmask16(_mm512_cmpge_epi32_mask(t, _mm512_setzero_si512()) & valid);
            if (out && nc <= 16) {
                // The caught lanes' records, 16 at a time (scatters; sqrt and the quotient
                // correctly rounded, min as std::min: the ratio is finite): most samples of an
                // S-iteration render are caught in their first steps.
                const __m512i vid = _mm512_loadu_si512(ids + i);
                // (maskz forms: the plain ones trip GCC 12's -Wmaybe-uninitialized in its headers)
                const __m512 r = _mm512_maskz_permutexvar_ps(out, t, radii);
                const __m512 ratio = _mm512_maskz_min_ps(
                    out, _mm512_maskz_div_ps(out, _mm512_maskz_sqrt_ps(out, k), r), one_minus);
                _mm512_mask_i32scatter_epi32(s.trap.data(), out, vid, t, 4);
                _mm512_mask_i32scatter_ps(s.ratio_out.data(), out, vid, ratio, 4);
                _mm512_mask_i32scatter_epi32(s.iteration.data(), out, vid, step, 4);
            } else if (out) {
                _mm512_store_si512(tr, t);
                _mm512_store_ps(kk, k);
                for (unsigned b = out; b; b &= b - 1) {
                    const auto l = size_t(__builtin_ctz(b));
                    record(i + l, l);
                }
            } else if (keep == i) { // nothing retired so far: the lanes stay where they are
                keep += m;
                continue;
            }
            const __mmask16 stay = __mmask16(valid & ~out);
            _mm512_mask_compressstoreu_ps(x + keep, stay, vx);
            _mm512_mask_compressstoreu_ps(y + keep, stay, vy);
            _mm512_mask_compressstoreu_epi32(ids + keep, stay, _mm512_loadu_si512(ids + i));
            keep += size_t(__builtin_popcount(unsigned(stay)));
        }
        return keep;
    }
#endif
    for (size_t i = 0; i < live; i += block) {
        const size_t m = std::min(block, live - i);
        if (check) {
            bool in = true;
            for (size_t l = 0; l < m; ++l)
                in &= x[i + l] >= range.lo && x[i + l] < range.hi && y[i + l] >= range.lo &&
                      y[i + l] < range.hi;
            if (!in) reduce_block(i, m);
        }
        for (size_t l = 0; l < block; ++l) tr[l] = -1, kk[l] = T(0);
        for (size_t j = nc; j-- > 0;) {
            const T cx = c.cx[j], cy = c.cy[j], key = c.key[j];
            const auto idx = std::int32_t(j);
            for (size_t l = 0; l < block; ++l) {
                const T dx = x[i + l] - cx, dy = y[i + l] - cy;
                const T kj = dx * dx + dy * dy;
                const bool hit = kj < key;
                tr[l] = hit ? idx : tr[l];
                kk[l] = hit ? kj : kk[l];
            }
        }
        unsigned out = 0;
        for (size_t l = 0; l < m; ++l) out |= unsigned(tr[l] >= 0) << l;
        if (!out && keep == i) {
            keep += m;
            continue;
        }
        for (size_t l = 0; l < m; ++l) {
            if (tr[l] >= 0) {
                record(i + l, l);
            } else {
                x[keep] = x[i + l], y[keep] = y[i + l], ids[keep] = ids[i + l];
                ++keep;
            }
        }
    }
    return keep;
}

template <class T>
size_t test_retire(const KnownCircles<T>& c, Scratch<T>& s, size_t live, uint32_t iteration, Reduction red,
                   bool check, bool& outside) {
    switch (c.cx.size()) {
    case 1: return test_retire<1>(c, s, live, iteration, red, check, outside);
    case 2: return test_retire<2>(c, s, live, iteration, red, check, outside);
    case 3: return test_retire<3>(c, s, live, iteration, red, check, outside);
    case 4: return test_retire<4>(c, s, live, iteration, red, check, outside);
    case 5: return test_retire<5>(c, s, live, iteration, red, check, outside);
    case 7: return test_retire<7>(c, s, live, iteration, red, check, outside);
    default: return test_retire<0>(c, s, live, iteration, red, check, outside);
    }
}

} // namespace fp_orbit_trap
