// chaos-game's checkpoints (`fixpoint render --checkpoint`, `--resume`): what a render saves
// and continues from (chaos-game/checkpoint.cpp writes and reads it; a chain's own record is
// chains.hpp's ChainRec).
//
// A render is a set of chains, each a pure function of (seed, chain, the steps it has run), and
// a histogram of exact integer sums over their points. So a render can stop anywhere between
// two steps of a block, its state be written out, and go on later, in other blocks, on other
// threads, with the same sums in the end:
//   - the work not yet done: blocks not started (chain ranges), and suspended blocks (each
//     chain's state, all at the same next step);
//   - the chains already finished or retired, with their final state and the step each would
//     run next: a render continued to more points (`--set renderer.points=`) gives each the
//     points it now has beyond the old count, and runs them on from there, in blocks of chains
//     at the same next step (the iteration scheme sees the step index; the last-colour rule
//     compares (step, chain));
//   - the histogram so far (every worker's folded into one: 64-bit sums, and last colours with
//     their (step, chain)), and the counts of the stats.
// A block stops at a poll (every poll_steps steps), after a steady run is settled and the
// fused step's lagged deposits are made: what it saves is what the step-by-step bookkeeping
// would hold there.
#pragma once

#include "chains.hpp"

#include <fixpoint/fixpoint.hpp>

#include <atomic>
#include <cstdint>
#include <vector>

namespace fp_chaos {

/// No final state recorded (ChainRec::step of a chain still running).
constexpr uint64_t not_final = UINT64_MAX;

/// A unit of work: fresh chains (`ids`, or c0 .. c0 + nb - 1) that start at step 0, or chains
/// continued from `saved` (all at the same next step).
struct Task {
    uint64_t c0 = 0;
    size_t nb = 0;
    std::vector<uint32_t> ids;
    std::vector<ChainRec> saved;
    bool done = false;
    BlockResult res;
    uint32_t chain(size_t i) const {
        return saved.empty() ? (ids.empty() ? uint32_t(c0 + i) : ids[i]) : saved[i].chain;
    }
    size_t size() const { return saved.empty() ? (ids.empty() ? nb : ids.size()) : saved.size(); }
};

/// What a checkpointed render shares between its blocks.
struct Keeping {
    std::atomic<bool> stop{false};     ///< a checkpoint is due: blocks stop at their next poll
    std::vector<ChainRec> finals;      ///< by chain: its final state (step = not_final: none yet)
    std::atomic<uint64_t> progress{0}; ///< units reported, for the next resume's bar
};

/// The payload's fixed part (after it: the pending tasks, the final states, the histogram and,
/// with last colours, the bins' last writes).
struct PayloadHead {
    /// 2: the rules' draw became paper 01's loop (the streams' outputs are used otherwise, so a
    /// checkpoint of version 1 would resume into other bytes); 3: a chain's record holds its
    /// palette index (ChainRec::ci).
    uint32_t version = 3;
    uint32_t precision = 4; ///< sizeof the chains' float type
    uint64_t points = 0, chains = 0;
    uint32_t width = 0, rows = 0;
    uint32_t colour = 0, last = 0;
    uint64_t samples = 0, restarts = 0, bad = 0, progress = 0;
    uint64_t tasks = 0, finals = 0;
};
static_assert(sizeof(PayloadHead) == 88, "PayloadHead is written as it is");

} // namespace fp_chaos
