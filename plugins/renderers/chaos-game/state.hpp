// chaos-game's state: the sizes of its blocks of chains, pcg32 on plain arrays, the aligned
// and huge-page buffers, the workers' histograms, a block's structure-of-arrays state and the
// partition of the chains into blocks. chaos-game.cpp includes it, and its tests (chaos-game.cpp's
// header comment says how they are used).
#pragma once

#include "kernels.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

// HugeBuf maps its memory itself on Linux (a fresh mapping comes zeroed), except under
// AddressSanitizer, which checks the bounds of operator new's blocks but not of a mapping: the
// sanitizer build keeps its checks on the deposits into the histograms.
#if defined(__SANITIZE_ADDRESS__)
#define FP_HUGEBUF_MAPPED 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FP_HUGEBUF_MAPPED 0
#endif
#endif
#if !defined(FP_HUGEBUF_MAPPED)
#if defined(__linux__)
#define FP_HUGEBUF_MAPPED 1
#else
#define FP_HUGEBUF_MAPPED 0
#endif
#endif
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

/// Chains per block (the unit of work). 512 keeps a block's state in L1 (about 30 KiB in float) and
/// gives the per-map segments enough points to amortise their virtual calls.
constexpr size_t block_size = 512;
/// Chains per block at the end of a render on several workers (see block_spans).
constexpr size_t tail_block_size = 128;
/// Steps between polls of ctx.cancelled() and progress reports (about 1 ms of work).
constexpr uint64_t poll_steps = 64;
/// Blocks of at most this many chains run lean when they can (one or a few orbits: the
/// papers' single orbit; see chaos-game.cpp's run_block).
constexpr size_t lean_chains = lean_max;
/// Candidates drawn for a start point outside every set before the last one is taken anyway.
constexpr unsigned start_tries = 32;
/// Restarts in a row without a plotted point after which a chain is retired.
constexpr uint32_t max_idle_restarts = 100;
/// Added to the seed for the chains' random start colours (fp::PixelRule::last): the stream
/// fp::chain_stream(seed + salt, chain), not the one the chain draws its maps from.
constexpr uint64_t colour_stream_salt = 0x636f6c6f7572ull; // ASCII "colour"

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

// ---------------------------------------------------------------- aligned buffers
struct AlignedFree {
    void operator()(void* p) const { ::operator delete(p, std::align_val_t(64)); }
};

/// Frees a HugeBuf: its mapping (FP_HUGEBUF_MAPPED), else its aligned allocation.
struct HugeFree {
    size_t bytes = 0;
    void operator()(void* p) const {
#if FP_HUGEBUF_MAPPED
        ::munmap(p, bytes);
#else
        ::operator delete(p, std::align_val_t(2u << 20));
#endif
    }
};

template <class U>
struct Buf {
    std::unique_ptr<U[], AlignedFree> p;
    void alloc(size_t n) {
        p.reset(static_cast<U*>(::operator new(std::max<size_t>(n, 1) * sizeof(U), std::align_val_t(64))));
        std::memset(static_cast<void*>(p.get()), 0, std::max<size_t>(n, 1) * sizeof(U));
    }
    U* get() const { return p.get(); }
};

/// A large zeroed buffer for random access (the histograms): 2 MiB aligned and, on Linux,
/// backed by transparent huge pages where the system allows, so that the deposits do not
/// miss the TLB on every point (a 1024 x 1024 histogram spans 8192 pages of 4 KiB). On Linux
/// (not under AddressSanitizer: FP_HUGEBUF_MAPPED) it is a fresh anonymous mapping, which the
/// kernel hands out zeroed as it faults it in: no memset, which would write every page once
/// more before the deposits do (a worker's 16 MiB of colour bins at 1024 x 1024: part of the
/// fixed cost of every render).
template <class U>
struct HugeBuf {
    std::unique_ptr<U[], HugeFree> p;
    /// `poll` is called between pieces of 64 MiB of zeroing where there is any (not mapped): a
    /// worker's histogram of an 8000 x 8000 render is 1 GiB, and a cancel must not wait for
    /// the whole memset.
    template <class Poll>
    void alloc(size_t n, Poll poll) {
        constexpr size_t huge = 2u << 20;
        const size_t bytes = (std::max<size_t>(n, 1) * sizeof(U) + huge - 1) / huge * huge;
        p.reset();
#if FP_HUGEBUF_MAPPED
        (void)poll;
        // Mapped with a huge page to spare, whose unaligned head and tail are unmapped.
        void* m = ::mmap(nullptr, bytes + huge, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (m == MAP_FAILED) throw std::bad_alloc();
        const uintptr_t b = reinterpret_cast<uintptr_t>(m), a = (b + huge - 1) & ~uintptr_t(huge - 1);
        if (a > b) ::munmap(m, a - b);
        ::munmap(reinterpret_cast<void*>(a + bytes), b + huge - a);  // (a - b < huge: never empty)
        ::madvise(reinterpret_cast<void*>(a), bytes, MADV_HUGEPAGE); // advice only: failure is harmless
        p = std::unique_ptr<U[], HugeFree>(reinterpret_cast<U*>(a), HugeFree{bytes});
#else
        p = std::unique_ptr<U[], HugeFree>(static_cast<U*>(::operator new(bytes, std::align_val_t(huge))),
                                           HugeFree{bytes});
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        ::madvise(static_cast<void*>(p.get()), bytes, MADV_HUGEPAGE); // advice only: failure is harmless
#endif
        constexpr size_t piece = size_t(64) << 20;
        for (size_t done = 0; done < bytes; done += piece) {
            poll();
            std::memset(reinterpret_cast<char*>(p.get()) + done, 0, std::min(piece, bytes - done));
        }
#endif
    }
    U* get() const { return p.get(); }
};

/// v.assign(n, {}) with the new buffer advised into transparent huge pages before it is
/// written (reserve, madvise the 2 MiB-aligned part, then assign): the 32 MiB total histogram
/// and the 12 MiB image of a 1024 x 1024 render fault in as about 22 huge pages instead of
/// 11264 small ones. Part of the fixed cost per render that does not scale with the threads.
/// `poll` is called between pieces of 64 MiB: filling gigabytes (an 8000 x 8000 histogram is
/// 2 GiB) takes seconds, and a cancel must not wait for it.
template <class V, class Poll>
void assign_huge(V& v, size_t n, Poll poll) {
    v.clear();
    v.shrink_to_fit();
    v.reserve(n);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr uintptr_t huge = 2u << 20;
    const uintptr_t b = (reinterpret_cast<uintptr_t>(v.data()) + huge - 1) & ~(huge - 1);
    const uintptr_t e =
        (reinterpret_cast<uintptr_t>(v.data()) + n * sizeof(typename V::value_type)) & ~(huge - 1);
    if (e > b) ::madvise(reinterpret_cast<void*>(b), e - b, MADV_HUGEPAGE); // advice only
#endif
    // Filled piece by piece within the reserved capacity (no reallocation), value-initialised:
    // for fp::HistBin the compilers make that a memset, where a fill with a copy of
    // HistBin{} is a loop of 32-byte stores (at 1024 x 1024, 4 ms against 10).
    const size_t piece = std::max<size_t>(1, (size_t(64) << 20) / sizeof(typename V::value_type));
    for (size_t done = 0; done < n; done = v.size()) {
        poll();
        v.resize(std::min(n, done + piece));
    }
}

/// A worker's histogram bin: {hits, r, g, b} in 32 bits each, 16 bytes, half of fp::HistBin,
/// so that twice as many of the bins a fractal touches stay in cache (at 1024 x 1024 this
/// alone took the circles benchmark from 45 to 57 M points/s). A bin spills into 64 bits
/// before it can overflow: when its hits reach 65536, its colour sums are at most
/// 65536 * 65535 < 2^32.
typedef uint32_t Cnt4 __attribute__((vector_size(16)));
typedef uint64_t Bin4 __attribute__((vector_size(32)));
constexpr uint32_t spill_hits = 65536;
/// The fused step deposits a step's colours during the next step's pass and lists the bins
/// whose hits reached this many, spilled after the pass: at most a block's deposits more reach
/// a bin before it is spilled, so its hits stay below spill_hits (the bound above holds).
constexpr uint32_t spill_lagged = spill_hits - uint32_t(block_size);

/// Tallies: with a colour that is the chosen map's own (the map rule: map-colour) and at most
/// tally_maps maps, the bins are instead a plane of 16-bit counters per map, the hits of each map
/// (Tallies below). The deposit is then one 16-bit increment, with no colour carried by the
/// chains or packed per point; a bin's colour sums are its counts times the maps' quantised
/// colours, the same integers as the sums of the deposits (chaos-game.cpp's "Tallies").
/// A counter spills when it reaches tally_spill (the deposits made at once), or, deposited
/// by the next pass, tally_lagged: at most a block's deposits more reach it before it is
/// spilled, so it stays below 65536.
constexpr uint32_t tally_spill = 65535;
constexpr uint32_t tally_lagged = 65536 - uint32_t(block_size);

/// The maps' quantised colours of a render with tallies: a counter's colour sums.
struct Tallies {
    uint32_t k = 0;
    uint32_t q[tally_maps][3] = {};
    /// The bin {hits, r, g, b} of a bin's counters n[0], n[plane], .. (one per map), into out.
    /// (Not returned: a 32-byte vector returned by value has another ABI with AVX, and GCC
    /// warns of it.)
    void bin(const Tally16* n, size_t plane, Bin4& out) const {
        out = Bin4{0, 0, 0, 0};
        for (uint32_t j = 0; j < k; ++j) {
            const uint64_t c = n[j * plane];
            out += Bin4{c, c * q[j][0], c * q[j][1], c * q[j][2]};
        }
    }
};

/// The 16-byte bins a worker's tallies take: k planes of px + 1 (the dummy's) 16-bit counters,
/// rounded up (WorkerHist::alloc, and the memory planner's count of it).
inline size_t tally_bins(uint32_t k, size_t px) { return (k * (px + 1) + 7) / 8; }

/// Chains are grouped by map with compress stores into one staging segment per map (up to
/// this many maps); beyond, by a scalar counting sort into contiguous segments. Both give the
/// same points in the same order.
constexpr size_t max_compress_maps = 16;
/// A map's staging segment: room for a whole block plus one full vector of the widest target
/// stored past its end (64 lanes: SVE-2048).
constexpr size_t seg_stride = block_size + 64;

/// Hits-only histograms (a colourer that needs no colour) are flushed into 64 bits after this
/// many deposits, before any 32-bit counter can overflow (a step deposits at most a block).
constexpr uint64_t hits_flush = uint64_t(1) << 31;

/// A worker's histogram: 32-bit bins (one more, the last, takes the points not plotted) and
/// the list of bins spilled into 64 bits; or, when the colourer needs no colour, 32-bit hit
/// counters alone (4 bytes a bin, as the reference kernels: four times as many bins per
/// cache line), flushed whole into 64-bit counters every hits_flush deposits. Made by the
/// worker on its first task.
/// The last point a worker wrote to a bin (fp::PixelRule::last): its (step + 1, chain), 0 for
/// none, and its colour packed like the deposit's. The workers' entries of a bin are merged
/// by the largest (step, chain): the same winner for any thread count.
struct LastWrite {
    uint64_t step;
    uint32_t chain;
    uint16_t r, g, b, pad;
};
/// Whether `a` comes after `b` in the order (step, chain) that decides a bin's last colour.
inline bool later(const LastWrite& a, const LastWrite& b) {
    return a.step > b.step || (a.step == b.step && a.chain > b.chain);
}

/// The last colours of step n's points: lw[idx[i]] takes point i's (step n + 1, its chain,
/// colour_of(i), {r, g, b} in 16 bits each) where that comes later than what the bin holds.
/// The points in the dummy bin (not plotted) write nothing. A worker's blocks do not come in
/// chain order, and a bin may hold an entry of an earlier block at a later step: compare.
template <class ColourOf>
void write_last_colours(LastWrite* lw, const uint32_t* idx, size_t nb, uint64_t n, const uint32_t* chain_of,
                        uint32_t dummy, ColourOf colour_of) {
    for (size_t i = 0; i < nb; ++i) {
        const uint32_t b = idx[i];
        if (b == dummy) continue;
        LastWrite w{n + 1, chain_of[i], 0, 0, 0, 0};
        if (later(w, lw[b])) {
            const std::array<uint16_t, 3> c = colour_of(i);
            w.r = c[0], w.g = c[1], w.b = c[2];
            lw[b] = w;
        }
    }
}

struct WorkerHist {
    /// {hits, r, g, b}; or, with tallies, their planes (counters(): map j's counter of bin i at
    /// j * plane + i).
    HugeBuf<Cnt4> bins;
    HugeBuf<LastWrite> last; ///< pixel rule last only
    std::vector<std::pair<uint32_t, Bin4>> spills;
    HugeBuf<uint32_t> hits;
    std::vector<uint64_t> wide; ///< hits flushed out of `hits` (empty until the first flush)
    uint64_t since = 0;         ///< deposits into `hits` since the last flush
    uint32_t dummy = 0;
    const Tallies* tallies = nullptr; ///< the bins are tallies (null: {hits, r, g, b})
    size_t plane = 0;                 ///< tallies: the counters of a map (the bins, the dummy's too)

    template <class Poll>
    void alloc(size_t px, bool colour, bool last_colour, const Tallies* t, Poll poll) {
        tallies = colour ? t : nullptr;
        if (last_colour) last.alloc(px + 1, poll);
        if (colour) {
            plane = px + 1;
            // (Tallies: at most the 16 bytes a bin of colour sums.)
            bins.alloc(tallies ? tally_bins(tallies->k, px) : px + 1, poll);
            spills.reserve(256);
        } else {
            hits.alloc(px + 1, poll);
        }
        dummy = uint32_t(px);
    }
    Tally16* counters() const { return reinterpret_cast<Tally16*>(bins.get()); }
    [[gnu::noinline, gnu::cold]] void spill(uint32_t i) {
        if (tallies) {
            Tally16* const n = counters() + i;
            if (i != dummy) {
                Bin4 v;
                tallies->bin(n, plane, v);
                spills.emplace_back(i, v);
            }
            zero_counters(i);
            return;
        }
        Cnt4& b = bins.get()[i];
        if (i != dummy) spills.emplace_back(i, Bin4{b[0], b[1], b[2], b[3]});
        b = Cnt4{0, 0, 0, 0};
    }
    /// Whether bin i, listed by the fused step, is still due to spill (an earlier entry of the
    /// list may have spilled it).
    bool due(uint32_t i) const {
        if (!tallies) return bins.get()[i][0] >= spill_lagged;
        const Tally16* const n = counters() + i;
        for (uint32_t j = 0; j < tallies->k; ++j)
            if (n[j * plane] >= tally_lagged) return true;
        return false;
    }
    /// Tallies: map[i]'s counter of bin idx[i] incremented for the points from `from` on, until
    /// one reaches tally_spill: returns that point's index, for the caller to spill bin idx[i]
    /// before going on from the next one; nb when done. (The points not plotted, in the dummy
    /// bin, may carry map k, "none": taken as map k - 1, as the fused step takes it.)
    size_t tally(const uint32_t* idx, const uint32_t* map, size_t from, size_t nb) {
        Tally16* const n = counters();
        const uint32_t last_map = tallies->k - 1;
        for (size_t i = from; i < nb; ++i)
            if (__builtin_expect(bump(n + std::min(map[i], last_map) * plane + idx[i]), 0)) return i;
        return nb;
    }
    /// The same with the counters' indices ci (map * plane + bin: the fused step's).
    size_t tally(const uint32_t* ci, size_t from, size_t nb) {
        Tally16* const n = counters();
        for (size_t i = from; i < nb; ++i)
            if (__builtin_expect(bump(n + ci[i]), 0)) return i;
        return nb;
    }
    /// Tallies: zeroes bin i's counter on every plane.
    void zero_counters(uint32_t i) {
        for (uint32_t j = 0; j < tallies->k; ++j) counters()[j * plane + i] = 0;
    }
    /// Zeroes the dummy bin (whose points are discarded).
    void clear_dummy() {
        if (hits.get()) hits.get()[dummy] = 0;
        if (tallies)
            zero_counters(dummy);
        else if (bins.get())
            bins.get()[dummy] = Cnt4{0, 0, 0, 0};
    }
    /// *n incremented; whether it reached tally_spill.
    static bool bump(Tally16* n) {
        const uint16_t v = uint16_t(*n + 1);
        *n = v;
        return v == tally_spill;
    }
    /// Adds bins [b0, b1) (hits, colour sums, flushed hits; not the spills) into `out`, and
    /// with `clear` zeroes them here.
    void add_to(fp::HistBin* out, size_t b0, size_t b1, bool clear) {
        if (uint32_t* in = hits.get()) {
            each_hits(b0, b1, [out](size_t i, uint64_t v) { out[i].hits += v; });
            if (clear) {
                std::memset(static_cast<void*>(in + b0), 0, (b1 - b0) * sizeof(uint32_t));
                if (!wide.empty())
                    std::fill(wide.begin() + std::ptrdiff_t(b0), wide.begin() + std::ptrdiff_t(b1), 0);
            }
        } else if (Tally16* n = counters(); n && tallies) {
            for (size_t i = b0; i < b1; ++i) {
                Bin4 v;
                tallies->bin(n + i, plane, v);
                out[i].hits += v[0];
                out[i].r += v[1];
                out[i].g += v[2];
                out[i].b += v[3];
            }
            if (clear)
                for (uint32_t j = 0; j < tallies->k; ++j)
                    std::memset(static_cast<void*>(n + j * plane + b0), 0, (b1 - b0) * sizeof(Tally16));
        } else if (Cnt4* in = bins.get()) {
            for (size_t i = b0; i < b1; ++i) {
                out[i].hits += in[i][0];
                out[i].r += in[i][1];
                out[i].g += in[i][2];
                out[i].b += in[i][3];
            }
            if (clear) std::memset(static_cast<void*>(in + b0), 0, (b1 - b0) * sizeof(Cnt4));
        }
    }
    /// Adds the hit counts of bins [b0, b1) (with the flushed ones) into `out`, a total of hit
    /// counts alone.
    void add_hits_to(uint64_t* out, size_t b0, size_t b1) const {
        if (hits.get()) each_hits(b0, b1, [out](size_t i, uint64_t v) { out[i] += v; });
    }
    /// add(i, v) for the counts of bins [b0, b1) of `hits`, then for those flushed into `wide`.
    template <class Add>
    void each_hits(size_t b0, size_t b1, Add add) const {
        const uint32_t* in = hits.get();
        for (size_t i = b0; i < b1; ++i) add(i, in[i]);
        if (!wide.empty())
            for (size_t i = b0; i < b1; ++i) add(i, wide[i]);
    }
    [[gnu::noinline, gnu::cold]] void flush() {
        if (wide.empty()) wide.assign(dummy, 0);
        uint32_t* h = hits.get();
        for (size_t i = 0; i < dummy; ++i) wide[i] += h[i];
        std::memset(static_cast<void*>(h), 0, (size_t(dummy) + 1) * sizeof(uint32_t));
        since = 0;
    }
};

// ---------------------------------------------------------------- per-worker block state
template <class T>
struct Scratch {
    // chain state
    Buf<T> x, y;
    Buf<uint64_t> rs, ri, left;
    Buf<uint32_t> prev, age, idle;
    Buf<float> cr, cg, cb;
    Buf<uint32_t> active;   // 0 / 1
    Buf<uint32_t> chain;    // the chain of each lane
    Buf<unsigned char> fin; // a checkpointed render: the lane's final state is recorded
    // per-step scratch
    Buf<unsigned char> inside; // k rows of block_size
    Buf<uint32_t> chosen, perm, idx, idx2, restart, plotf, cnt;
    Buf<uint64_t> dep, dep2; // packed {1, r, g, b} of each chain's point (this step's, the last)
    Buf<uint32_t> full;      // bins to spill, listed by the fused step
    Buf<unsigned char> moved;
    Buf<T> gx, gy;    // the staging segments of the grouping by map
    Buf<uint32_t> gi; // the chain of each staged point
    // start points
    Buf<T> sx, sy;
    Buf<uint32_t> pend;
    Buf<unsigned char> hit, any;
    // the scheme's step at the current step index (the fused step with a scheme)
    fp_chaos::LaneProgram<T> program;

    explicit Scratch(size_t k) {
        const size_t B = block_size;
        x.alloc(B), y.alloc(B), rs.alloc(B), ri.alloc(B), left.alloc(B);
        prev.alloc(B), age.alloc(B), idle.alloc(B), cr.alloc(B), cg.alloc(B), cb.alloc(B), active.alloc(B);
        chain.alloc(B), fin.alloc(B);
        inside.alloc(k * B);
        chosen.alloc(B), perm.alloc(B), idx.alloc(B), idx2.alloc(B), restart.alloc(B);
        plotf.alloc(B), cnt.alloc(k + 1), dep.alloc(B), dep2.alloc(B), full.alloc(B);
        moved.alloc(B), gx.alloc(staging(k)), gy.alloc(staging(k)), gi.alloc(staging(k));
        sx.alloc(B), sy.alloc(B), pend.alloc(B), hit.alloc(B), any.alloc(B);
    }

    static size_t staging(size_t k) { return k <= max_compress_maps ? k * seg_stride : block_size; }
    static uint64_t bytes(size_t k) {
        const uint64_t B = block_size;
        return B * (4 * sizeof(T) + 3 * 8 + 3 * 4 + 3 * 4 + 4 + 5 + k + 8 * 4 + 16 + 1 + 4 + 2) +
               (2 * sizeof(T) + 4) * staging(k) + 12 * (k + 2) + 64 * 40;
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
