// The SIMD layer's kernel side: loop drivers over point batches, written once on Google
// Highway and compiled for every target of the build (see fixpoint/simd.hpp for the host
// side and the rules that keep renders the same bytes on every target).
//
// A plugin puts its per-point arithmetic in a per-target section and dispatches to it:
//
//   // my-shape.cpp
//   #undef HWY_TARGET_INCLUDE
//   #define HWY_TARGET_INCLUDE "my-shape.cpp"  // this file, as found on the include path
//   #include <hwy/foreach_target.h>           // compiles what follows once per target
//   #include <fixpoint/simd-inl.hpp>
//   HWY_BEFORE_NAMESPACE();
//   namespace my_shape::HWY_NAMESPACE {
//   namespace hn = hwy::HWY_NAMESPACE;
//   namespace fs = fp::simd::HWY_NAMESPACE;
//   void inside_f(const Params& c, fp::Points<const float> p, unsigned char* out) {
//       const hn::ScalableTag<float> d;
//       fs::test_points(d, p, out, [&](auto x, auto y) { return hn::Lt(..., ...); });
//   }
//   }  // namespace my_shape::HWY_NAMESPACE
//   HWY_AFTER_NAMESPACE();
//   #if HWY_ONCE
//   namespace my_shape {
//   HWY_EXPORT(inside_f);
//   ... HWY_DYNAMIC_DISPATCH(inside_f)(params, p, out);   // in the plugin's class
//   }
//   #endif
//
// (fixpoint_add_plugin puts the plugin's own folder on the include path.) The drivers below
// take a lambda on whole vectors: full vectors straight from the arrays, the last partial
// one through a small buffer on the stack (no read or write past the batch's end on any
// target), and fp::Mask honoured lane by lane. No FMA (MulAdd) and no approximate
// reciprocals in kernels: the same recipe must give the same bytes on every target.

// Per-target include guard (Highway's convention): this file is compiled once per target.
#if defined(FIXPOINT_SIMD_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef FIXPOINT_SIMD_INL_HPP_
#undef FIXPOINT_SIMD_INL_HPP_
#else
#define FIXPOINT_SIMD_INL_HPP_
#endif

#include <fixpoint/batch.hpp>
#include <fixpoint/types.hpp>

#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace fp::simd::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

/// The most lanes of T a vector of any target holds (stack buffers for the tails).
template <class T>
constexpr std::size_t max_lanes = HWY_MAX_BYTES / sizeof(T);

/// The lane mask of n bytes of an fp::Mask (non-zero = active).
template <class D>
HWY_INLINE hn::Mask<D> load_mask(D d, const unsigned char* m) {
    using T = hn::TFromD<D>;
    using U = hwy::MakeUnsigned<T>;
    const hn::RebindToUnsigned<D> du;
    alignas(HWY_MAX_BYTES) U wide[max_lanes<T>];
    const std::size_t n = hn::Lanes(d);
    for (std::size_t i = 0; i < n; ++i) wide[i] = m[i] ? U(1) : U(0);
    return hn::RebindMask(d, hn::Ne(hn::Load(du, wide), hn::Zero(du)));
}

/// n bytes, 1 where the mask is set, else 0 (32-bit lanes: narrowed in registers).
template <class D>
HWY_INLINE void store_mask(D d, hn::Mask<D> m, unsigned char* out, std::size_t n) {
    using T = hn::TFromD<D>;
    if constexpr (sizeof(T) == 4) {
        const hn::RebindToSigned<D> di;
        const hn::Rebind<std::uint8_t, D> d8;
        const auto b = hn::DemoteTo(d8, hn::IfThenElseZero(hn::RebindMask(di, m), hn::Set(di, 1)));
        if (n == hn::Lanes(d)) {
            hn::StoreU(b, d8, out);
        } else {
            alignas(HWY_MAX_BYTES) std::uint8_t buf[max_lanes<T>];
            hn::Store(b, d8, buf);
            std::copy_n(buf, n, out);
        }
    } else {
        using U = hwy::MakeUnsigned<T>;
        const hn::RebindToUnsigned<D> du;
        alignas(HWY_MAX_BYTES) U wide[max_lanes<T>];
        hn::Store(hn::IfThenElseZero(hn::RebindMask(du, m), hn::Set(du, U(1))), du, wide);
        for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<unsigned char>(wide[i]);
    }
}

/// p[i] <- f(p[i]) for the active points: f(x, y) takes two vectors by reference and
/// replaces them. Inactive lanes (mask) keep their values whatever f computes for them.
template <class D, class F>
HWY_INLINE void map_points(D d, fp::Points<hn::TFromD<D>> p, fp::Mask mask, F&& f) {
    using T = hn::TFromD<D>;
    const std::size_t N = hn::Lanes(d);
    std::size_t i = 0;
    for (; i + N <= p.n; i += N) {
        auto x = hn::LoadU(d, p.x + i), y = hn::LoadU(d, p.y + i);
        const auto x0 = x, y0 = y;
        f(x, y);
        if (mask) {
            const auto m = load_mask(d, mask + i);
            x = hn::IfThenElse(m, x, x0);
            y = hn::IfThenElse(m, y, y0);
        }
        hn::StoreU(x, d, p.x + i);
        hn::StoreU(y, d, p.y + i);
    }
    if (i == p.n) return;
    const std::size_t r = p.n - i;
    alignas(HWY_MAX_BYTES) T bx[max_lanes<T>] = {}, by[max_lanes<T>] = {};
    unsigned char bm[max_lanes<T>] = {};
    std::copy_n(p.x + i, r, bx);
    std::copy_n(p.y + i, r, by);
    if (mask) std::copy_n(mask + i, r, bm);
    auto x = hn::Load(d, bx), y = hn::Load(d, by);
    const auto x0 = x, y0 = y;
    f(x, y);
    if (mask) {
        const auto m = load_mask(d, bm);
        x = hn::IfThenElse(m, x, x0);
        y = hn::IfThenElse(m, y, y0);
    }
    hn::Store(x, d, bx);
    hn::Store(y, d, by);
    std::copy_n(bx, r, p.x + i);
    std::copy_n(by, r, p.y + i);
}

/// map_points with one more array read alongside: f(x, y, e) with e the vector of extra[i].
template <class D, class F>
HWY_INLINE void map_points_with(D d, fp::Points<hn::TFromD<D>> p, fp::Mask mask, const hn::TFromD<D>* extra,
                                F&& f) {
    using T = hn::TFromD<D>;
    const std::size_t N = hn::Lanes(d);
    std::size_t i = 0;
    for (; i + N <= p.n; i += N) {
        auto x = hn::LoadU(d, p.x + i), y = hn::LoadU(d, p.y + i);
        const auto x0 = x, y0 = y;
        f(x, y, hn::LoadU(d, extra + i));
        if (mask) {
            const auto m = load_mask(d, mask + i);
            x = hn::IfThenElse(m, x, x0);
            y = hn::IfThenElse(m, y, y0);
        }
        hn::StoreU(x, d, p.x + i);
        hn::StoreU(y, d, p.y + i);
    }
    if (i == p.n) return;
    const std::size_t r = p.n - i;
    alignas(HWY_MAX_BYTES) T bx[max_lanes<T>] = {}, by[max_lanes<T>] = {}, be[max_lanes<T>] = {};
    unsigned char bm[max_lanes<T>] = {};
    std::copy_n(p.x + i, r, bx);
    std::copy_n(p.y + i, r, by);
    std::copy_n(extra + i, r, be);
    if (mask) std::copy_n(mask + i, r, bm);
    auto x = hn::Load(d, bx), y = hn::Load(d, by);
    const auto x0 = x, y0 = y;
    f(x, y, hn::Load(d, be));
    if (mask) {
        const auto m = load_mask(d, bm);
        x = hn::IfThenElse(m, x, x0);
        y = hn::IfThenElse(m, y, y0);
    }
    hn::Store(x, d, bx);
    hn::Store(y, d, by);
    std::copy_n(bx, r, p.x + i);
    std::copy_n(by, r, p.y + i);
}

/// out[i] = 1 where f(x, y) (a mask) holds for point i, else 0.
template <class D, class F>
HWY_INLINE void test_points(D d, fp::Points<const hn::TFromD<D>> p, unsigned char* out, F&& f) {
    using T = hn::TFromD<D>;
    const std::size_t N = hn::Lanes(d);
    std::size_t i = 0;
    for (; i + N <= p.n; i += N) store_mask(d, f(hn::LoadU(d, p.x + i), hn::LoadU(d, p.y + i)), out + i, N);
    if (i == p.n) return;
    const std::size_t r = p.n - i;
    alignas(HWY_MAX_BYTES) T bx[max_lanes<T>] = {}, by[max_lanes<T>] = {};
    std::copy_n(p.x + i, r, bx);
    std::copy_n(p.y + i, r, by);
    store_mask(d, f(hn::Load(d, bx), hn::Load(d, by)), out + i, r);
}

/// out[i] = f(x, y) (a vector) for point i.
template <class D, class F>
HWY_INLINE void eval_points(D d, fp::Points<const hn::TFromD<D>> p, hn::TFromD<D>* out, F&& f) {
    using T = hn::TFromD<D>;
    const std::size_t N = hn::Lanes(d);
    std::size_t i = 0;
    for (; i + N <= p.n; i += N) hn::StoreU(f(hn::LoadU(d, p.x + i), hn::LoadU(d, p.y + i)), d, out + i);
    if (i == p.n) return;
    const std::size_t r = p.n - i;
    alignas(HWY_MAX_BYTES) T bx[max_lanes<T>] = {}, by[max_lanes<T>] = {}, bo[max_lanes<T>];
    std::copy_n(p.x + i, r, bx);
    std::copy_n(p.y + i, r, by);
    hn::Store(f(hn::Load(d, bx), hn::Load(d, by)), d, bo);
    std::copy_n(bo, r, out + i);
}

// ---------------------------------------------------------------- per-point plugins
// The batch loops of a shape or transform written per point (fp::ShapeBase's inside_pt and
// ray_exit_pt, compiled here once per target: the compiler
// vectorises them with each target's instructions. The per-point functions must be inlined
// into these loops: declare them FIXPOINT_INLINE (see FIXPOINT_SIMD_SHAPE below).

template <class S, class T>
HWY_INLINE void shape_inside(const S& s, fp::Points<const T> p, unsigned char* out) {
    for (std::size_t i = 0; i < p.n; ++i) out[i] = s.inside_pt(p.x[i], p.y[i]) ? 1 : 0;
}
template <class S, class T>
HWY_INLINE void shape_ray_exit(const S& s, fp::Vec2 o, fp::Points<const T> d, T* t) {
    const T ox = T(o.x), oy = T(o.y);
    for (std::size_t i = 0; i < d.n; ++i) t[i] = s.ray_exit_pt(ox, oy, d.x[i], d.y[i]);
}
/// Finite lanes (neither NaN nor infinite): x - x == 0.
template <class V>
HWY_INLINE auto finite(V x) {
    return hn::Eq(hn::Sub(x, x), hn::Zero(hn::DFromV<V>()));
}

// ---------------------------------------------------------------- compress
// hn::Compress without the table copy. Highway 1.0.3 (Debian 12) finds the lane order of a
// compress in a table declared `constexpr` but not `static` inside the function: for 64-bit
// lanes of AVX-512 and for 32- and 64-bit lanes of AVX2 (CompressStore and
// CompressBlendedStore too), and GCC builds that table on the stack at every call (`rep
// movsq` of up to 2 KiB). The chaos game's grouping by map spent 29% of an AVX2 render of
// configs/inversion/fig6a.yaml, and 62% of a double render on AVX-512, copying it. Here the
// table is a constant of its own, for vectors of 2 to 8 lanes; wider vectors (AVX-512's
// 32-bit lanes, which have a compress instruction; SVE) keep hn::Compress.
namespace detail {
/// For each mask of 8 lanes: the lanes it selects, then the others, in 4-bit fields.
struct CompressTable {
    std::uint32_t order[256];
};
constexpr CompressTable make_compress_table() {
    CompressTable t{};
    for (unsigned m = 0; m < 256; ++m) {
        std::uint32_t packed = 0;
        unsigned at = 0;
        for (unsigned pass = 0; pass < 2; ++pass)
            for (unsigned l = 0; l < 8; ++l)
                if (((m >> l) & 1u) == (pass == 0 ? 1u : 0u)) packed |= std::uint32_t(l) << (4 * at++);
        t.order[m] = packed;
    }
    return t;
}
inline constexpr CompressTable compress_table = make_compress_table();
} // namespace detail

/// Whether compress() takes the table path for vectors of D.
template <class D>
constexpr bool compress_by_table() {
    return HWY_TARGET != HWY_SCALAR && hn::MaxLanes(D()) >= 2 && hn::MaxLanes(D()) <= 8;
}

/// The lane order that moves the lanes set in m to the front, for compress(); computed once
/// for all the vectors moved by the same mask.
template <class D>
HWY_INLINE hn::Vec<hn::RebindToUnsigned<D>> compress_order(D d, hn::Mask<D> m) {
    const hn::RebindToUnsigned<D> du;
    using U = hn::TFromD<decltype(du)>;
    if constexpr (compress_by_table<D>()) {
        std::uint8_t bits[8] = {};
        hn::StoreMaskBits(d, m, bits);
        const auto packed = hn::Set(du, U(detail::compress_table.order[bits[0]]));
        const auto shift = hn::ShiftLeft<2>(hn::Iota(du, U(0)));
        return hn::And(packed >> shift, hn::Set(du, U(7)));
    } else {
        (void)d;
        (void)m;
        return hn::Zero(du);
    }
}

/// hn::Compress(v, m): the lanes set in m first, in order (the other lanes hold other values
/// of v); `order` is compress_order(d, m), of any tag with v's lane size.
template <class D>
HWY_INLINE hn::Vec<D> compress(D d, hn::Vec<D> v, hn::Mask<D> m, hn::Vec<hn::RebindToUnsigned<D>> order) {
    if constexpr (compress_by_table<D>()) {
        (void)m;
        return hn::TableLookupLanes(v, hn::IndicesFromVec(d, order));
    } else {
        (void)d;
        (void)order;
        return hn::Compress(v, m);
    }
}

/// hn::CompressBlendedStore(v, m, d, p): the lanes set in m stored from p, in order, and
/// nothing past them (order: compress_order(d, m)).
template <class D>
HWY_INLINE void compress_blended_store(D d, hn::Vec<D> v, hn::Mask<D> m,
                                       hn::Vec<hn::RebindToUnsigned<D>> order, hn::TFromD<D>* p) {
    if constexpr (compress_by_table<D>()) {
        hn::BlendedStore(compress(d, v, m, order), hn::FirstN(d, hn::CountTrue(d, m)), d, p);
    } else {
        (void)order;
        hn::CompressBlendedStore(v, m, d, p);
    }
}

} // namespace fp::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif // per-target include guard
