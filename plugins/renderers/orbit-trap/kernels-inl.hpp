// orbit-trap's passes over its batch after each step, on the SIMD layer (compiled once per
// instruction set of the build from orbit-trap.cpp, dispatched at run time):
//   - retire: record the samples some trap caught (trap, ratio, iteration) and move the others
//     to the front, keeping their order; returns how many are left;
//   - test_retire: the same fused with the test of a trap the renderer tests inline
//     (fp::TrapKernel: Euclidean circles), in one pass: no virtual call, no key array written
//     and read back per circle. The trap test is exactly TrapKernel's formula: the circles from
//     last to first, a later hit replacing an earlier one, so the first circle that holds the
//     lane is left standing, as circles.cpp does. Lanes beyond `live` in the last vector are
//     computed on whatever the (padded) arrays hold and ignored.
// Survivors are written with compressing stores, in place (safe: a vector is loaded before
// anything at or after its start is written); the caught lanes' records are written lane by
// lane (a few per step). tests/unit/test_orbit_trap.cpp compares renders with Algorithm 3
// through the plugins' interfaces.
//
// With `check`, each vector is first checked against the reduction's target range (values in it
// stay as they are under the reduction, exactly; for `hexagonal` the hexagon, in_cell's
// operations lane-wise); a vector with a value outside is reduced in place before its test (the
// same reduction as the whole batch's) and `outside` is set.
// NC: the number of circles when it is one of the presets' (the loop over the circles unrolled,
// their constants kept in registers), 0 for any other.

#if defined(FP_ORBIT_TRAP_KERNELS_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef FP_ORBIT_TRAP_KERNELS_INL_HPP_
#undef FP_ORBIT_TRAP_KERNELS_INL_HPP_
#else
#define FP_ORBIT_TRAP_KERNELS_INL_HPP_
#endif

#include "batch.hpp"
#include "reduce.hpp"

#include <fixpoint/check.hpp>
#include <fixpoint/kernels-inl.hpp>
#include <fixpoint/simd-inl.hpp>

#include <hwy/highway.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace fp_orbit_trap::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace fs = fp::simd::HWY_NAMESPACE;
namespace fk = fp::kernels::HWY_NAMESPACE;

template <class T>
HWY_INLINE size_t retire_t(Scratch<T>& s, size_t live, uint32_t iteration) {
    const hn::ScalableTag<T> d;
    const size_t N = hn::Lanes(d);
    T* HWY_RESTRICT x = s.x.data();
    T* HWY_RESTRICT y = s.y.data();
    uint32_t* HWY_RESTRICT ids = s.id.data();
    const std::int32_t* HWY_RESTRICT caught = s.caught.data();
    // (The arrays are padded to whole blocks of the widest vectors: batch.hpp's Scratch.)
    FP_DCHECK(live <= s.caught.size() && s.x.size() % block == 0 && live <= s.x.size());
    size_t keep = 0;
    for (size_t i = 0; i < live; i += N) {
        const size_t m = std::min(N, live - i);
        // The survivors' mask, as bits (caught[i] >= 0: retired).
        uint8_t bits[(HWY_MAX_BYTES / sizeof(T) + 7) / 8] = {};
        bool any = false;
        for (size_t l = 0; l < m; ++l) {
            const bool out = caught[i + l] >= 0;
            any |= out;
            bits[l / 8] |= uint8_t(out ? 0 : 1) << (l % 8);
        }
        if (!any && keep == i) { // nothing retired so far: the lanes stay where they are
            keep += m;
            continue;
        }
        for (size_t l = 0; l < m; ++l)
            if (caught[i + l] >= 0) {
                const uint32_t id = ids[i + l];
                FP_DCHECK(id < s.trap.size());
                s.trap[id] = caught[i + l];
                s.ratio_out[id] = float(s.ratio[i + l]);
                s.iteration[id] = iteration;
            }
        const auto stay = hn::LoadMaskBits(d, bits);
        const auto order = fs::compress_order(d, stay); // (the SIMD layer's: see simd-inl.hpp)
        fs::compress_blended_store(d, hn::LoadU(d, x + i), stay, order, x + keep);
        fs::compress_blended_store(d, hn::LoadU(d, y + i), stay, order, y + keep);
        for (size_t l = 0; l < m; ++l) { // (w <= i + l: each id is read before it is overwritten)
            ids[keep] = ids[i + l];
            keep += caught[i + l] < 0 ? 1 : 0;
        }
    }
    return keep;
}

template <size_t NC, class T>
HWY_INLINE size_t test_retire_t(const KnownCircles<T>& c, Scratch<T>& s, size_t live, uint32_t iteration,
                                Reduction red, bool check, bool& outside) {
    const hn::ScalableTag<T> d;
    const hn::RebindToSigned<decltype(d)> di;
    using I = hn::TFromD<decltype(di)>;
    const size_t N = hn::Lanes(d);
    const Range<T> range(red);
    T* HWY_RESTRICT x = s.x.data();
    T* HWY_RESTRICT y = s.y.data();
    uint32_t* HWY_RESTRICT ids = s.id.data();
    const size_t nc = NC ? NC : c.cx.size();
    FP_DCHECK(nc == c.cx.size() && s.x.size() % block == 0 && live <= s.x.size());
    const T below_one = std::nextafter(T(1), T(0));
    alignas(HWY_MAX_BYTES) I tr[HWY_MAX_BYTES / sizeof(T)];
    alignas(HWY_MAX_BYTES) T kk[HWY_MAX_BYTES / sizeof(T)];
    const auto lo = hn::Set(d, range.lo), hi = hn::Set(d, range.hi);
    // The hexagonal reduction's range: the hexagon (the SDK's in_cell, lane-wise).
    const bool hexagonal = red == Reduction::hexagonal;
    size_t keep = 0;
    for (size_t i = 0; i < live; i += N) {
        const size_t m = std::min(N, live - i);
        const auto valid = hn::FirstN(d, m);
        auto vx = hn::LoadU(d, x + i), vy = hn::LoadU(d, y + i);
        if (check) {
            auto in = hn::And(hn::And(hn::Not(hn::Lt(vx, lo)), hn::Lt(vx, hi)),
                              hn::And(hn::Not(hn::Lt(vy, lo)), hn::Lt(vy, hi)));
            if (hexagonal) in = fk::in_cell(d, vx, vy);
            if (!hn::AllTrue(d, hn::Or(in, hn::Not(valid)))) {
                fp_orbit_trap::reduce_xy(x + i, y + i, m, red);
                outside = true;
                vx = hn::LoadU(d, x + i), vy = hn::LoadU(d, y + i);
            }
        }
        auto t = hn::Set(di, I(-1));
        auto k = hn::Zero(d);
        for (size_t j = nc; j-- > 0;) {
            // (The key of the Euclidean metric: |p - c|^2.)
            const auto kj = fk::offset(vx, vy, hn::Set(d, c.cx[j]), hn::Set(d, c.cy[j])).d2;
            const auto hit = hn::Lt(kj, hn::Set(d, c.key[j]));
            t = hn::IfThenElse(hn::RebindMask(di, hit), hn::Set(di, I(j)), t);
            k = hn::IfThenElse(hit, kj, k);
        }
        const auto out = hn::And(hn::RebindMask(d, hn::Not(hn::Lt(t, hn::Zero(di)))), valid);
        const bool any = !hn::AllFalse(d, out);
        if (!any && keep == i) { // nothing retired so far: the lanes stay where they are
            keep += m;
            continue;
        }
        hn::Store(any ? t : hn::Set(di, I(-1)), di, tr);
        if (any) {
            // The caught lanes' records (sqrt and the quotient correctly rounded, min as
            // std::min: the ratio is finite).
            hn::Store(k, d, kk);
            for (size_t l = 0; l < m; ++l) {
                if (tr[l] < 0) continue;
                const uint32_t id = ids[i + l];
                const auto tj = size_t(tr[l]);
                FP_DCHECK(id < s.trap.size() && tj < nc);
                s.trap[id] = std::int32_t(tr[l]);
                s.ratio_out[id] = float(std::min(std::sqrt(kk[l]) / c.r[tj], below_one));
                s.iteration[id] = iteration;
            }
        }
        const auto stay = hn::AndNot(out, valid);
        const auto order = fs::compress_order(d, stay);
        fs::compress_blended_store(d, vx, stay, order, x + keep);
        fs::compress_blended_store(d, vy, stay, order, y + keep);
        for (size_t l = 0; l < m; ++l) { // (keep <= i + l: each id is read before it is overwritten)
            ids[keep] = ids[i + l];
            keep += tr[l] < 0 ? 1 : 0;
        }
    }
    return keep;
}

template <class T>
HWY_INLINE size_t test_retire_any(const KnownCircles<T>& c, Scratch<T>& s, size_t live, uint32_t iteration,
                                  Reduction red, bool check, bool& outside) {
    switch (c.cx.size()) {
    case 1: return test_retire_t<1>(c, s, live, iteration, red, check, outside);
    case 2: return test_retire_t<2>(c, s, live, iteration, red, check, outside);
    case 3: return test_retire_t<3>(c, s, live, iteration, red, check, outside);
    case 4: return test_retire_t<4>(c, s, live, iteration, red, check, outside);
    case 5: return test_retire_t<5>(c, s, live, iteration, red, check, outside);
    case 7: return test_retire_t<7>(c, s, live, iteration, red, check, outside);
    default: return test_retire_t<0>(c, s, live, iteration, red, check, outside);
    }
}

size_t retire_f(Scratch<float>& s, size_t live, uint32_t iteration) { return retire_t(s, live, iteration); }
size_t retire_d(Scratch<double>& s, size_t live, uint32_t iteration) { return retire_t(s, live, iteration); }
size_t test_retire_f(const KnownCircles<float>& c, Scratch<float>& s, size_t live, uint32_t iteration,
                     Reduction red, bool check, bool& outside) {
    return test_retire_any(c, s, live, iteration, red, check, outside);
}
size_t test_retire_d(const KnownCircles<double>& c, Scratch<double>& s, size_t live, uint32_t iteration,
                     Reduction red, bool check, bool& outside) {
    return test_retire_any(c, s, live, iteration, red, check, outside);
}

// ---------------------------------------------------------------- a tile's start and end
// Plain loops, vectorised by the compiler for each target of this section (the same IEEE
// operations on every one: no contraction, exact conversions).

/// The tile's start points: pixels p0 .. p0 + np - 1 in row-major order, sample-major (sample
/// q of pixel p is lane q * np + p, so that every loop is a vector loop; the order of the lanes
/// changes nothing: each orbit is its own, and a pixel's samples are summed in integers); and
/// the per-sample records reset.
template <class T>
HWY_INLINE void tile_starts_t(const TileFrame& f, Scratch<T>& s, size_t p0, size_t np) {
    const size_t b = np * f.ns;
    const double w1 = double(f.width - 1), h1 = double(f.height - 1);
    size_t pi = p0 % f.width, pj = p0 / f.width; // pixel (pi, pj): no division per pixel
    for (size_t p = 0; p < np; ++p, pi = pi + 1 == f.width ? (++pj, 0) : pi + 1)
        s.u[p] = 2 * double(pi) - w1, s.v[p] = 2 * double(pj) - h1;
    // 1 / (W - 1) as a factor: a product is as symmetric under negation as a quotient, and the
    // same expression serves x and y, so the symmetry of the start points is exact either way.
    for (size_t q = 0; q < f.ns; ++q) {
        const double ox = 2 * f.offsets[q].x, oy = 2 * f.offsets[q].y;
        T* __restrict x = s.x.data() + q * np;
        T* __restrict y = s.y.data() + q * np;
        const double* __restrict u = s.u.data();
        const double* __restrict v = s.v.data();
        for (size_t p = 0; p < np; ++p) {
            x[p] = T(f.cx + f.hx * ((u[p] + ox) * f.iw));
            y[p] = T(f.cy - f.hy * ((v[p] + oy) * f.ih));
        }
    }
    for (size_t k = 0; k < b; ++k) s.id[k] = uint32_t(k);
    std::fill_n(s.trap.data(), b, -1);
    std::fill_n(s.ratio_out.data(), b, 0.0f);
    std::fill_n(s.iteration.data(), b, f.max_iterations);
}

void tile_starts_f(const TileFrame& f, Scratch<float>& s, size_t p0, size_t np) {
    tile_starts_t(f, s, p0, np);
}
void tile_starts_d(const TileFrame& f, Scratch<double>& s, size_t p0, size_t np) {
    tile_starts_t(f, s, p0, np);
}

/// The mean of each pixel's ns samples (rgb: sample-major, 3 channels each) into out, summed in
/// integers (order-independent): each channel value clamped to [0, 1] (NaN -> 0) and rounded
/// to nearest (halves up; llround's rule for v >= 0) at 24 fractional bits, exactly (v * 2^24
/// and the + 0.5 are exact in double), in one vectorised pass; then the sums per pixel.
void tile_mean_all(const float* __restrict rgb, uint32_t* __restrict q, uint64_t* __restrict sum, size_t np,
                   size_t ns, float* __restrict out) {
    const size_t nv = 3 * np * ns;
    // Two loops, each a vector loop (in one, GCC 12 turns the clamp into branches and keeps it
    // scalar): the clamp on the bits (negative values and NaNs -> 0, values >= 1 -> 1), then the
    // conversion (within int32's range).
    for (size_t i = 0; i < nv; ++i) {
        const auto u = std::bit_cast<std::int32_t>(rgb[i]);
        q[i] = uint32_t(u > 0x7f800000 ? 0 : u >= 0x3f800000 ? 0x3f800000 : u < 0 ? 0 : u);
    }
    for (size_t i = 0; i < nv; ++i)
        q[i] = uint32_t(std::int32_t(double(std::bit_cast<float>(q[i])) * sum_scale + 0.5));
    const double inv = 1.0 / (sum_scale * double(ns));
    if (ns == 1) {
        for (size_t i = 0; i < nv; ++i) out[i] = float(double(q[i]) * inv);
        return;
    }
    const size_t nc = 3 * np; // channel values per sample index
    for (size_t i = 0; i < nc; ++i) sum[i] = q[i];
    for (size_t k = 1; k < ns; ++k) {
        const uint32_t* __restrict c = q + k * nc;
        for (size_t i = 0; i < nc; ++i) sum[i] += c[i];
    }
    for (size_t i = 0; i < nc; ++i) out[i] = float(double(sum[i]) * inv);
}

} // namespace fp_orbit_trap::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif // per-target include guard
