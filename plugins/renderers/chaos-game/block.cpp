// One block of chains, run step by step to its end (or to a checkpoint): Block, whose run() is the
// list of a step's stages. Each stage is a function of its own because it has a reason to exist
// apart: a checkpoint may stop the block only between two steps (poll); a step either runs fused
// (every map a known kernel: one vectorised pass) or generic (the plugins' batch calls), and the
// two paths must leave the same state behind; the deposit of the fused path lags one step (its
// cache misses overlap the next pass), so it must be settled before anything reads the histogram
// or the block stops; restarts are rare and batched; a checkpointed render records a chain's
// final state as it finishes. What a step computes is described in chaos-game.cpp's header.
#include "chaos-game/chains.hpp"
#include "chaos-game/histogram.hpp"
#include "chaos-game/kernels.hpp"
#include "chaos-game/renderer.hpp"

#include <fixpoint/check.hpp>
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace fp_chaos {

template <class T, bool Rules, bool Colour>
class Block {
public:
    Block(const ChaosGame& g, Task& t, Scratch<T>& s, WorkerHist& hist, fp::RenderContext& ctx, uint32_t row0,
          uint32_t rows, Keeping* keep)
        : g_(g), t_(t), s_(s), c_(s.c), hist_(hist), ctx_(ctx), keep_(keep), nb_(t.size()),
          none_(uint32_t(g.maps_.size())), bv_(s.book_args(nb_)), out_(s.idx.get()), dep_out_(s.dep.get()),
          // A block of few chains counting hits only runs lean (lean-inl.hpp's fused_run_t): the
          // fused steps up to the next poll in one call, each depositing its own bins. (Not with
          // a scheme's program, which may change from step to step.)
          lean_(g.fused_ && !g.program_ && !Colour && nb_ <= lean_chains) {
        FP_DCHECK(nb_ > 0 && nb_ <= block_size);
        set_window(row0, rows);
    }

    /// The chains to their end (true), or until a checkpoint is due (false: their state is in
    /// the task's `saved`).
    bool run() {
        start();
        for (uint64_t n = n0_; live_ > 0; ++n) {
            if (n % poll_steps == 0 && n > n0_ && poll(n)) return false;
            const size_t live_before = live_;
            uint64_t steps = 1;
            const bool fused = fused_now(n);
            const Counts sc = fused ? step_fused(n, steps) : step_generic(n);
            deposit(fused, steps);
            t_.res.plotted += sc.plotted;
            t_.res.bad += sc.bad;
            live_ = sc.still;
            if (sc.restarts) restart();
            if (keep_ && live_ < live_before) keep_finals(n + 1);
        }
        deposit_lag();
        report(nominal_ - std::min(nominal_, reported_));
        return true;
    }

private:
    /// The bookkeeping's window: the view, its scale to pixels, the rows binned (a strip), the
    /// dummy bin of the points not plotted.
    void set_window(uint32_t row0, uint32_t rows) {
        const fp::Frame& f = g_.hist_;
        bv_.xmin = T(f.region.xmin), bv_.xmax = T(f.region.xmax), bv_.ymin = T(f.region.ymin),
        bv_.ymax = T(f.region.ymax);
        bv_.scx = T(double(f.width) / (f.region.xmax - f.region.xmin)),
        bv_.scy = T(double(f.height) / (f.region.ymax - f.region.ymin));
        bv_.W = uint32_t(f.width), bv_.H = uint32_t(f.height);
        bv_.row0 = row0, bv_.rows = rows;
        bv_.dummy = uint32_t(size_t(f.width) * size_t(rows));
        bv_.skip = uint32_t(std::min<uint64_t>(g_.skip_, 0xffffffffu));
        bv_.bound = T(g_.escape_);
        bv_.none = none_;
    }

    /// The chains' state at the block's first step: fresh chains at step 0 (each from its own
    /// stream, a start point outside every set), or where a checkpoint left them. Counts the
    /// steps the block runs without restarts (`nominal`, for progress).
    void start() {
        uint32_t* list = s_.perm.get();
        const StartColour colour{
            g_.last_,    g_.seed_, g_.initial_colour_.r, g_.initial_colour_.g, g_.initial_colour_.b,
            g_.palette_, g_.steal_};
        for (size_t i = 0; i < nb_; ++i) {
            if (!t_.saved.empty()) {
                const ChainRec& r = t_.saved[i];
                c_.restore(i, r);
                n0_ = r.step;
                if (r.active) {
                    nominal_ += (r.age < g_.skip_ ? g_.skip_ - r.age : 0) + r.left;
                    ++nlive_;
                }
                continue;
            }
            const uint64_t chain = t_.chain(i), left = points_of(chain, g_.points_, g_.chains_);
            c_.fresh(i, chain, g_.seed_, left, none_, colour);
            if (left > 0) {
                nominal_ += g_.skip_ + left;
                list[nlive_++] = uint32_t(i);
            } else if (keep_) {
                // No points: final before it starts (step 0 says so to a continued render).
                keep_->finals[chain] = c_.record(i, 0);
                c_.fin.get()[i] = 1;
            }
        }
        c_.idle_tail(nb_);
        colours_in_range_ = c_.colours_in_unit(nb_);
        if (t_.saved.empty()) g_.new_starts(s_, list, nlive_);
        live_ = nlive_;
    }

    /// Every poll_steps steps: cancellation and progress, and, in a checkpointed render whose
    /// checkpoint is due, the stop: the state the step-by-step bookkeeping would hold (a steady
    /// run settled, the lagged deposits made), every lane saved. True when the block stopped.
    bool poll(uint64_t n) {
        if (ctx_.cancelled()) throw fp::Cancelled();
        const uint64_t done = std::min(nominal_, (n - n0_) * uint64_t(nlive_));
        report(done - reported_);
        reported_ = done;
        if (!keep_ || !(keep_->stop.load(std::memory_order_relaxed) || ctx_.checkpoint_due())) return false;
        keep_->stop.store(true, std::memory_order_relaxed);
        end_steady();
        deposit_lag();
        t_.saved.resize(nb_);
        for (size_t i = 0; i < nb_; ++i) t_.saved[i] = c_.record(i, n);
        return true;
    }

    /// Whether step n runs fused. With a scheme's program: when every map gives the same one at
    /// this n (else, rare, the generic step, after the fused step's pending work is settled).
    bool fused_now(uint64_t n) {
        if (!g_.program_) return g_.fused_;
        if (g_.lane_program(n, s_.program)) return true;
        end_steady();
        steady_wait_ = 0;
        deposit_lag();
        bv_.idx = s_.idx.get();
        bv_.dep = s_.dep.get();
        return false;
    }

    /// Steps 1-5 in one fused pass: a steady run where the block may take one, a lean run of
    /// several steps for few chains (n and `steps` then move on by the steps it ran).
    Counts step_fused(uint64_t& n, uint64_t& steps) {
        if (steady_left_ == 0) {
            if (steady_wait_ > 0) {
                --steady_wait_;
            } else {
                const SteadyCheck c = c_.steady_budget(nb_, bv_.skip);
                steady_left_ = c.budget;
                steady_wait_ = c.wait;
            }
        }
        const bool steady = steady_left_ > 0;
        Counts sc;
        uint64_t ran = 1;
        if (lean_) {
            // Up to the next poll (or the end of the steady run) in one call.
            const uint64_t m = steady ? std::min(steady_left_, poll_steps - n % poll_steps) : 1;
            const RunCounts rc = fused_run(fused_args(nullptr, steady), m);
            sc = rc.last;
            sc.plotted = rc.plotted;
            ran = rc.steps;
            n += ran - 1;
        } else {
            bv_.idx = out_;
            bv_.dep = dep_out_;
            FusedArgs<T> f = fused_args(lag_, steady);
            if (g_.program_) f.program = &s_.program;
            if constexpr (Colour) {
                f.bins = reinterpret_cast<uint32_t*>(hist_.bins.get());
                f.lag_dep = lag_dep_;
                f.full = s_.full.get();
                f.nfull = &nfull_;
                f.spill_at = hist_.tallies ? tally_lagged : spill_lagged;
                f.plane = uint32_t(hist_.plane);
                f.colours_in_range = colours_in_range_;
            }
            sc = fused(f);
            // Last colours: the step's plotted points (the dummy bin holds the others), each the
            // colour of its map, which the step left in `prev` (map rule only: see setup_fused).
            if (Colour && g_.last_) {
                // (Locals: the stores into the last writes could alias members, read per lane.)
                const uint32_t* prev = c_.prev.get();
                const std::array<uint16_t, 3>* map_q = g_.map_q_.data();
                const uint32_t last_map = none_ - 1;
                write_last_colours(hist_.last.get(), out_, nb_, n, c_.chain.get(), bv_.dummy,
                                   [&](size_t i) { return map_q[std::min(prev[i], last_map)]; });
            }
        }
        steps = ran;
        if (steady) {
            sc.still = uint32_t(live_);
            steady_steps_ += ran;
            steady_left_ -= ran;
            // The end of a steady run: a restart (its chain must wait out its skip again), or as
            // many steps as the block's fewest points left, less one.
            if (steady_left_ == 0 || sc.restarts) {
                jump_streams();
                sc.plotted = c_.settle_steady(nb_, steady_steps_, s_.restart.get());
                steady_left_ = steady_steps_ = 0;
            }
        }
        return sc;
    }

    /// Steps 1-5 through the plugins: 1-3. a map per chain (k: it does not move this step), the
    /// chains grouped by map, one step call per map, back in place; 4. the colours (not when the
    /// colourer needs none); 5. the bookkeeping, bin indices and colour values.
    Counts step_generic(uint64_t n) {
        if (g_.has_xaos_)
            g_.choose_xaos(s_, nb_);
        else if constexpr (Rules)
            g_.choose_rules(s_, nb_);
        else
            g_.choose_alias(s_, nb_);
        g_.move_chains(s_, nb_, n);
        if constexpr (Colour) {
            const uint32_t* __restrict chosen = s_.chosen.get();
            const uint32_t* __restrict age = c_.age.get();
            unsigned char* __restrict moved = s_.moved.get();
            if (g_.last_) {
                // Algorithm 2: the colour changes with the points plotted only (line 16 under "if
                // i > 20"): the chains that move and are past their skip.
                FP_IVDEP
                for (size_t i = 0; i < nb_; ++i) moved[i] = chosen[i] < none_ && age[i] >= bv_.skip ? 1 : 0;
            } else {
                FP_IVDEP
                for (size_t i = 0; i < nb_; ++i) moved[i] = chosen[i] < none_ ? 1 : 0;
            }
            if (g_.steal_) {
                g_.steal(s_, nb_, moved);
            } else {
                fp::ColourState cs{c_.cr.get(), c_.cg.get(), c_.cb.get(), nb_};
                if (g_.palette_) {
                    cs.index = c_.ci.get();
                    cs.map_index = g_.map_index_.data();
                    cs.map_speed = g_.map_speed_.data();
                }
                g_.colourer_->update(chosen, cs, g_.colours_.data(), moved);
            }
            colours_in_range_ = false; // (a colourer's rule: no promise of its range)
        }
        const Counts sc = g_.has_finals_ ? bookkeep_finals(n) : bookkeep(bv_, Colour);
        if (g_.has_opacity_) g_.hide(s_, nb_, n, bv_.dummy);
        if (Colour && g_.last_) {
            const uint64_t* dep = s_.dep.get();
            write_last_colours(
                hist_.last.get(), s_.idx.get(), nb_, n, c_.chain.get(), bv_.dummy, [&](size_t i) {
                    const uint64_t v = dep[i]; // {1, r, g, b} in 16 bits each
                    return std::array<uint16_t, 3>{uint16_t(v >> 16), uint16_t(v >> 32), uint16_t(v >> 48)};
                });
        }
        return sc;
    }

    /// The bookkeeping of a recipe with final maps or a camera: of the plotted points and
    /// colours (ChaosGame::finals), the chains' own left as they are. A chain whose plotted point
    /// is not finite restarts, as one whose own point is not.
    Counts bookkeep_finals(uint64_t n) {
        g_.finals(s_, nb_, n, Colour);
        BookArgs<T> b = bv_;
        b.x = s_.fx.get(), b.y = s_.fy.get();
        if constexpr (Colour) b.cr = s_.fr.get(), b.cg = s_.fg.get(), b.cb = s_.fb.get();
        return bookkeep(b, Colour);
    }

    /// 6. The deposit: one 4 x 32-bit add per chain (or one 16-bit tally), or one 32-bit increment
    /// when counting hits only; the unplotted land in the dummy bin. The fused step's are made by
    /// the next pass (lagged), the bins it found full spilled now.
    void deposit(bool fused, uint64_t steps) {
        const uint32_t* idx = s_.idx.get();
        if constexpr (Colour) {
            if (fused) {
                for (uint32_t t = 0; t < nfull_; ++t)
                    if (hist_.due(s_.full.get()[t])) hist_.spill(s_.full.get()[t]);
                nfull_ = 0;
                lag_ = out_;
                lag_dep_ = dep_out_;
                out_ = out_ == s_.idx.get() ? s_.idx2.get() : s_.idx.get();
                dep_out_ = dep_out_ == s_.dep.get() ? s_.dep2.get() : s_.dep.get();
            } else if (hist_.tallies) {
                // (The plotted points' maps are their colours.)
                for (size_t i = 0; i < nb_; ++i) {
                    i = hist_.tally(idx, s_.chosen.get(), i, nb_);
                    if (i < nb_) hist_.spill(idx[i]);
                }
            } else {
                uint32_t* const b32 = reinterpret_cast<uint32_t*>(hist_.bins.get());
                for (size_t i = 0; i < nb_; ++i) {
                    i = deposit_colours(b32, idx, s_.dep.get(), i, nb_, spill_hits);
                    if (i < nb_) hist_.spill(idx[i]);
                }
            }
        } else {
            if (lean_) {
                // (deposited by the lean run itself)
            } else if (fused) {
                lag_ = out_;
                out_ = out_ == s_.idx.get() ? s_.idx2.get() : s_.idx.get();
            } else {
                uint32_t* const hits = hist_.hits.get();
                for (size_t i = 0; i < nb_; ++i) {
                    FP_DCHECK(idx[i] <= hist_.dummy);
                    ++hits[idx[i]];
                }
            }
            hist_.since += nb_ * steps;
            if (__builtin_expect(hist_.since >= hits_flush, 0)) hist_.flush();
        }
    }

    /// 7. Restarts (rare): a fresh start point, or retirement after too many in a row without a
    /// plotted point.
    void restart() {
        uint32_t* list = s_.perm.get();
        const uint32_t* restart = s_.restart.get();
        uint32_t* active = c_.active.get();
        size_t m = 0;
        for (size_t i = 0; i < nb_; ++i) {
            if (!restart[i]) continue;
            ++t_.res.restarts;
            if (++c_.idle.get()[i] > max_idle_restarts) {
                if (active[i]) --live_;
                active[i] = 0;
                c_.left.get()[i] = 0;
                continue;
            }
            if (!active[i]) continue; // finished with its last point (cannot happen: bad)
            c_.prev.get()[i] = none_;
            c_.age.get()[i] = g_.restart_age_;
            list[m++] = uint32_t(i);
        }
        g_.new_starts(s_, list, m);
    }

    /// 8. A checkpointed render records each chain's final state as it finishes or retires (for
    /// a render continued to more points), `step` the step it would run next.
    void keep_finals(uint64_t step) {
        for (size_t i = 0; i < nb_; ++i) {
            if (c_.active.get()[i] || c_.fin.get()[i]) continue;
            FP_DCHECK(c_.chain.get()[i] < keep_->finals.size());
            keep_->finals[c_.chain.get()[i]] = c_.record(i, step);
            c_.fin.get()[i] = 1;
        }
    }

    /// The fused step's lagged deposits made now (at the block's end, or where it stops for a
    /// checkpoint or takes a generic step).
    void deposit_lag() {
        if (lag_ && Colour && hist_.tallies) {
            for (size_t i = 0; i < nb_; ++i) {
                i = hist_.tally(reinterpret_cast<const uint32_t*>(lag_dep_), i, nb_);
                if (i < nb_) hist_.spill(lag_[i]);
            }
        } else if (lag_ && Colour) {
            uint32_t* const b32 = reinterpret_cast<uint32_t*>(hist_.bins.get());
            for (size_t i = 0; i < nb_; ++i) {
                i = deposit_colours(b32, lag_, lag_dep_, i, nb_, spill_hits);
                if (i < nb_) hist_.spill(lag_[i]);
            }
        } else if (lag_) {
            uint32_t* const hits = hist_.hits.get();
            for (size_t i = 0; i < nb_; ++i) ++hits[lag_[i]];
        }
        lag_ = nullptr;
        lag_dep_ = nullptr;
    }

    /// The end of a steady run before it ran its course (a checkpoint, or a step the fused step
    /// cannot take): the state the step-by-step bookkeeping would hold, as at its end; the last
    /// step's restarts, none, are cleared for settle_steady.
    void end_steady() {
        if (steady_steps_ > 0) {
            jump_streams();
            std::memset(static_cast<void*>(s_.restart.get()), 0, nb_ * sizeof(uint32_t));
            t_.res.plotted += c_.settle_steady(nb_, steady_steps_, s_.restart.get());
        }
        steady_left_ = steady_steps_ = 0;
    }

    /// One map without the rules: the kernels left the streams where the steady run began (see
    /// fused_t); they move on by its length now, before any restart draws from them.
    void jump_streams() {
        const LaneTables<T>& lt = g_.lane_tables<T, Colour>();
        if (lt.k == 1 && !lt.rules) pcg_jump(c_.rs.get(), c_.ri.get(), nb_, steady_steps_);
    }

    /// A block step in fused-inl.hpp's pass: the draw, the maps, the colours and the bookkeeping.
    FusedArgs<T> fused_args(const uint32_t* lag, bool steady) const {
        FusedArgs<T> f;
        f.tables = &g_.lane_tables<T, Colour>();
        f.draw = s_.draw_args(bv_.nb, none_);
        f.book = bv_;
        f.hits = hist_.hits.get();
        f.lag = lag;
        f.steady = steady;
        return f;
    }

    void report(uint64_t units) {
        ctx_.progress(units);
        if (keep_) keep_->progress.fetch_add(units, std::memory_order_relaxed);
    }

    const ChaosGame& g_;
    Task& t_;
    Scratch<T>& s_;
    Chains<T>& c_;
    WorkerHist& hist_;
    fp::RenderContext& ctx_;
    Keeping* const keep_;
    const size_t nb_;
    const uint32_t none_; ///< k: "no map"
    BookArgs<T> bv_;      ///< the bookkeeping's arrays and the constants of the deposit
    uint64_t nominal_ = 0, reported_ = 0, n0_ = 0;
    size_t nlive_ = 0, live_ = 0;
    /// Whether every chain's colour lies in [0, 1] (FusedArgs::colours_in_range): the fused step
    /// keeps them there; a colourer's own update ends the promise for the block.
    bool colours_in_range_ = true;
    // The fused step deposits each step's bins during the next step's pass (the increments'
    // cache misses then overlap its arithmetic instead of following it): `out_` takes this
    // step's bins, `lag_` holds the previous step's, deposited by the pass. With colour, the
    // packed colours go the same way: `dep_out_` and `lag_dep_`.
    uint32_t* out_;
    const uint32_t* lag_ = nullptr;
    uint64_t* dep_out_;
    const uint64_t* lag_dep_ = nullptr;
    uint32_t nfull_ = 0;
    // The fused step's steady runs (fused_t with Steady): steps the block may still run that way
    // (0: not in one), the steps run since the run began, and steps before asking again.
    uint64_t steady_left_ = 0, steady_steps_ = 0, steady_wait_ = 0;
    const bool lean_;
};

template <class T>
bool ChaosGame::run_block(Task& t, Scratch<T>& s, WorkerHist& hist, fp::RenderContext& ctx, uint32_t row0,
                          uint32_t rows, bool colour, Keeping* keep) const {
    if (rules_ && colour) return Block<T, true, true>(*this, t, s, hist, ctx, row0, rows, keep).run();
    if (rules_) return Block<T, true, false>(*this, t, s, hist, ctx, row0, rows, keep).run();
    if (colour) return Block<T, false, true>(*this, t, s, hist, ctx, row0, rows, keep).run();
    return Block<T, false, false>(*this, t, s, hist, ctx, row0, rows, keep).run();
}

template bool ChaosGame::run_block<float>(Task&, Scratch<float>&, WorkerHist&, fp::RenderContext&, uint32_t,
                                          uint32_t, bool, Keeping*) const;
template bool ChaosGame::run_block<double>(Task&, Scratch<double>&, WorkerHist&, fp::RenderContext&, uint32_t,
                                           uint32_t, bool, Keeping*) const;

} // namespace fp_chaos
