// chaos-game's chains: a block's chains as one structure of arrays (Chains: everything a chain
// carries from one step to the next, and what a checkpoint records of it), the per-worker block
// state around it (Scratch), pcg32 on its arrays, the partition of a render's chains into blocks,
// and the steady runs that skip the bookkeeping which cannot change. chaos-game/block.cpp runs a
// block's steps on them.
#pragma once

#include "buffers.hpp"
#include "kernels.hpp"

#include <fixpoint/check.hpp>
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

// The scalar loops over a block's arrays have no dependences between iterations: tell GCC,
// so that they vectorise without run-time alias checks (GCC ignores __restrict on locals).
#if defined(__GNUC__) && !defined(__clang__)
#define FP_IVDEP _Pragma("GCC ivdep")
#else
#define FP_IVDEP
#endif

namespace fp_chaos {

using std::size_t;
using std::uint32_t;
using std::uint64_t;

/// Chains per block at the end of a render on several workers (see block_spans).
constexpr size_t tail_block_size = 128;
/// Steps between polls of ctx.cancelled() and progress reports (about 1 ms of work).
constexpr uint64_t poll_steps = 64;
/// Blocks of at most this many chains run lean when they can (one or a few orbits: the
/// papers' single orbit; see chaos-game/block.cpp).
constexpr size_t lean_chains = lean_max;
/// Candidates drawn for a start point outside every set before the last one is taken anyway.
constexpr unsigned start_tries = 32;
/// Restarts in a row without a plotted point after which a chain is retired.
constexpr uint32_t max_idle_restarts = 100;
/// Added to the seed for the chains' random start colours (fp::PixelRule::last): the stream
/// fp::chain_stream(seed + salt, chain), not the one the chain draws its maps from.
constexpr uint64_t colour_stream_salt = 0x636f6c6f7572ull; // ASCII "colour"

/// Chains are grouped by map with compress stores into one staging segment per map (up to
/// this many maps); beyond, by a scalar counting sort into contiguous segments. Both give the
/// same points in the same order.
constexpr size_t max_compress_maps = 16;
/// A map's staging segment: room for a whole block plus one full vector of the widest target
/// stored past its end (64 lanes: SVE-2048).
constexpr size_t seg_stride = block_size + 64;

// ---------------------------------------------------------------- pcg32, structure of arrays
// fp::Rng is pcg32 (setseq XSH-RR 64/32, output of the previous state). The same generator on
// plain arrays, so that a block's draws vectorise; chain_stream(seed, i) seeds it.
constexpr uint64_t pcg_mult = 6364136223846793005ull;

inline void pcg_seed(uint64_t seed, uint64_t chain, uint64_t& state, uint64_t& inc) {
    inc = (chain << 1) | 1u;
    state = (fp::mix64(seed) + inc) * pcg_mult + inc;
}

inline uint32_t pcg_next(uint64_t& state, uint64_t inc) {
    const uint64_t old = state;
    state = old * pcg_mult + inc;
    const auto x = uint32_t(((old >> 18) ^ old) >> 27);
    const auto rot = uint32_t(old >> 59);
    return (x >> rot) | (x << ((32u - rot) & 31u));
}

/// Advances each of n streams by `steps` outputs at once: the states `steps` calls of pcg_next
/// would leave. (Jump-ahead for an LCG, F. Brown 1994: state * A + inc * G with A = mult^steps
/// and G = 1 + mult + ... + mult^(steps - 1), modulo 2^64, by squaring.) A steady run of one
/// map without the rules draws nothing from its streams, which then move on once at its end.
inline void pcg_jump(uint64_t* rs, const uint64_t* ri, size_t n, uint64_t steps) {
    uint64_t A = 1, G = 0, mult = pcg_mult, plus = 1;
    for (uint64_t d = steps; d > 0; d >>= 1) {
        if (d & 1) A *= mult, G = G * mult + plus;
        plus *= mult + 1;
        mult *= mult;
    }
    for (size_t i = 0; i < n; ++i) rs[i] = rs[i] * A + ri[i] * G;
}

/// fp::uniform_double on the SoA stream: uniform in [0, 1) with 53 random bits.
inline double pcg_uniform(uint64_t& state, uint64_t inc) {
    const uint64_t hi = pcg_next(state, inc) >> 5, lo = pcg_next(state, inc) >> 6;
    return double((hi << 26) | lo) * 0x1.0p-53;
}

/// The points chain `chain` plots of `points` over `chains` chains.
inline uint64_t points_of(uint64_t chain, uint64_t points, uint64_t chains) {
    return points / chains + (chain < points % chains ? 1 : 0);
}

// ---------------------------------------------------------------- bookkeeping and steady runs
// The bookkeeping of a step (book-inl.hpp's bookkeep_t, or the fused step in registers): for each
// chain, whether it moved, whether its point is finite (else: a bad value and a restart), whether
// it plots (moved, finite, past `skip`); its age, previous map, idle count, points left and
// activity; its bin (the last one, outside the image, when not plotted or outside the view: x in
// [xmin, xmax), y in (ymin, ymax], y = ymax the top row, indices clamped in case the products
// round up to width or height); and its colour packed {1, r, g, b} in 16 bits each (round(c *
// colour_scale), c clamped to [0, 1], NaN to 0).
//
// A steady run of the fused step (fused_t with Steady) leaves age, idle, points left and activity
// alone while they cannot change: every active chain past its skip and far from its last point.
// They are settled at the run's end (Chains::settle_steady).

/// Whether a block may run steady: `budget` steps when every active chain is past its skip,
/// fewer than the fewest points any of them has left (so that none runs out during the run); 0
/// otherwise. `wait`: steps before asking again can help, when some chain is still young (its age
/// grows by at most one a step), so that a block full of restarting chains is not scanned at
/// every step.
struct SteadyCheck {
    uint64_t budget = 0, wait = 0;
};

// ---------------------------------------------------------------- a block's chains
/// One chain's state between two steps, as a checkpoint writes it. 72 bytes, no padding (written
/// as it is).
struct ChainRec {
    double x, y;   ///< exact for float chains too
    uint64_t rs;   ///< pcg32 state (the increment follows from the chain)
    uint64_t left; ///< points left
    uint64_t step; ///< the step it runs next (the iteration scheme's n)
    uint32_t chain, prev, age, idle, active;
    float cr, cg, cb;
    float ci; ///< the palette index (Colourer::palette_index), or colour stealing's u; else 0
    float cv; ///< colour stealing's v; else 0 (the record's size a multiple of 8)
};
static_assert(sizeof(ChainRec) == 80, "ChainRec is written as it is");

/// A chain's colour at its start: the maps' mean colour, or (paper 02's Algorithm 2, line 4: "c =
/// random colour") one drawn from fp::chain_stream(seed + colour_stream_salt, chain), which its
/// draws never touch.
struct StartColour {
    bool random = false;
    uint64_t seed = 0;
    float r = 0, g = 0, b = 0;
    /// A palette index too (Colourer::palette_index): drawn from the same stream, after the
    /// colours where they are random (flam3 starts each chain at a random index).
    bool index = false;
    /// Colour stealing (picture.hpp): the colour point starts at (1/2, 1/2), drawn from no stream.
    bool steal = false;
};

/// A block's chains, lane i the i-th: the one declaration of a chain's state. The kernels see it
/// through DrawArgs and BookArgs (Scratch::draw_args, book_args), a checkpoint as ChainRec.
template <class T>
struct Chains {
    Buf<T> x, y;            ///< the point
    Buf<uint64_t> rs, ri;   ///< pcg32 state and increment: the stream fp::chain_stream(seed, chain)
    Buf<uint64_t> left;     ///< points left to plot
    Buf<uint32_t> prev;     ///< the previous map (k: none)
    Buf<uint32_t> age;      ///< steps since the start or the last restart (counted up to skip)
    Buf<uint32_t> idle;     ///< restarts in a row without a plotted point
    Buf<uint32_t> active;   ///< 0 / 1; 0 past the block's last chain (the kernels read whole vectors)
    Buf<float> cr, cg, cb;  ///< the colour
    Buf<float> ci;          ///< the palette index (Colourer::palette_index), or colour stealing's u
    Buf<float> cv;          ///< colour stealing's v (picture.hpp)
    Buf<uint32_t> chain;    ///< the chain in this lane
    Buf<unsigned char> fin; ///< a checkpointed render: the lane's final state is recorded

    Chains() {
        const size_t B = block_size;
        x.alloc(B), y.alloc(B), rs.alloc(B), ri.alloc(B), left.alloc(B);
        prev.alloc(B), age.alloc(B), idle.alloc(B), cr.alloc(B), cg.alloc(B), cb.alloc(B), ci.alloc(B);
        cv.alloc(B), active.alloc(B);
        chain.alloc(B), fin.alloc(B);
    }

    /// Lane i as a checkpoint records it, `step` the step it runs next.
    ChainRec record(size_t i, uint64_t step) const {
        return ChainRec{double(x.get()[i]), double(y.get()[i]), rs.get()[i],  left.get()[i], step,
                        chain.get()[i],     prev.get()[i],      age.get()[i], idle.get()[i], active.get()[i],
                        cr.get()[i],        cg.get()[i],        cb.get()[i],  ci.get()[i],   cv.get()[i]};
    }
    /// Lane i continues chain c.chain where a checkpoint left it (its increment follows from the
    /// chain); a lane that finished before the checkpoint has its final state recorded already.
    void restore(size_t i, const ChainRec& c) {
        chain.get()[i] = c.chain;
        rs.get()[i] = c.rs;
        ri.get()[i] = (uint64_t(c.chain) << 1) | 1u;
        left.get()[i] = c.left;
        active.get()[i] = c.active;
        prev.get()[i] = c.prev;
        age.get()[i] = c.age;
        idle.get()[i] = c.idle;
        cr.get()[i] = c.cr, cg.get()[i] = c.cg, cb.get()[i] = c.cb;
        ci.get()[i] = c.ci;
        cv.get()[i] = c.cv;
        x.get()[i] = T(c.x);
        y.get()[i] = T(c.y);
        fin.get()[i] = c.active ? 0 : 1;
    }
    /// Lane i starts chain `ch` at step 0 with `points` points to plot, no previous map (k), its
    /// start colour, and the point (0, 0) until its start point is drawn.
    void fresh(size_t i, uint64_t ch, uint64_t seed, uint64_t points, uint32_t k, const StartColour& c) {
        chain.get()[i] = uint32_t(ch);
        fin.get()[i] = 0;
        pcg_seed(seed, ch, rs.get()[i], ri.get()[i]);
        left.get()[i] = points;
        active.get()[i] = points > 0 ? 1u : 0u;
        prev.get()[i] = k;
        age.get()[i] = 0;
        idle.get()[i] = 0;
        fp::Rng r = fp::chain_stream(c.seed + colour_stream_salt, ch);
        if (c.random) {
            cr.get()[i] = fp::uniform_float(r);
            cg.get()[i] = fp::uniform_float(r);
            cb.get()[i] = fp::uniform_float(r);
        } else {
            cr.get()[i] = c.r, cg.get()[i] = c.g, cb.get()[i] = c.b;
        }
        ci.get()[i] = c.index ? fp::uniform_float(r) : c.steal ? 0.5f : 0.0f;
        cv.get()[i] = c.steal ? 0.5f : 0.0f;
        x.get()[i] = T(0);
        y.get()[i] = T(0);
    }
    /// The lanes from nb to the block's end inactive: the fused step reads whole vectors and
    /// takes `active` alone for the lanes that step.
    void idle_tail(size_t nb) { std::fill(active.get() + nb, active.get() + block_size, 0u); }
    /// Whether every colour of lanes [0, nb) lies in [0, 1] (FusedArgs::colours_in_range).
    bool colours_in_unit(size_t nb) const {
        const auto unit = [](float v) { return v >= 0.0f && v <= 1.0f; };
        bool in = true;
        for (size_t i = 0; i < nb; ++i)
            in = in && unit(cr.get()[i]) && unit(cg.get()[i]) && unit(cb.get()[i]);
        return in;
    }
    /// Whether lanes [0, nb) may run steady (SteadyCheck).
    SteadyCheck steady_budget(size_t nb, uint32_t skip) const {
        uint64_t fewest = UINT64_MAX;
        uint32_t youngest = skip; // the smallest age of an active chain, capped at skip
        for (size_t i = 0; i < nb; ++i) {
            const bool a = active.get()[i] != 0;
            youngest = std::min(youngest, a ? age.get()[i] : skip);
            fewest = std::min(fewest, a ? left.get()[i] : UINT64_MAX);
        }
        if (youngest < skip) return {0, skip - youngest - 1};
        return {fewest == UINT64_MAX ? 0 : fewest - 1, 0};
    }
    /// The end of a steady run of `steps` steps: every active chain plotted at each step but the
    /// last when that one restarted it (no allowed map, or a point not finite: restart[i] set),
    /// so its points left and idle count become what the step-by-step bookkeeping would have
    /// made them. Returns the points plotted.
    uint64_t settle_steady(size_t nb, uint64_t steps, const uint32_t* restart) {
        uint64_t plotted = 0;
        for (size_t i = 0; i < nb; ++i) {
            if (!active.get()[i]) continue;
            const uint64_t p = steps - (restart[i] ? 1 : 0);
            // A run longer than steady_budget allows would have plotted past a chain's last point
            // (and the chain would never finish): say so rather than spin.
            if (p >= left.get()[i])
                throw fp::InternalError("chaos-game: a steady run outlived a chain's points");
            left.get()[i] -= p;
            if (p) idle.get()[i] = 0;
            plotted += p;
        }
        return plotted;
    }
};

// ---------------------------------------------------------------- per-worker block state
/// A worker's block: its chains and the arrays one step writes and reads (the draw's inside tests,
/// the chosen maps, the bins and packed colours, the grouping's staging segments), and those of
/// the start points. Allocated once per worker; about 100 bytes a chain, k more for the tests, 8 k
/// for the staging segments: it stays in L1/L2.
template <class T>
struct Scratch {
    Chains<T> c;
    // per-step scratch
    Buf<unsigned char> inside; // k rows of block_size
    Buf<uint32_t> chosen, perm, idx, idx2, restart, plotf, cnt;
    Buf<uint64_t> dep, dep2; // packed {1, r, g, b} of each chain's point (this step's, the last)
    Buf<uint32_t> full;      // bins to spill, listed by the fused step
    Buf<unsigned char> moved;
    Buf<T> gx, gy;    // the staging segments of the grouping by map
    Buf<uint32_t> gi; // the chain of each staged point
    Buf<uint64_t> gk; // the staged points' random keys (maps that draw random numbers)
    // the plotted points and colours when the recipe has final maps or a camera (ChaosGame::finals)
    Buf<T> fx, fy;
    Buf<float> fr, fg, fb, fi;
    Buf<uint32_t> fchosen;
    Buf<uint64_t> fk;
    Buf<T> ox, oy; // a final map's input, kept for the points it skips (its opacity below 1)
    Buf<float> orr, og, ob, oi;
    // start points
    Buf<T> sx, sy;
    Buf<uint32_t> pend;
    Buf<unsigned char> hit, any;
    // the scheme's step at the current step index (the fused step with a scheme)
    fp_chaos::LaneProgram<T> program;

    /// `finals`: the recipe has final maps or a camera (ChaosGame::finals's arrays); `random`:
    /// a map draws random numbers (the staged points' keys).
    Scratch(size_t k, bool finals, bool random) {
        const size_t B = block_size;
        inside.alloc(k * B);
        chosen.alloc(B), perm.alloc(B), idx.alloc(B), idx2.alloc(B), restart.alloc(B);
        plotf.alloc(B), cnt.alloc(k + 1), dep.alloc(B), dep2.alloc(B), full.alloc(B);
        moved.alloc(B), gx.alloc(staging(k)), gy.alloc(staging(k)), gi.alloc(staging(k));
        if (random) gk.alloc(staging(k));
        if (finals) {
            fx.alloc(B), fy.alloc(B), fr.alloc(B), fg.alloc(B), fb.alloc(B), fi.alloc(B), fchosen.alloc(B);
            fk.alloc(B), ox.alloc(B), oy.alloc(B), orr.alloc(B), og.alloc(B), ob.alloc(B), oi.alloc(B);
        }
        sx.alloc(B), sy.alloc(B), pend.alloc(B), hit.alloc(B), any.alloc(B);
    }

    /// The draw's view of the chains (its tables, inside tests and weights left for the caller).
    DrawArgs draw_args(size_t nb, uint32_t k) const {
        return DrawArgs{
            c.rs.get(), c.ri.get(), c.prev.get(), c.active.get(), nullptr, 0, chosen.get(), restart.get(),
            nb,         k,          nullptr,      nullptr,        nullptr};
    }
    /// The bookkeeping's view (its window and constants left for the caller).
    BookArgs<T> book_args(size_t nb) const {
        return BookArgs<T>{c.x.get(),   c.y.get(),    chosen.get(),   c.prev.get(),
                           c.age.get(), c.idle.get(), restart.get(),  plotf.get(),
                           idx.get(),   c.left.get(), c.active.get(), c.cr.get(),
                           c.cg.get(),  c.cb.get(),   dep.get(),      nb};
    }

    static size_t staging(size_t k) { return k <= max_compress_maps ? k * seg_stride : block_size; }
    static uint64_t bytes(size_t k, bool finals, bool random) {
        const uint64_t B = block_size;
        return B * (4 * sizeof(T) + 3 * 8 + 3 * 4 + 3 * 4 + 4 + 5 + k + 8 * 4 + 16 + 1 + 4 + 2 + 4 /* cv */) +
               (2 * sizeof(T) + 4) * staging(k) + 12 * (k + 2) + 64 * 40 +
               (random ? 8 * staging(k) + 64 : 0) + (finals ? B * (2 * sizeof(T) + 5 * 4 + 8) + 64 * 8 : 0);
    }
};

/// A block of chains: chains c0 .. c0 + nb - 1.
struct Span {
    uint64_t c0;
    size_t nb;
};

/// The blocks of a render, in the order the workers take them: blocks of block_size, then,
/// with several workers, the last 4 * workers * tail_block_size chains in blocks of
/// tail_block_size, so that the workers run out of work at nearly the same time. A block is
/// the unit of work: in 1e8-point benchmark renders on two workers, with 8 equal blocks of 512
/// one worker waited 1-56 ms (20 ms on average, 12 renders) for the other at the end; with
/// the tail of 128, 0.2-18 ms (about 6 ms on average, 21 renders; bench/README.md). On one
/// worker, all large: a small block costs as much per step outside its pass as a large one.
/// The partition does not change the image.
inline std::vector<Span> block_spans(uint64_t chains, unsigned workers) {
    const uint64_t tail =
        workers > 1 ? std::min<uint64_t>(chains, uint64_t(4) * workers * tail_block_size) : 0;
    std::vector<Span> v;
    uint64_t c = 0;
    for (; c < chains - tail; c += block_size)
        v.push_back({c, size_t(std::min<uint64_t>(block_size, chains - tail - c))});
    for (; c < chains; c += tail_block_size)
        v.push_back({c, size_t(std::min<uint64_t>(tail_block_size, chains - c))});
    return v;
}

struct BlockResult {
    uint64_t plotted = 0, restarts = 0, bad = 0;
};

} // namespace fp_chaos
