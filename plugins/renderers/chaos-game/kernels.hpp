// chaos-game's step stages: the arguments of the vectorised kernels (kernels-inl.hpp, compiled for
// every instruction set of the build by chaos-game/kernels.cpp) and the functions that dispatch to
// them at run time. Everything here is plain data: the kernels see arrays, never a plugin.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace fp_chaos {

using std::size_t;
using std::uint32_t;
using std::uint64_t;

/// Chains per block (the unit of work). 512 keeps a block's state in L1 (about 30 KiB in float)
/// and gives the per-map segments enough points to amortise their virtual calls. Every block
/// array holds this many lanes, a multiple of every target's lane count: the kernels read whole
/// vectors.
constexpr std::size_t block_size = 512;

/// Entries of the per-map tables (weights, circles): a whole vector of the widest target
/// (64 float lanes of SVE-2048) so that a table loads as one vector; k above the lane count
/// of the target at hand selects per map instead of by table lookup (the same values).
constexpr std::size_t table_size = 64;

/// The most chains of a lean run (chaos-game/block.cpp; chains.hpp's lean_chains).
constexpr std::size_t lean_max = 64;

/// The draws of paper 01's rejection loop (kernels-inl.hpp's draw_paper) before the direct draw
/// among the allowed maps settles the chains still rejected.
constexpr int rejection_draws = 4;

/// The draw of a map per chain (paper 01's rules, or Walker's alias table).
struct DrawArgs {
    std::uint64_t* rs;           ///< pcg32 states, advanced by one output per chain
    const std::uint64_t* ri;     ///< pcg32 increments
    const std::uint32_t* prev;   ///< previous map (k: none)
    const std::uint32_t* active; ///< 0 / 1 (the fused step: 0 past nb, to its last whole vector)
    const unsigned char* inside; ///< rules: k rows of block_size bytes (1: the map's set holds the point)
    std::size_t row;             ///< the stride of `inside`
    std::uint32_t* chosen;       ///< out: the map, k when none (inactive, or none allowed)
    std::uint32_t* restart;      ///< out: 1 for an active chain with no allowed map, else 0
    std::size_t nb;              ///< chains
    std::uint32_t k;             ///< maps
    const std::uint32_t* q;      ///< rules: integer weights (sum below 2^32)
    const std::uint32_t* thr;    ///< alias (and rules with unequal weights): Walker's thresholds
    const std::uint32_t* alias;  ///< alias (and rules with unequal weights): each column's other map
    bool uniform = false;        ///< rules: every weight the same
};

/// Bookkeeping of a step (see chaos_bookkeep.hpp's description).
template <class T>
struct BookArgs {
    T* x; ///< (the fused step moves the points; the bookkeeping only reads them)
    T* y;
    const std::uint32_t* chosen;
    std::uint32_t* prev;
    std::uint32_t* age;
    std::uint32_t* idle;
    std::uint32_t* restart; ///< bit 0 set by the draw, bit 1 (bad value) added here
    std::uint32_t* plotf;
    std::uint32_t* idx;
    std::uint64_t* left;
    std::uint32_t* active;
    float* cr; ///< (the fused step updates the colours; the bookkeeping only reads them)
    float* cg;
    float* cb;
    std::uint64_t* dep; ///< packed {1, r, g, b} (colour only)
    std::size_t nb;
    T xmin = 0, xmax = 0, ymin = 0, ymax = 0, scx = 0, scy = 0;
    std::uint32_t W = 0, H = 0, dummy = 0, skip = 0, none = 0;
    /// `escape`: a point with |x| or |y| above it is bad as a point that is not finite is (0: none).
    T bound = 0;
    /// The rows binned (a strip of the image: chaos-game/plan.cpp's "Strips"): a point whose row is
    /// outside [row0, row0 + rows) goes to dummy, the others to (row - row0) * W + column.
    /// The defaults: every row.
    std::uint32_t row0 = 0, rows = 0xffffffffu;
};

struct Counts {
    std::uint64_t plotted = 0;
    std::uint32_t bad = 0, restarts = 0, still = 0;
};

/// A lean run of fused steps (kernels-inl.hpp's fused_run_t): the last step's counts, the
/// points plotted over all of them, and how many steps ran.
struct RunCounts {
    Counts last;
    std::uint64_t plotted = 0, steps = 0;
};

/// Grouping by map: each map's points compressed into its own segment of the staging arrays
/// (stride `stride`), with the chains' indices; counts per map out.
template <class T>
struct GroupArgs {
    const T* x;
    const T* y;
    const std::uint32_t* chosen;
    T* gx;
    T* gy;
    std::uint32_t* gi;
    std::uint32_t* counts; ///< k entries
    std::size_t stride;
    std::size_t nb;
    std::uint32_t k;
};

/// What the fused step computes per map (fp::KnownKernel's kinds) and per chain's colour
/// (fp::ColourRule; none: hits only; tally: the map rule counted per map, histogram.hpp's Tallies:
/// no colour carried, the chosen map deposited).
enum class LaneKind : std::uint32_t { circle, affine, gumowski_mira };
enum class LaneColour : std::uint32_t { none, map, average, tally };
/// Tallies: the most maps, a plane of 16-bit counters each (histogram.hpp's WorkerHist).
constexpr std::size_t tally_maps = 8;
/// A tally's 16-bit counter (the planes' memory is the colour bins', allocated as such).
typedef std::uint16_t Tally16 __attribute__((may_alias));

/// The fused step's tables, one entry per map: the map's parameters (circle: cx, cy, r2;
/// affine: a .. f; Gumowski-Mira: alpha, mu, 2 (1 - mu)), its weight for the rules' draw, its
/// column of Walker's alias table, and its colour.
template <class T>
struct LaneTables {
    using U = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
    alignas(64) T p[6][table_size] = {};
    alignas(64) U thr[table_size] = {};
    alignas(64) U alias[table_size] = {};
    alignas(64) float cr[table_size] = {};
    alignas(64) float cg[table_size] = {};
    alignas(64) float cb[table_size] = {};
    std::uint32_t q[table_size] = {};
    /// The circles' parameters (cx, cy, r2) and the rules' weights of the first wide_maps maps,
    /// each repeated over a vector of the widest target (256 bytes: SVE-2048): the draw reads
    /// them as whole vector operands, where targets without broadcasting operands (AVX2,
    /// SSE4, NEON) would spend an instruction a parameter and map on a broadcast.
    static constexpr std::size_t wide_maps = 16;
    static constexpr std::size_t wide_lanes = 256 / sizeof(T);
    alignas(64) T wp[3][wide_maps][wide_lanes] = {};
    alignas(64) U wq[wide_maps][wide_lanes] = {};
    /// Fills wp and wq from p and q for the first k maps: once the other tables are set.
    void repeat_wide() {
        for (std::size_t j = 0; j < k && j < wide_maps; ++j) {
            for (std::size_t l = 0; l < wide_lanes; ++l) {
                wq[j][l] = U(q[j]);
                for (int i = 0; i < 3; ++i) wp[i][j][l] = p[i][j];
            }
        }
    }
    std::uint32_t k = 0;
    LaneKind kind = LaneKind::circle;
    LaneColour colour = LaneColour::none;
    bool rules = true;    ///< paper 01's rules (circles: their sets too); else the alias table
    bool uniform = false; ///< rules: every weight the same (see DrawArgs)
    /// Every map's colour lies in [0, 1] (see FusedArgs::colours_in_range).
    bool colours_in_range = false;
};

/// An iteration scheme's step as the fused step runs it: fp::SchemeProgram (scheme_program.hpp)
/// with its coefficients rounded to the chains' precision, as run_program rounds them. Each map
/// instruction applies the chain's chosen map (its parameters gathered once per vector).
enum class ProgOp : std::uint32_t { map, copy, lin2, lin3 };
template <class T>
struct LaneProgram {
    static constexpr std::size_t max_instrs = 16, max_regs = 8; // (fp::SchemeProgram's)
    struct Instr {
        ProgOp op;
        std::uint32_t dst, u, v, w;
        T k[12];
    };
    Instr code[max_instrs];
    std::uint32_t size = 0, regs = 1;
};

/// The fused step: the draw, the maps, the colour and the bookkeeping of a block in one pass;
/// with hits only, `lag` (or null) holds the previous step's bins, deposited into `hits`
/// during it.
template <class T>
struct FusedArgs {
    const LaneTables<T>* tables;
    /// inside, q, thr and alias unused; prev, active, chosen and restart are book's arrays (the
    /// step's main loop reads them through `book` alone: fewer pointers held in registers)
    DrawArgs draw;
    BookArgs<T> book;
    std::uint32_t* hits;
    const std::uint32_t* lag;
    bool steady; ///< the block is in a steady run (see chains.hpp's steady runs)
    /// The scheme's step at this step index; null: the Picard step p <- T(p).
    const LaneProgram<T>* program = nullptr;
    /// With colour: the worker's bins (4 counters each), the previous step's packed colours
    /// (beside `lag`, its bins), deposited during the pass like the hits; the bins whose hits
    /// reach `spill_at` are listed in `full` (count in *nfull) for the caller to spill.
    /// With tallies: `bins` holds a plane of `plane` 16-bit counters per map (one per bin, the
    /// dummy's included), `lag_dep` the previous step's counters (map * plane + bin) as 32-bit
    /// values (the pass writes this step's into book.dep so), and the bins whose counter
    /// reaches `spill_at` are listed.
    std::uint32_t* bins = nullptr;
    const std::uint64_t* lag_dep = nullptr;
    std::uint32_t* full = nullptr;
    std::uint32_t* nfull = nullptr;
    std::uint32_t spill_at = 0;
    std::uint32_t plane = 0;
    /// Every chain's colour lies in [0, 1] (none NaN). With the maps' colours in range too
    /// (LaneTables::colours_in_range), the colour rules keep them there: (c + c_j) * 0.5 of two
    /// values in [0, 1] is in [0, 1] in float arithmetic (the sum is rounded within [0, 2], the
    /// halving exact), c_j is. The packing then skips the clamp of fp::quantise_colour, whose
    /// result it cannot change.
    bool colours_in_range = false;
};

// ---------------------------------------------------------------- Walker's alias table
/// Walker's alias table (Vose's construction) for weights w, with 32-bit thresholds: column c =
/// floor(u * k), kept when the fraction's 32 bits are below thr[c], else alias[c]. Padded with
/// zeros to at least table_size entries, so that the draw's table lookups may load whole
/// vectors. (The rules-off draw, and the rules' draw with unequal weights.)
inline void walker_table(const std::vector<double>& w, std::vector<uint32_t>& thr,
                         std::vector<uint32_t>& alias) {
    const size_t k = w.size();
    double sum = 0;
    for (double x : w) sum += x;
    thr.assign(k, 0xffffffffu);
    alias.resize(k);
    std::vector<double> sc(k);
    std::vector<uint32_t> small, large;
    for (size_t j = 0; j < k; ++j) {
        sc[j] = w[j] / sum * double(k);
        alias[j] = uint32_t(j);
        (sc[j] < 1.0 ? small : large).push_back(uint32_t(j));
    }
    while (!small.empty() && !large.empty()) {
        const uint32_t s = small.back(), l = large.back();
        small.pop_back();
        thr[s] = uint32_t(std::min(4294967295.0, std::floor(sc[s] * 4294967296.0)));
        alias[s] = l;
        sc[l] = (sc[l] + sc[s]) - 1.0;
        if (sc[l] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // What is left (rounding) is full: its column keeps itself (thr = max, alias = self).
    thr.resize(std::max(k, table_size), 0);
    alias.resize(std::max(k, table_size), 0);
}

// ---------------------------------------------------------------- the dispatched stages
// Each calls the kernel compiled for the best instruction set this CPU has (chaos-game/kernels.cpp:
// Highway's dynamic dispatch, one indirect call per block step).
/// Choice of a map per chain: paper 01's rules (draw_rules) or Walker's alias table.
void draw_by_rules(const DrawArgs& a);
void draw_by_alias(const DrawArgs& a);
/// Grouping by map and the way back.
void group(const GroupArgs<float>& a);
void group(const GroupArgs<double>& a);
void scatter(const float* gx, const float* gy, const std::uint32_t* gi, std::size_t n, float* x, float* y);
void scatter(const double* gx, const double* gy, const std::uint32_t* gi, std::size_t n, double* x,
             double* y);
/// The bookkeeping of a step (with the packed colours when `colour`).
Counts bookkeep(const BookArgs<float>& a, bool colour);
Counts bookkeep(const BookArgs<double>& a, bool colour);
/// The deposit of packed colours from point `from` on until a bin is due to spill (its index),
/// nb when done.
std::size_t deposit_colours(std::uint32_t* bins, const std::uint32_t* idx, const std::uint64_t* dep,
                            std::size_t from, std::size_t nb, std::uint32_t spill);
/// The fused step, and a lean run of up to `steps` of them.
Counts fused(const FusedArgs<float>& a);
Counts fused(const FusedArgs<double>& a);
RunCounts fused_run(const FusedArgs<float>& a, std::uint64_t steps);
RunCounts fused_run(const FusedArgs<double>& a, std::uint64_t steps);

} // namespace fp_chaos
