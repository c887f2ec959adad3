// chaos-game's histograms: what a worker deposits its points into (16-byte bins of 32-bit
// counters that spill into 64 bits, 4-byte hit counters, or per-map tallies), and the last
// colours of paper 02's Algorithm 2; the workers' histograms are summed into one fp::Histogram by
// chaos-game/render.cpp.
//
// The workers' histograms have 16-byte bins {hits, r, g, b} of 32 bits (half of
// fp::HistBin: the bins a fractal touches are what limits the deposit, and twice as many
// stay in cache); a bin spills into a list of 64-bit bins when its hits reach 65536, before
// its colour sums (at most 65535 per point) can overflow. They live in 2 MiB-aligned memory
// advised for transparent huge pages (no TLB miss per deposit). At the end they and the
// spills are summed into one fp::Histogram (rows in parallel), which the colourer resolves
// on the workers too (Colourer::resolve_parallel: rows in parallel, the same bytes as the
// serial resolve). A colourer whose needs_colour() is false (density) reads hit counts
// only: then the chains carry no colour and the workers count hits alone in 4-byte
// counters (as the reference kernels do: four times as many bins per cache line), flushed
// whole into 64-bit counters every 2^31 deposits of a worker, before any can overflow; the
// fp::Histogram gets hits and zero colour sums, or hit counts alone (fp::Histogram::hits)
// where its reader asks for no more (Colourer::reads_hits_only, and the summary of a render
// in strips).
//
// Tallies: with the map rule (map-colour: each point the colour of the map that made it) and
// at most 8 maps, on the fused path (a recipe's steps that fall back to the generic one too),
// a worker's bins are instead 16-bit counters, the points each map put there, in a plane per
// map (map j's counter of bin i at j * plane + i: a map's points lie in a region of their own,
// the image of its set, so its counters share cache lines; a bin's 8 counters side by side
// took as many lines as the 16-byte bins, more than twice those of 4-byte hit counts).
// The deposit is one 16-bit increment by the point's map; the chains carry no colour and no
// colour is packed per point. A counter spills (the whole bin, into the list of 64-bit bins)
// before it can wrap, and the sums into fp::Histogram turn a bin's counts n_j into {sum n_j,
// sum n_j q_j} with q_j map j's quantised colour: the integers the colour deposits would have
// summed, so the image is the same bytes (the generic path keeps {hits, r, g, b}: `kernels:
// generic` renders compare the two in tests/unit/test_chaos_kernel.cpp). On bench/circles.yaml
// with map-colour this took one core from 212 to 271 M points/s pinned to AVX2, and from 313 to
// about 375 on AVX-512 (a 2-core Xeon); the planes, from 287 to 339 and from 379 to 430 (a
// 2-core AMD EPYC with AVX-512 and a 1 MiB L2 a core).
//
// Last colours (a colourer whose fp::PixelRule is last: flame's `last` and `set-colour`):
// paper 02's Algorithm 2 as written. A chain starts with a random colour (from the stream
// fp::chain_stream(seed + colour_stream_salt, chain), which its draws never touch), update()
// changes it only at the steps where it plots, and each worker keeps per bin the colour of
// its point with the largest (step, chain); the workers' entries merge by the same order, so
// the winner, and the image, are the same on any number of threads. With the map rule
// (set-colour), where a point's colour is its map's, the fused step runs and the renderer
// writes the last colours after each of its steps; the running colour (`last`) takes the
// generic path.
#pragma once

#include "buffers.hpp"
#include "kernels.hpp"

#include <fixpoint/check.hpp>
#include <fixpoint/histogram.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

namespace fp_chaos {

using std::size_t;
using std::uint32_t;
using std::uint64_t;

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

/// Hits-only histograms (a colourer that needs no colour) are flushed into 64 bits after this
/// many deposits, before any 32-bit counter can overflow (a step deposits at most a block).
constexpr uint64_t hits_flush = uint64_t(1) << 31;

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
        FP_DCHECK(b <= dummy);
        if (b == dummy) continue;
        LastWrite w{n + 1, chain_of[i], 0, 0, 0, 0};
        if (later(w, lw[b])) {
            const std::array<uint16_t, 3> c = colour_of(i);
            w.r = c[0], w.g = c[1], w.b = c[2];
            lw[b] = w;
        }
    }
}

/// A worker's histogram: 32-bit bins (one more, the last, takes the points not plotted) and
/// the list of bins spilled into 64 bits; or, when the colourer needs no colour, 32-bit hit
/// counters alone (4 bytes a bin, as the reference kernels: four times as many bins per
/// cache line), flushed whole into 64-bit counters every hits_flush deposits. Made by the
/// worker on its first task.
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
        for (size_t i = from; i < nb; ++i) {
            FP_DCHECK(idx[i] < plane && map[i] <= tallies->k);
            if (__builtin_expect(bump(n + std::min(map[i], last_map) * plane + idx[i]), 0)) return i;
        }
        return nb;
    }
    /// The same with the counters' indices ci (map * plane + bin: the fused step's).
    size_t tally(const uint32_t* ci, size_t from, size_t nb) {
        Tally16* const n = counters();
        for (size_t i = from; i < nb; ++i) {
            FP_DCHECK(ci[i] < tallies->k * plane);
            if (__builtin_expect(bump(n + ci[i]), 0)) return i;
        }
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
    /// Adds the bins spilled into 64 bits into `out`; returns their hits.
    uint64_t add_spills_to(fp::HistBin* out) const {
        uint64_t hits = 0;
        for (const auto& [i, v] : spills) {
            fp::HistBin& o = out[i];
            o.hits += v[0];
            hits += v[0];
            o.r += v[1];
            o.g += v[2];
            o.b += v[3];
        }
        return hits;
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

} // namespace fp_chaos
