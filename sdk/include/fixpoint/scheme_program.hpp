// SchemeProgram: one step of an iteration scheme written out as a short straight-line program
// over a few point registers, for renderers that run the step inside their own vectorised loop
// (chaos-game's fused step) instead of calling IterationScheme::step on grouped batches.
//
// Register 0 holds the point p on entry and the new point on exit; the others are scratch. The
// instructions, in order, each over every point:
//   map  : r[dst] <- T(r[u])
//   copy : r[dst] <- r[u]
//   lin2 : r[dst] <- A r[u] + B r[v]           k = {A.a, A.b, A.c, A.d, B.a, B.b, B.c, B.d}
//   lin3 : r[dst] <- A r[u] + B r[v] + C r[w]  k = {A, B, C} likewise
// with a linear combination computed, in the precision of the points (each coefficient first
// rounded to it), exactly as fixpoint/scheme-inl.hpp's lin2_t and lin3_t do:
//   x' = (A.a x_u + A.b y_u) + (B.a x_v + B.b y_v) [+ (C.a x_w + C.b y_w)], y' likewise.
// run_program below is that meaning in plain code: the conformance suite compares it with the
// scheme's step(), bit for bit, and a renderer's vectorised form computes the same operations.
//
// fp::SchemeBase records a scheme's program from its kernel (scheme.hpp); other schemes give
// none (IterationScheme::program returns false) and renderers call step() for them.
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/transform.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace fp {

struct SchemeProgram {
    enum class Op : std::uint8_t { map, copy, lin2, lin3 };
    /// An instruction; v is used by lin2 and lin3, w by lin3, and k holds coefficients(op)
    /// values (the rest are not set). (No initialisers: a renderer records a program at every
    /// step, and zeroing the array each time cost more than the recording; only the first
    /// `size` instructions are meaningful.)
    struct Instr {
        Op op;
        std::uint8_t dst, u, v, w;
        double k[12];
    };
    static constexpr std::size_t coefficients(Op op) { return op == Op::lin2 ? 8 : op == Op::lin3 ? 12 : 0; }
    /// Limits that keep a program on the stack and in a renderer's registers; a scheme whose
    /// step needs more (Schu composing T many times) has no program at that step.
    static constexpr std::size_t max_instrs = 16;
    static constexpr std::size_t max_regs = 8;

    std::array<Instr, max_instrs> code;
    std::uint32_t size = 0; ///< instructions used
    std::uint32_t regs = 1; ///< registers used (register 0: the point)

    /// The same instructions with the same coefficients, bit for bit (a renderer runs one
    /// program for every map of a step only where their programs are equal).
    bool same_as(const SchemeProgram& o) const {
        if (size != o.size || regs != o.regs) return false;
        for (std::uint32_t i = 0; i < size; ++i) {
            const Instr &a = code[i], &b = o.code[i];
            if (a.op != b.op || a.dst != b.dst || a.u != b.u) return false;
            if (a.op != Op::map && a.op != Op::copy && a.v != b.v) return false;
            if (a.op == Op::lin3 && a.w != b.w) return false;
            if (std::memcmp(a.k, b.k, coefficients(a.op) * sizeof(double)) != 0) return false;
        }
        return true;
    }
};

/// The meaning of a program (see the top of this file): p <- program(p), the map being t.
template <class T>
void run_program(const SchemeProgram& prog, const Transform& t, Points<T> p) {
    using Op = SchemeProgram::Op;
    std::vector<T> rx(prog.regs * p.n), ry(prog.regs * p.n);
    std::copy(p.x, p.x + p.n, rx.begin());
    std::copy(p.y, p.y + p.n, ry.begin());
    const auto X = [&](std::uint8_t r) { return rx.data() + r * p.n; };
    const auto Y = [&](std::uint8_t r) { return ry.data() + r * p.n; };
    for (std::uint32_t s = 0; s < prog.size; ++s) {
        const SchemeProgram::Instr& in = prog.code[s];
        T k[12] = {};
        for (std::size_t j = 0; j < SchemeProgram::coefficients(in.op); ++j) k[j] = T(in.k[j]);
        for (std::size_t i = 0; i < p.n; ++i) {
            const T x0 = X(in.u)[i], y0 = Y(in.u)[i];
            if (in.op == Op::copy || in.op == Op::map) {
                X(in.dst)[i] = x0, Y(in.dst)[i] = y0;
                continue;
            }
            const T x1 = X(in.v)[i], y1 = Y(in.v)[i];
            T nx = (k[0] * x0 + k[1] * y0) + (k[4] * x1 + k[5] * y1);
            T ny = (k[2] * x0 + k[3] * y0) + (k[6] * x1 + k[7] * y1);
            if (in.op == Op::lin3) {
                const T x2 = X(in.w)[i], y2 = Y(in.w)[i];
                nx = nx + (k[8] * x2 + k[9] * y2);
                ny = ny + (k[10] * x2 + k[11] * y2);
            }
            X(in.dst)[i] = nx, Y(in.dst)[i] = ny;
        }
        if (in.op == Op::map) t.apply(Points<T>{X(in.dst), Y(in.dst), p.n}, nullptr);
    }
    std::copy(rx.begin(), rx.begin() + p.n, p.x);
    std::copy(ry.begin(), ry.begin() + p.n, p.y);
}

} // namespace fp
