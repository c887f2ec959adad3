// Shared machinery of the iteration schemes of paper 02 (Mann, Ishikawa, Noor, SP, S, CR, ...).
//
// Every scheme is a few linear combinations of p and of T applied to intermediate points,
// with coefficients that are numbers of the scheme's number system (real, complex, q-system;
// paper 02 Sec. 4). Multiplying by a fixed number c = a + qb is a linear map of the plane,
// the 2x2 matrix M(c) = NumberSystem::multiplier(c) (for the reals c I), and M is linear in c:
// M(1 - c) = I - M(c), M(1 - c - d) = I - M(c) - M(d). So a step turns each parameter into
// its matrix once per batch (the step index n is the same for the whole batch), and the
// point loops are small fixed matrix products over structure-of-arrays chunks: no per-point
// dispatch on the number system. The mappings R and Q of eqs. (18)-(19) are the identity on
// this representation ((x, y) <-> x + qy), so "Q o T o R" is simply T.
//
// A scheme derives from SchemeBase<Derived>, declares its parameter names, and writes
//
//   static constexpr const char* sequences[] = {"alpha", ...};
//   template <class T> void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t n) const;
//
// where c.p holds the chunk's points (in place: the result goes there), c.t(...) applies the
// map to a scratch buffer, and k[i] is the matrix of the i-th declared parameter at this step.
#pragma once

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

// The chunks' point loops, once per instruction set (combine-inl.hpp), dispatched at run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "combine-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include "combine-inl.hpp"

namespace fp_iter {
namespace kernels {
HWY_EXPORT(lin2_f);
HWY_EXPORT(lin2_d);
HWY_EXPORT(lin3_f);
HWY_EXPORT(lin3_d);
HWY_EXPORT(merge_f);
HWY_EXPORT(merge_d);

inline void lin2(const float* k, const float* ux, const float* uy, const float* vx, const float* vy,
                 float* dx, float* dy, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(lin2_f)(k, ux, uy, vx, vy, dx, dy, n);
}
inline void lin2(const double* k, const double* ux, const double* uy, const double* vx, const double* vy,
                 double* dx, double* dy, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(lin2_d)(k, ux, uy, vx, vy, dx, dy, n);
}
inline void lin3(const float* k, const float* ux, const float* uy, const float* vx, const float* vy,
                 const float* wx, const float* wy, float* dx, float* dy, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(lin3_f)(k, ux, uy, vx, vy, wx, wy, dx, dy, n);
}
inline void lin3(const double* k, const double* ux, const double* uy, const double* vx, const double* vy,
                 const double* wx, const double* wy, double* dx, double* dy, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(lin3_d)(k, ux, uy, vx, vy, wx, wy, dx, dy, n);
}
inline void merge(float* x, float* y, const float* px, const float* py, const unsigned char* m,
                  std::size_t n) {
    HWY_DYNAMIC_DISPATCH(merge_f)(x, y, px, py, m, n);
}
inline void merge(double* x, double* y, const double* px, const double* py, const unsigned char* m,
                  std::size_t n) {
    HWY_DYNAMIC_DISPATCH(merge_d)(x, y, px, py, m, n);
}
} // namespace kernels

/// A chunk of up to fp::chunk_size points and scratch buffers, all on the stack.
template <class T>
struct Buf {
    alignas(64) T x[fp::chunk_size];
    alignas(64) T y[fp::chunk_size];
};

template <class T>
struct Chunk {
    // A constructor, not aggregate initialisation: `p` is filled right after, and zeroing its
    // 2 KiB for every batch showed up in profiles.
    Chunk(const fp::Transform& m, std::size_t count) : map(m), n(count) {}

    const fp::Transform& map;
    std::size_t n;
    Buf<T> p; ///< the points; the kernel leaves the new points here

    /// dst <- T(src) (dst may be src).
    void t(Buf<T>& dst, const Buf<T>& src) const {
        if (&dst != &src) copy(dst, src);
        map.apply(fp::Points<T>{dst.x, dst.y, n}, nullptr);
    }
    void copy(Buf<T>& dst, const Buf<T>& src) const {
        std::copy(src.x, src.x + n, dst.x);
        std::copy(src.y, src.y + n, dst.y);
    }
    /// dst <- A u + B v (matrices acting on points; dst may alias u or v).
    void lin(Buf<T>& dst, const fp::Mat2& A, const Buf<T>& u, const fp::Mat2& B, const Buf<T>& v) const {
        const T k[8] = {T(A.a), T(A.b), T(A.c), T(A.d), T(B.a), T(B.b), T(B.c), T(B.d)};
        kernels::lin2(k, u.x, u.y, v.x, v.y, dst.x, dst.y, n);
    }
    /// dst <- A u + B v + C w.
    void lin(Buf<T>& dst, const fp::Mat2& A, const Buf<T>& u, const fp::Mat2& B, const Buf<T>& v,
             const fp::Mat2& C, const Buf<T>& w) const {
        const T k[12] = {T(A.a), T(A.b), T(A.c), T(A.d), T(B.a), T(B.b),
                         T(B.c), T(B.d), T(C.a), T(C.b), T(C.c), T(C.d)};
        kernels::lin3(k, u.x, u.y, v.x, v.y, w.x, w.y, dst.x, dst.y, n);
    }
};

constexpr fp::Mat2 identity{1, 0, 0, 1};
constexpr fp::Mat2 zero{0, 0, 0, 0};

/// The matrices of the declared parameters at one step.
using Coefs = std::array<fp::Mat2, 8>;

/// `numbers` is every scheme's first parameter; the schemes list it in their schema with this.
constexpr fp::ParamSpec numbers_param =
    fp::param::object("numbers", fp::Kind::NumberSystem,
                      "the numbers the iteration computes in (paper 02 Sec. 4): real, complex or q-system")
        .def("{type: real}");

/// A scheme's parameter: a sequence over n of numbers of its number system.
constexpr fp::ParamSpec seq(const char* name, const char* def, const char* doc) {
    return fp::param::sequence(name, doc).def(def);
}

inline std::string format_number(fp::Vec2 v) {
    auto f = [](double d) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", d);
        return std::string(buf);
    };
    if (v.y == 0) return f(v.x);
    return f(v.x) + (v.y < 0 ? "-" : "+") + f(std::fabs(v.y)) + "q";
}

template <class D>
class SchemeBase : public fp::IterationScheme {
public:
    /// Reads `numbers` and the sequences named in D::sequences (in that order: k[0], k[1], ...).
    explicit SchemeBase(const fp::ParamBag& p) : numbers_(p.object<fp::NumberSystem>("numbers")) {
        static_assert(std::size(D::sequences) <= std::tuple_size_v<Coefs>,
                      "Coefs holds at most 8 parameters");
        const bool real = numbers_->is_real();
        for (const char* name : D::sequences) {
            seqs_.push_back(p.sequence(name).resolve(real));
            if (real)
                for (fp::Vec2 v : seqs_.back().values)
                    if (v.y != 0)
                        throw fp::ParamError(name,
                                             format_number(v) +
                                                 " is a q-system number, but the scheme computes in the real "
                                                 "numbers (set numbers: {type: q-system, A: ..., B: ...})");
        }
    }

    void step(const fp::Transform& t, fp::Points<float> p, fp::Mask m, std::uint64_t n) const override {
        run(t, p, m, n);
    }
    void step(const fp::Transform& t, fp::Points<double> p, fp::Mask m, std::uint64_t n) const override {
        run(t, p, m, n);
    }

protected:
    /// The matrix of declared parameter i at step n.
    fp::Mat2 coef(std::size_t i, std::uint64_t n) const { return numbers_->multiplier(seqs_[i].at(n)); }
    const fp::NumberSystem& numbers() const { return *numbers_; }

private:
    template <class T>
    void run(const fp::Transform& t, fp::Points<T> p, fp::Mask mask, std::uint64_t n) const {
        Coefs k{};
        for (std::size_t i = 0; i < seqs_.size(); ++i) k[i] = coef(i, n);
        const D& self = static_cast<const D&>(*this);
        for (std::size_t begin = 0; begin < p.n; begin += fp::chunk_size) {
            Chunk<T> c(t, std::min(fp::chunk_size, p.n - begin));
            T* x = p.x + begin;
            T* y = p.y + begin;
            std::copy(x, x + c.n, c.p.x);
            std::copy(y, y + c.n, c.p.y);
            self.template kernel<T>(c, k, n);
            kernels::merge(x, y, c.p.x, c.p.y, mask ? mask + begin : nullptr, c.n);
        }
    }

    std::shared_ptr<const fp::NumberSystem> numbers_;
    std::vector<fp::Sequence> seqs_;
};

} // namespace fp_iter
