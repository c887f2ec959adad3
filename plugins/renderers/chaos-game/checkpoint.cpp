// chaos-game's checkpoints (checkpoint.hpp says what a payload holds and why a render can stop
// and go on anywhere between two steps): the payload written at each checkpoint, and a resumed
// render's state read back from one, every field bounded by the recipe.
#include "chaos-game/checkpoint.hpp"
#include "chaos-game/renderer.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace fp_chaos {

template <class T>
void ChaosGame::save(fp::RenderContext& ctx, const std::vector<Task>& tasks, const Keeping& keep,
                     const fp::Histogram& total, const std::vector<LastWrite>& last,
                     const BlockResult& base) const {
    PayloadHead head;
    head.precision = uint32_t(sizeof(T));
    head.points = points_, head.chains = chains_;
    head.width = uint32_t(hist_.width), head.rows = uint32_t(total.height);
    head.colour = colour_ ? 1 : 0, head.last = last.empty() ? 0 : 1;
    head.samples = base.plotted, head.restarts = base.restarts, head.bad = base.bad;
    for (const Task& t : tasks) {
        head.samples += t.res.plotted, head.restarts += t.res.restarts, head.bad += t.res.bad;
        if (!t.done) ++head.tasks;
    }
    head.progress = keep.progress.load();
    for (const ChainRec& c : keep.finals) head.finals += c.step != not_final ? 1 : 0;
    ctx.write_checkpoint([&](fp::CheckpointSink& out) {
        out.write(&head, sizeof head);
        for (const Task& t : tasks) {
            if (t.done) continue;
            // Saved chains (stopped mid-way), or fresh ones (never started: their ids).
            const uint64_t kind = t.saved.empty() ? 0 : 1, n = t.size();
            out.write(&kind, 8);
            out.write(&n, 8);
            if (kind == 1) {
                out.write(t.saved.data(), n * sizeof(ChainRec));
            } else {
                std::vector<uint32_t> ids(n);
                for (size_t i = 0; i < n; ++i) ids[i] = t.chain(i);
                out.write(ids.data(), n * sizeof(uint32_t));
            }
        }
        for (const ChainRec& c : keep.finals)
            if (c.step != not_final) out.write(&c, sizeof c);
        out.write(total.bins.data(), total.bins.size() * sizeof(fp::HistBin));
        if (!last.empty()) out.write(last.data(), last.size() * sizeof(LastWrite));
    });
}

template <class T>
void ChaosGame::resume(fp::CheckpointSource& in, std::vector<Task>& tasks, Keeping& keep,
                       fp::Histogram& total, std::vector<LastWrite>& last, BlockResult& base,
                       const std::vector<Span>& mine) const {
    PayloadHead head;
    in.read(&head, sizeof head);
    // The envelope matched the recipe (but points): these only fail for a damaged payload.
    if (head.version != PayloadHead{}.version || head.precision != sizeof(T) || head.chains != chains_ ||
        head.width != uint32_t(hist_.width) || head.rows != uint32_t(total.height) ||
        head.colour != (colour_ ? 1u : 0u) || head.last != (last.empty() ? 0u : 1u) ||
        head.points > points_ || head.tasks > chains_ || head.finals > chains_)
        throw fp::InputError("the checkpoint's payload does not fit this render (damaged?)");
    base.plotted = head.samples, base.restarts = head.restarts, base.bad = head.bad;
    keep.progress.store(head.progress);
    // The points each chain gains over the checkpoint's.
    const auto more = [&](uint64_t chain) {
        return points_of(chain, points_, chains_) - points_of(chain, head.points, chains_);
    };
    // Every field bounded by the recipe: a forged payload (its CRC recomputed) must not make a
    // resume run longer than the render it claims to continue, nor read out of its arrays.
    // Each chain is in the payload once: pending (fresh, or suspended and running) or final.
    // (A shard's payload holds its own chains alone: the others count as seen, and naming one
    // is naming it twice.)
    std::vector<uint8_t> seen(chains_, 1);
    for (const Span& sp : mine) std::fill_n(seen.begin() + std::ptrdiff_t(sp.c0), sp.nb, uint8_t(0));
    const auto check_chain = [&](uint64_t chain) {
        if (chain >= chains_)
            throw fp::InputError("the checkpoint's payload names a chain that does not exist");
        if (seen[chain]++) throw fp::InputError("the checkpoint's payload names a chain twice (damaged?)");
    };
    const auto check_state = [&](const ChainRec& c) {
        if (c.left > points_of(c.chain, head.points, chains_) || c.prev > maps_.size() || c.active > 1)
            throw fp::InputError(
                "the checkpoint's payload holds a chain state this render cannot have (damaged?)");
    };
    std::vector<uint32_t> fresh;
    for (uint64_t t = 0; t < head.tasks; ++t) {
        uint64_t kind = 0, n = 0;
        in.read(&kind, 8);
        in.read(&n, 8);
        if (kind > 1 || n > block_size) throw fp::InputError("the checkpoint's payload is damaged");
        if (kind == 0) {
            std::vector<uint32_t> ids(n);
            in.read(ids.data(), n * sizeof(uint32_t));
            for (uint32_t c : ids) check_chain(c), fresh.push_back(c);
            continue;
        }
        Task task;
        task.saved.resize(n);
        in.read(task.saved.data(), n * sizeof(ChainRec));
        // The lanes still running, with the points they gain; those that finished are in the
        // final states.
        std::vector<ChainRec> running;
        for (ChainRec c : task.saved) {
            if (c.chain >= chains_)
                throw fp::InputError("the checkpoint's payload names a chain that does not exist");
            check_state(c);
            if (!c.active) continue; // (recorded again among the final states)
            check_chain(c.chain);
            c.left += more(c.chain);
            running.push_back(c);
        }
        task.saved = std::move(running);
        if (!task.saved.empty()) tasks.push_back(std::move(task));
    }
    // Finished chains: final, or, with more points now, running on from their next step, in
    // blocks of chains at the same step (a chain that never had a point starts fresh).
    std::vector<ChainRec> again;
    for (uint64_t f = 0; f < head.finals; ++f) {
        ChainRec c;
        in.read(&c, sizeof c);
        check_chain(c.chain);
        check_state(c);
        const uint64_t gain = c.idle > max_idle_restarts ? 0 : more(c.chain);
        if (gain == 0) {
            keep.finals[c.chain] = c;
        } else if (c.step == 0) {
            fresh.push_back(c.chain);
        } else {
            c.left = gain;
            c.active = 1;
            again.push_back(c);
        }
    }
    std::stable_sort(again.begin(), again.end(),
                     [](const ChainRec& a, const ChainRec& b) { return a.step < b.step; });
    for (size_t i = 0; i < again.size();) {
        Task task;
        const uint64_t step = again[i].step;
        while (i < again.size() && again[i].step == step && task.saved.size() < block_size)
            task.saved.push_back(again[i++]);
        tasks.push_back(std::move(task));
    }
    for (size_t i = 0; i < fresh.size(); i += block_size) {
        Task task;
        task.ids.assign(fresh.begin() + std::ptrdiff_t(i),
                        fresh.begin() + std::ptrdiff_t(std::min(fresh.size(), i + block_size)));
        tasks.push_back(std::move(task));
    }
    if (std::find(seen.begin(), seen.end(), uint8_t(0)) != seen.end())
        throw fp::InputError("the checkpoint's payload leaves a chain out (damaged?)");
    in.read(total.bins.data(), total.bins.size() * sizeof(fp::HistBin));
    if (!last.empty()) in.read(last.data(), last.size() * sizeof(LastWrite));
    if (in.left() != 0) throw fp::InputError("the checkpoint's payload is longer than this render's state");
}

template void ChaosGame::save<float>(fp::RenderContext&, const std::vector<Task>&, const Keeping&,
                                     const fp::Histogram&, const std::vector<LastWrite>&,
                                     const BlockResult&) const;
template void ChaosGame::save<double>(fp::RenderContext&, const std::vector<Task>&, const Keeping&,
                                      const fp::Histogram&, const std::vector<LastWrite>&,
                                      const BlockResult&) const;
template void ChaosGame::resume<float>(fp::CheckpointSource&, std::vector<Task>&, Keeping&, fp::Histogram&,
                                       std::vector<LastWrite>&, BlockResult&, const std::vector<Span>&) const;
template void ChaosGame::resume<double>(fp::CheckpointSource&, std::vector<Task>&, Keeping&, fp::Histogram&,
                                        std::vector<LastWrite>&, BlockResult&,
                                        const std::vector<Span>&) const;

} // namespace fp_chaos
