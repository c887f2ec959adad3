// The wallpaper map's hot loop: f(p) = u(X)^T Q v(Y) reduced "mod 2 pi", over batches.
//
// Per point (no call, branch or lookup; the loop over a chunk vectorises):
//   (X, Y) = (x, y), or (v0 . p, v1 . p) for the hexagonal groups;
//   sin and cos of X and Y once (wallpaper_fastmath.hpp), sin 2t = (2 cos t) sin t,
//   cos 2t = (2 cos t) cos t - 1;
//   f_x = sum_i u_i (sum_j Qx_ij v_j)    (row by row),
//   f_y = sum_j v_j (sum_i Qy_ij u_i)    (column by column),
// each sum in increasing index order, starting with its first term (no "0 +"), with u_0 = v_0 = 1
// not multiplied. f_y is f_x's expression with the roles of (u, v) and of (Qx, Qy^T) exchanged, so
// when Qy = Qx^T (a mirror x <-> y) f_y(x, y) and f_x(y, x) are the same operations on the same
// numbers: bitwise equal. With sin odd and cos even bitwise, and negation exact, f(-x, y),
// f(x, -y) and the rotation (-y, x) are bitwise what the symmetry says too (up to the sign of an
// exact zero).
//
// Zero terms: the coefficient masks are template parameters; the constructor picks the
// smallest of a few masks (the "cross" form of pmm, cmm and p4m, the odd form of p2, p4 and
// p4g, the hexagonal form, dense) that holds every non-zero coefficient, once, so the dense form
// stays correct for any Q and a sparse group skips its zeros at no cost per point.
#pragma once

#include "wallpaper_fastmath.hpp"
#include "wallpaper_groups.hpp"

#include <fixpoint/batch.hpp>
#include <fixpoint/lattice.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>

#if defined(__GNUC__) && !defined(__clang__)
#define FP_WALLPAPER_IVDEP _Pragma("GCC ivdep")
#else
#define FP_WALLPAPER_IVDEP
#endif

namespace fp_wallpaper {

/// "mod 2 pi" (the SDK's lattice reductions, which the orbit-trap renderer applies too).
using Reduction = fp::kernels::Reduction;

// ------------------------------------------------------------------ coefficient masks

/// Bit i * 5 + j: Q_ij may be non-zero. rows / cols: 5-bit sets.
constexpr std::uint32_t block(unsigned rows, unsigned cols) {
    std::uint32_t m = 0;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
            if ((rows >> i & 1) && (cols >> j & 1)) m |= 1u << (i * 5 + j);
    return m;
}
constexpr unsigned even = 0b00111, odd = 0b11000; // {1, cos t, cos 2t}, {sin t, sin 2t}
constexpr std::uint32_t mask_dense = block(31, 31);
constexpr std::uint32_t mask_odd = block(even, odd) | block(odd, even);          // f(-p) = -f(p)
constexpr std::uint32_t mask_cross = block(odd, even);                           // f_x of pmm
constexpr std::uint32_t mask_hex = block(0b10101, 0b01010) | block(0b01010, 31); // |a|, |b| <= 2

constexpr bool has(std::uint32_t m, int i, int j) { return (m >> (i * 5 + j)) & 1; }
constexpr bool row_any(std::uint32_t m, int i) { return (m >> (i * 5)) & 31u; }
constexpr int first_col(std::uint32_t m, int i) {
    for (int j = 0; j < 5; ++j)
        if (has(m, i, j)) return j;
    return 5;
}
constexpr int first_row(std::uint32_t m) {
    for (int i = 0; i < 5; ++i)
        if (row_any(m, i)) return i;
    return 5;
}

// ------------------------------------------------------------------ the form

template <std::uint32_t M, int I, int J, class T>
[[gnu::always_inline]] inline T term(const T (&c)[5][5], const T (&b)[5]) {
    if constexpr (J == 0)
        return c[I][0];
    else
        return c[I][J] * b[J];
}

/// sum_j c_Ij b_j over the row's mask, b_0 = 1.
template <std::uint32_t M, int I, class T, int... J>
[[gnu::always_inline]] inline T row_sum(const T (&c)[5][5], const T (&b)[5],
                                        std::integer_sequence<int, J...>) {
    constexpr int first = first_col(M, I);
    T acc = term<M, I, first>(c, b);
    (
        [&]() __attribute__((always_inline)) {
            if constexpr (J > first && has(M, I, J)) acc = acc + term<M, I, J>(c, b);
        }(),
        ...);
    return acc;
}

template <std::uint32_t M, int I, class T>
[[gnu::always_inline]] inline T row_term(const T (&c)[5][5], const T (&a)[5], const T (&b)[5]) {
    const T t = row_sum<M, I>(c, b, std::make_integer_sequence<int, 5>{});
    if constexpr (I == 0)
        return t;
    else
        return a[I] * t;
}

/// sum_i a_i (sum_j c_ij b_j) over the mask, a_0 = b_0 = 1.
template <std::uint32_t M, class T, int... I>
[[gnu::always_inline]] inline T form(const T (&c)[5][5], const T (&a)[5], const T (&b)[5],
                                     std::integer_sequence<int, I...>) {
    if constexpr (M == 0) {
        return T(0);
    } else {
        constexpr int first = first_row(M);
        T acc = row_term<M, first>(c, a, b);
        (
            [&]() __attribute__((always_inline)) {
                if constexpr (I > first && row_any(M, I)) acc = acc + row_term<M, I>(c, a, b);
            }(),
            ...);
        return acc;
    }
}

/// Coefficients in one precision: qx[i][j] = Qx_ij, qyt[j][i] = Qy_ij.
template <class T>
struct Coef {
    alignas(64) T qx[5][5];
    alignas(64) T qyt[5][5];
};

template <std::uint32_t MX, std::uint32_t MYT, bool HEX, class T>
[[gnu::always_inline]] inline void map_point(const Coef<T>& k, T x, T y, T& fx, T& fy) {
    T X = x, Y = y;
    if constexpr (HEX) {
        // v0 = (1, -1/sqrt 3), v1 = (0, -2/sqrt 3)
        X = x - y * T(0.57735026918962576451);
        Y = y * T(-1.15470053837925152902);
    }
    T sx, cx, sy, cy;
    sincos(X, sx, cx);
    sincos(Y, sy, cy);
    const T tx = cx + cx, ty = cy + cy; // cos 2t = (2 cos t) cos t - 1, sin 2t = (2 cos t) sin t
    const T u[5] = {T(1), cx, tx * cx - T(1), sx, tx * sx};
    const T v[5] = {T(1), cy, ty * cy - T(1), sy, ty * sy};
    fx = form<MX>(k.qx, u, v, std::make_integer_sequence<int, 5>{});
    fy = form<MYT>(k.qyt, v, u, std::make_integer_sequence<int, 5>{});
}

template <std::uint32_t MX, std::uint32_t MYT, bool HEX, class T>
[[gnu::always_inline]] inline void map_chunk(const Coef<T>& k, const T* x, const T* y, T* fx, T* fy,
                                             std::size_t n) {
    FP_WALLPAPER_IVDEP
    for (std::size_t i = 0; i < n; ++i) map_point<MX, MYT, HEX>(k, x[i], y[i], fx[i], fy[i]);
}

template <class T, class R>
[[gnu::always_inline]] inline void store(T* x, T* y, const T* fx, const T* fy, fp::Mask m, std::size_t n,
                                         R r) {
    if (!m) {
        FP_WALLPAPER_IVDEP
        for (std::size_t i = 0; i < n; ++i) x[i] = r(fx[i]), y[i] = r(fy[i]);
        return;
    }
    FP_WALLPAPER_IVDEP
    for (std::size_t i = 0; i < n; ++i) {
        const T a = r(fx[i]), b = r(fy[i]);
        x[i] = m[i] ? a : x[i];
        y[i] = m[i] ? b : y[i];
    }
}

/// The hexagonal reduction (fixpoint/lattice.hpp) needs x and y together.
template <class T>
[[gnu::always_inline]] inline void store_hexagonal(T* x, T* y, const T* fx, const T* fy, fp::Mask m,
                                                   std::size_t n) {
    if (!m) {
        FP_WALLPAPER_IVDEP
        for (std::size_t i = 0; i < n; ++i) {
            T a = fx[i], b = fy[i];
            fp::kernels::reduce_hexagonal(a, b);
            x[i] = a, y[i] = b;
        }
        return;
    }
    FP_WALLPAPER_IVDEP
    for (std::size_t i = 0; i < n; ++i) {
        T a = fx[i], b = fy[i];
        fp::kernels::reduce_hexagonal(a, b);
        x[i] = m[i] ? a : x[i];
        y[i] = m[i] ? b : y[i];
    }
}

// ------------------------------------------------------------------ the map

/// f(p) = u(X)^T Q v(Y) mod 2 pi, for any Q (hex: (X, Y) = (v0 . p, v1 . p)); mod the hexagonal
/// lattice with Reduction::hexagonal.
class Map {
public:
    Map(const Matrix& Q, bool hex, Reduction reduction) : hex_(hex), reduction_(reduction) {
        std::uint32_t nzx = 0, nzyt = 0;
        for (int i = 0; i < 5; ++i)
            for (int j = 0; j < 5; ++j) {
                f_.qx[i][j] = float(Q[i][j].x), f_.qyt[j][i] = float(Q[i][j].y);
                d_.qx[i][j] = Q[i][j].x, d_.qyt[j][i] = Q[i][j].y;
                if (Q[i][j].x != 0) nzx |= 1u << (i * 5 + j);
                if (Q[i][j].y != 0) nzyt |= 1u << (j * 5 + i);
            }
        const auto fits = [&](std::uint32_t m) { return (nzx & ~m) == 0 && (nzyt & ~m) == 0; };
        if (hex)
            form_ = fits(mask_hex) ? Form::hex : Form::hex_dense;
        else
            form_ = fits(mask_cross) ? Form::cross : fits(mask_odd) ? Form::odd : Form::dense;
    }

    template <class T>
    void apply(fp::Points<T> p, fp::Mask mask) const {
        for (std::size_t base = 0; base < p.n; base += fp::chunk_size) {
            const std::size_t n = std::min(fp::chunk_size, p.n - base);
            T *x = p.x + base, *y = p.y + base;
            if (!mask) {
                run(x, y, nullptr, n);
                continue;
            }
            // Runs of retired points are skipped 32 at a time: renderers retire orbits in
            // coherent groups (neighbouring pixels), and a retired lane costs as much as an
            // active one in the vector loop. One test per 32 points; the result is the same.
            const fp::Mask m = mask + base;
            std::size_t s = 0;
            while (s < n) {
                std::size_t e = s;
                while (e < n && any(m + e, std::min<std::size_t>(32, n - e)))
                    e += std::min<std::size_t>(32, n - e);
                if (e > s) run(x + s, y + s, m + s, e - s);
                s = e < n ? e + std::min<std::size_t>(32, n - e) : n; // e's block is all retired
            }
        }
    }

    /// Which form the constructor chose ("cross", "odd", "dense", "hex", "hex-dense").
    const char* form_name() const {
        static const char* names[] = {"cross", "odd", "dense", "hex", "hex-dense"};
        return names[int(form_)];
    }
    bool hexagonal() const { return hex_; }

private:
    static bool any(fp::Mask m, std::size_t n) {
        unsigned char a = 0;
        for (std::size_t i = 0; i < n; ++i) a |= m[i];
        return a != 0;
    }

public:
    /// f and the reduction on n <= chunk_size points. The loops compiled per instruction set (the plugin's
    /// run_f / run_d, each run_body inlined into a function of one Highway target, whose instruction set the
    /// loops then vectorise with); without them, run_body as compiled here.
    template <class T>
    using Runner = void (*)(const Map&, T*, T*, fp::Mask, std::size_t);
    void set_runners(Runner<float> f, Runner<double> d) {
        run_f_ = f;
        run_d_ = d;
    }

    /// One chunk: the map's form, then the reduction; inlined into its callers.
    template <class T>
    [[gnu::always_inline]] inline void run_body(T* x, T* y, fp::Mask m, std::size_t n) const {
        alignas(64) T fx[fp::chunk_size], fy[fp::chunk_size];
        const Coef<T>& k = coef<T>();
        switch (form_) {
        case Form::cross: map_chunk<mask_cross, mask_cross, false>(k, x, y, fx, fy, n); break;
        case Form::odd: map_chunk<mask_odd, mask_odd, false>(k, x, y, fx, fy, n); break;
        case Form::dense: map_chunk<mask_dense, mask_dense, false>(k, x, y, fx, fy, n); break;
        case Form::hex: map_chunk<mask_hex, mask_hex, true>(k, x, y, fx, fy, n); break;
        case Form::hex_dense: map_chunk<mask_dense, mask_dense, true>(k, x, y, fx, fy, n); break;
        }
        switch (reduction_) {
        case Reduction::fmod:
            store(
                x, y, fx, fy, m, n,
                [](T v) __attribute__((always_inline)) { return fp::kernels::reduce_fmod(v); });
            break;
        case Reduction::centred:
            store(
                x, y, fx, fy, m, n,
                [](T v) __attribute__((always_inline)) { return fp::kernels::reduce_centred(v); });
            break;
        case Reduction::floor:
            store(
                x, y, fx, fy, m, n,
                [](T v) __attribute__((always_inline)) { return fp::kernels::reduce_floor(v); });
            break;
        case Reduction::none:
            store(
                x, y, fx, fy, m, n, [](T v) __attribute__((always_inline)) { return v; });
            break;
        case Reduction::hexagonal: store_hexagonal(x, y, fx, fy, m, n); break;
        }
    }

private:
    template <class T>
    void run(T* x, T* y, fp::Mask m, std::size_t n) const {
        if constexpr (sizeof(T) == sizeof(float)) {
            if (run_f_) return run_f_(*this, x, y, m, n);
        } else {
            if (run_d_) return run_d_(*this, x, y, m, n);
        }
        run_body(x, y, m, n);
    }

    enum class Form { cross, odd, dense, hex, hex_dense };

    template <class T>
    const Coef<T>& coef() const {
        if constexpr (sizeof(T) == sizeof(float))
            return f_;
        else
            return d_;
    }

    Coef<float> f_{};
    Coef<double> d_{};
    bool hex_;
    Reduction reduction_;
    Form form_ = Form::dense;
    Runner<float> run_f_ = nullptr;
    Runner<double> run_d_ = nullptr;
};

} // namespace fp_wallpaper
