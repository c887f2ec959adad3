// SchemeBase: write an iteration scheme of paper 02 (Mann, Ishikawa, Noor, SP, S, CR, ...) as
// a few linear combinations of points, in any number system; every built-in scheme but picard
// and switching is one (plugins/iterations/), and docs/writing-a-scheme.md is the guide.
//
// Every such scheme is a few linear combinations of p and of T applied to intermediate points,
// with coefficients that are numbers of the scheme's number system (real, complex, q-system;
// paper 02 Sec. 4). Multiplying by a fixed number c = a + qb is a linear map of the plane,
// the 2x2 matrix M(c) = NumberSystem::multiplier(c) (for the reals c I), and M is linear in c:
// M(1 - c) = I - M(c), M(1 - c - d) = I - M(c) - M(d). So a step turns each parameter into
// its matrix once per batch (the step index n is the same for the whole batch), and the
// point loops are small fixed matrix products over structure-of-arrays chunks: no per-point
// dispatch on the number system. The mappings R and Q of eqs. (18)-(19) are the identity on
// this representation ((x, y) <-> x + qy), so "Q o T o R" is simply T.
//
// A scheme derives from fp::SchemeBase<Derived>, declares its parameters once, as the public
// static member `params` (a fp::scheme::seq per coefficient, plus any other parameter it reads
// itself in a constructor of its own), and writes one step for a chunk of points:
//
//   struct Mann final : fp::SchemeBase<Mann> {
//       static constexpr fp::ParamSpec params[] = {
//           fp::scheme::seq("alpha", "0.5", "alpha_n: weight of T(p_n)"),
//       };
//
//       template <class T>
//       void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t n) const {
//           const fp::Mat2& alpha = k["alpha"]; // the matrix of alpha_n at this step
//           Buf<T> tp;
//           c.t(tp, c.p);                                // T(p)
//           c.lin(c.p, identity - alpha, c.p, alpha, tp); // p <- (1 - alpha) p + alpha T(p)
//       }
//   };
//   FIXPOINT_PLUGIN(fp::scheme::describe<Mann>("mann", "..."))
//
// fp::scheme::describe publishes `numbers` (fp::scheme::numbers_param) before `params` (a
// scheme written before it lists numbers_param itself, and declares `using
// SchemeBase::SchemeBase;`: both still work). SchemeBase reads `numbers` and every sequence
// parameter of `params` (refusing q-numbers when
// the scheme computes in the reals), and per batch turns each sequence's value at step n into
// its matrix. k["alpha"] finds the matrix by name at compile time: a name that `params` does
// not declare as a sequence does not compile, and a bare index is refused. c.p holds the
// chunk's points (in place: the result goes there), c.t(dst, src) applies the map, c.lin(...)
// forms linear combinations with the matrices; the loops run on the best instruction set of
// the CPU (fixpoint/scheme-inl.hpp, dispatched at run time) and give the same bits on all.
//
// SchemeBase also records the kernel as a SchemeProgram (IterationScheme::program): run on a
// chunk of no points, c.t, c.copy and c.lin write instructions instead of computing, and a
// renderer runs the program in its own vectorised loop (the chaos game's fused step). So a
// kernel combines points only through those three; one that reads or writes the points itself
// overrides program() to return false (the conformance suite finds one that does not).
//
// Including this header compiles those loops into the plugin (Highway's foreach_target), so
// include it once per plugin, from the scheme's .cpp.
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/errors.hpp>
#include <fixpoint/iteration.hpp>
#include <fixpoint/number_system.hpp>
#include <fixpoint/params.hpp>
#include <fixpoint/plugin.hpp>
#include <fixpoint/scheme_program.hpp>
#include <fixpoint/transform.hpp>
#include <fixpoint/types.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

// The chunks' point loops, once per instruction set (scheme-inl.hpp), dispatched at run time.
// Named by its path on the SDK's include path, in the source tree and installed alike.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "fixpoint/scheme-inl.hpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include <fixpoint/scheme-inl.hpp>

namespace fp {
template <class D>
class SchemeBase;
}

namespace fp::scheme {
namespace detail {
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

/// How many of `params` are sequences (the coefficients of a scheme).
template <std::size_t N>
consteval std::size_t sequence_count(const ParamSpec (&params)[N]) {
    std::size_t count = 0;
    for (const ParamSpec& s : params) count += s.type == ParamType::Sequence;
    return count;
}

// Not constexpr on purpose: reaching it at compile time is the error message.
inline void no_sequence_parameter_of_this_name_in_params() {}

/// The position of sequence `name` among the sequences of `params`.
template <std::size_t N>
consteval std::size_t sequence_index(const ParamSpec (&params)[N], std::string_view name) {
    std::size_t index = 0;
    for (const ParamSpec& s : params) {
        if (s.type != ParamType::Sequence) continue;
        if (std::string_view(s.name) == name) return index;
        ++index;
    }
    no_sequence_parameter_of_this_name_in_params();
    return index;
}

/// Writes a kernel's operations into a SchemeProgram instead of running them (SchemeBase::
/// program): each buffer the kernel names (c.p first) becomes a register, by its address.
class Recorder {
public:
    Recorder(const void* p, SchemeProgram& out) : out_(out) {
        out_.size = 0;
        out_.regs = 1;
        reg_[0] = p;
    }
    void add(SchemeProgram::Op op, const void* dst, const void* u, const void* v = nullptr,
             const void* w = nullptr, const double* k = nullptr, std::size_t nk = 0) {
        if (out_.size == SchemeProgram::max_instrs) {
            overflow = true;
            return;
        }
        SchemeProgram::Instr& in = out_.code[out_.size++];
        in.op = op;
        in.u = reg(u);
        in.v = v ? reg(v) : 0;
        in.w = w ? reg(w) : 0;
        in.dst = reg(dst);
        // (Only the coefficients the instruction has: zeroing the rest took a third of a
        // recording, and nothing reads them.)
        if (nk == 8)
            std::memcpy(in.k, k, 8 * sizeof(double));
        else if (nk == 12)
            std::memcpy(in.k, k, 12 * sizeof(double));
    }
    bool overflow = false; ///< more instructions or registers than a program holds

private:
    std::uint8_t reg(const void* b) {
        for (std::uint32_t i = 0; i < out_.regs; ++i)
            if (reg_[i] == b) return std::uint8_t(i);
        if (out_.regs == SchemeProgram::max_regs) {
            overflow = true;
            return 0;
        }
        reg_[out_.regs] = b;
        return std::uint8_t(out_.regs++);
    }
    SchemeProgram& out_;
    const void* reg_[SchemeProgram::max_regs] = {};
};

/// True when `params` declares `numbers`, an object of kind number-system.
template <std::size_t N>
consteval bool declares_numbers(const ParamSpec (&params)[N]) {
    for (const ParamSpec& s : params)
        if (std::string_view(s.name) == "numbers")
            return s.type == ParamType::Object && s.kind == Kind::NumberSystem;
    return false;
}
} // namespace detail

/// A chunk of up to fp::chunk_size points, or scratch space for one, on the stack.
template <class T>
struct Buf {
    alignas(64) T x[chunk_size];
    alignas(64) T y[chunk_size];
};

/// The points of one chunk and the operations a scheme's kernel combines them with.
template <class T>
struct Chunk {
    // A constructor, not aggregate initialisation: `p` is filled right after, and zeroing its
    // 2 KiB for every batch showed up in profiles.
    Chunk(const Transform& m, std::size_t count) : map(m), n(count) {}

    const Transform& map;               ///< T
    std::size_t n;                      ///< the points in this chunk (at most chunk_size)
    Buf<T> p;                           ///< the points; the kernel leaves the new points here
    const std::uint64_t* key = nullptr; ///< the points' random keys (fp::Points::key), or null

    /// dst <- T(src) (dst may be src).
    void t(Buf<T>& dst, const Buf<T>& src) const {
        if (rec_) return rec_->add(SchemeProgram::Op::map, &dst, &src);
        if (&dst != &src) copy(dst, src);
        // Each application of T in the step draws its own randoms (salt), from the chain's keys.
        map.apply(Points<T>{dst.x, dst.y, n, key, salt_++}, nullptr);
    }
    /// dst <- src.
    void copy(Buf<T>& dst, const Buf<T>& src) const {
        if (rec_) return rec_->add(SchemeProgram::Op::copy, &dst, &src);
        std::copy(src.x, src.x + n, dst.x);
        std::copy(src.y, src.y + n, dst.y);
    }
    /// dst <- A u + B v (matrices acting on points; dst may alias u or v).
    void lin(Buf<T>& dst, const Mat2& A, const Buf<T>& u, const Mat2& B, const Buf<T>& v) const {
        if (rec_) {
            const double r[8] = {A.a, A.b, A.c, A.d, B.a, B.b, B.c, B.d};
            return rec_->add(SchemeProgram::Op::lin2, &dst, &u, &v, nullptr, r, 8);
        }
        const T k[8] = {T(A.a), T(A.b), T(A.c), T(A.d), T(B.a), T(B.b), T(B.c), T(B.d)};
        detail::lin2(k, u.x, u.y, v.x, v.y, dst.x, dst.y, n);
    }
    /// dst <- A u + B v + C w (dst may alias any of them).
    void lin(Buf<T>& dst, const Mat2& A, const Buf<T>& u, const Mat2& B, const Buf<T>& v, const Mat2& C,
             const Buf<T>& w) const {
        if (rec_) {
            const double r[12] = {A.a, A.b, A.c, A.d, B.a, B.b, B.c, B.d, C.a, C.b, C.c, C.d};
            return rec_->add(SchemeProgram::Op::lin3, &dst, &u, &v, &w, r, 12);
        }
        const T k[12] = {T(A.a), T(A.b), T(A.c), T(A.d), T(B.a), T(B.b),
                         T(B.c), T(B.d), T(C.a), T(C.b), T(C.c), T(C.d)};
        detail::lin3(k, u.x, u.y, v.x, v.y, w.x, w.y, dst.x, dst.y, n);
    }

private:
    template <class D>
    friend class fp::SchemeBase;
    detail::Recorder* rec_ = nullptr; ///< set while SchemeBase::program records the kernel
    mutable std::uint32_t salt_ = 0;  ///< applications of T so far in this step
};

/// The matrix of the number 1 (M(1) = I in every number system) and of 0.
constexpr Mat2 identity{1, 0, 0, 1};
constexpr Mat2 zero{0, 0, 0, 0};

/// `numbers`, the number system a scheme computes in: SchemeBase reads it. fp::scheme::describe
/// puts it first in the scheme's parameters unless the scheme lists it itself.
constexpr ParamSpec numbers_param =
    param::object("numbers", Kind::NumberSystem,
                  "the numbers the iteration computes in (paper 02 Sec. 4): real, complex or q-system")
        .def("{type: real}");

/// A scheme's coefficient: a sequence over n of numbers of its number system, with its
/// default (YAML: "0.5", "0.3+0.5q", "[0.7, 0.9]").
constexpr ParamSpec seq(const char* name, const char* def, const char* doc) {
    return param::sequence(name, doc).def(def);
}

/// A q-system number a + qb as text: "0.5", "0.5+0.3q".
inline std::string format_number(Vec2 v) {
    auto f = [](double d) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", d);
        return std::string(buf);
    };
    if (v.y == 0) return f(v.x);
    return f(v.x) + (v.y < 0 ? "-" : "+") + f(std::fabs(v.y)) + "q";
}

/// Coefficient `s` of a scheme (a sequence parameter) as the scheme computes with it, in the
/// reals or not: a bare pair [x, y] is resolved (Sequence::resolve), and a q-number is refused
/// where the scheme computes in the reals or the coefficient declares a range (a + qb has no
/// order; the host checks each value written, here only a bare pair read as x + qy can still
/// have a q part). SchemeBase and python-scheme read their coefficients through it.
inline Sequence read_coefficient(const ParamSpec& s, const ParamBag& p, bool real) {
    Sequence seq = p.sequence(s.name).resolve(real);
    if (std::isfinite(s.lo) || std::isfinite(s.hi))
        for (Vec2 v : seq.values)
            if (v.y != 0)
                throw ParamError(s.name,
                                 "[" + format_number(Vec2{v.x, 0}) + ", " + format_number(Vec2{v.y, 0}) +
                                     "] is the number " + format_number(v) +
                                     " here, and a coefficient with a declared range is real (write the "
                                     "periodic list with its period twice: [x, y, x, y])");
    if (real)
        for (Vec2 v : seq.values)
            if (v.y != 0)
                throw ParamError(s.name,
                                 format_number(v) +
                                     " is a q-system number, but the scheme computes in the real numbers "
                                     "(set numbers: {type: q-system, A: ..., B: ...})");
    return seq;
}

} // namespace fp::scheme

namespace fp {

/// The base of a scheme D written as linear combinations (see the top of this file). D has
///   static constexpr ParamSpec params[];  // seq(...) per coefficient, others (numbers implied)
///   template <class T> void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t n) const;
template <class D>
class SchemeBase : public IterationScheme {
public:
    template <class T>
    using Chunk = scheme::Chunk<T>;
    template <class T>
    using Buf = scheme::Buf<T>;
    static constexpr Mat2 identity = scheme::identity;
    static constexpr Mat2 zero = scheme::zero;

    /// The matrices of D's sequence parameters at one step, found by name: k["alpha"].
    class Coefs {
    public:
        /// A sequence parameter of D, named by a string literal and looked up when compiling.
        class Name {
        public:
            consteval Name(const char* name) : index_(scheme::detail::sequence_index(D::params, name)) {}
            /// Coefficients are named, not numbered: k["alpha"], not k[0].
            template <std::integral I>
            Name(I) = delete;

        private:
            friend class Coefs;
            std::size_t index_;
        };

        const Mat2& operator[](Name name) const { return m_[name.index_]; }

    private:
        friend class SchemeBase;
        std::array<Mat2, scheme::detail::sequence_count(D::params)> m_;
    };

    /// Reads `numbers` and every sequence parameter of D::params, in their order.
    explicit SchemeBase(const ParamBag& p) { read(p); }

    /// Builds D for fp::scheme::describe: by D's constructor from a ParamBag where it has one,
    /// else default-built (a scheme that declares no constructor) and read here.
    static Object* create(const ParamBag& p) {
        if constexpr (std::is_constructible_v<D, const ParamBag&>) {
            return new D(p);
        } else {
            auto d = std::make_unique<D>();
            d->read(p);
            return d.release();
        }
    }

    void step(const Transform& t, Points<float> p, Mask m, std::uint64_t n) const override {
        run(t, p, m, n);
    }
    void step(const Transform& t, Points<double> p, Mask m, std::uint64_t n) const override {
        run(t, p, m, n);
    }
    /// The kernel's operations at step n on map t, recorded rather than run (on a chunk of no
    /// points): the program the kernel computes, provided it combines points only through
    /// c.t, c.copy and c.lin. A kernel that reads or writes the points itself overrides this to
    /// return false (the conformance suite finds one that does not).
    bool program(const Transform& t, std::uint64_t n, bool dbl, SchemeProgram& out) const override {
        return dbl ? record<double>(t, n, out) : record<float>(t, n, out);
    }

protected:
    /// For a scheme that declares no constructor (fp::scheme::describe reads its parameters).
    SchemeBase() = default;

    /// The matrices of the sequence parameters at step n.
    Coefs coefs(std::uint64_t n) const {
        Coefs k;
        for (std::size_t i = 0; i < k.m_.size(); ++i) k.m_[i] = numbers_->multiplier(seqs_[i].at(n));
        return k;
    }
    const NumberSystem& numbers() const { return *numbers_; }

private:
    void read(const ParamBag& p) {
        numbers_ = p.object<NumberSystem>("numbers");
        for (const ParamSpec& s : D::params)
            if (s.type == ParamType::Sequence)
                seqs_.push_back(scheme::read_coefficient(s, p, numbers_->is_real()));
    }

    template <class T>
    bool record(const Transform& t, std::uint64_t n, SchemeProgram& out) const {
        scheme::Chunk<T> c(t, 0);
        scheme::detail::Recorder r(&c.p, out);
        c.rec_ = &r;
        static_cast<const D&>(*this).template kernel<T>(c, coefs(n), n);
        return !r.overflow;
    }

    template <class T>
    void run(const Transform& t, Points<T> p, Mask mask, std::uint64_t n) const {
        const Coefs k = coefs(n);
        const D& self = static_cast<const D&>(*this);
        for (std::size_t begin = 0; begin < p.n; begin += chunk_size) {
            scheme::Chunk<T> c(t, std::min(chunk_size, p.n - begin));
            c.key = p.key ? p.key + begin : nullptr;
            T* x = p.x + begin;
            T* y = p.y + begin;
            std::copy(x, x + c.n, c.p.x);
            std::copy(y, y + c.n, c.p.y);
            self.template kernel<T>(c, k, n);
            scheme::detail::merge(x, y, c.p.x, c.p.y, mask ? mask + begin : nullptr, c.n);
        }
    }

    std::shared_ptr<const NumberSystem> numbers_;
    std::vector<Sequence> seqs_;
};

} // namespace fp

namespace fp::scheme {

/// Scheme D's parameters as the host sees them: `numbers` (numbers_param) first unless D::params
/// lists it, then D::params in their order.
template <class D>
inline constexpr auto all_params = [] {
    constexpr bool listed = detail::declares_numbers(D::params);
    std::array<ParamSpec, std::size(D::params) + (listed ? 0 : 1)> a{};
    std::size_t i = 0;
    if (!listed) a[i++] = numbers_param;
    for (const ParamSpec& s : D::params) a[i++] = s;
    return a;
}();

/// The descriptor of scheme D (an fp::SchemeBase<D>): kind, name, summary and all_params<D>.
/// D is built from its parameters by its own constructor from a ParamBag where it declares one
/// (`using SchemeBase::SchemeBase;`, or one that reads more), else default-built and read by
/// SchemeBase:
///   FIXPOINT_PLUGIN(fp::scheme::describe<Mann>("mann", "the Mann iteration ..."))
template <class D>
constexpr PluginDescriptor describe(const char* name, const char* summary) {
    PluginDescriptor d;
    d.name = name;
    d.kind = Kind::IterationScheme;
    d.summary = summary;
    d.params = all_params<D>.data();
    d.n_params = std::uint32_t(all_params<D>.size());
    d.create = &SchemeBase<D>::create;
    return d;
}

} // namespace fp::scheme
