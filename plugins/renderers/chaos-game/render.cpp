// The chaos-game render: the whole image (render, with the sets drawn over or beside it, or the
// sets alone as a vector document), and the histogram of a pass (render_t): the workers take
// blocks of chains (chaos-game/block.cpp runs them) into histograms of their own, which are summed
// into one fp::Histogram in a fixed order of exact integer sums, so the image is the same bytes on
// any number of threads; over MPI ranks the blocks are dealt and the ranks' histograms summed the
// same way. A checkpointed render goes in rounds (chaos-game/checkpoint.cpp).
#include "chaos-game/buffers.hpp"
#include "chaos-game/chains.hpp"
#include "chaos-game/checkpoint.hpp"
#include "chaos-game/histogram.hpp"
#include "chaos-game/renderer.hpp"
#include "chaos-game/sets.hpp"

#include <fixpoint/check.hpp>
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace fp_chaos {

void ChaosGame::draw_set_panel(cairo_t* cr) const {
    cairo_set_source_rgb(cr, frame_.background.r, frame_.background.g, frame_.background.b);
    cairo_paint(cr);
    // (The sets' own view: set_view, or by default the sets whole; chaos-game.cpp fits it.)
    draw_sets(cr, set_drawings_, set_view_.value_or(frame_.region), frame_.width, frame_.height, set_style_);
}

std::string ChaosGame::render_vector(fp::RenderContext& ctx, fp::RenderStats& stats, fp::VectorFormat format,
                                     const std::string& recipe) const {
    if (sets_ != Sets::only) return fp::Renderer::render_vector(ctx, stats, format, recipe);
    stats = fp::RenderStats{};
    stats.samples = set_drawings_.size();
    stats.unit = "sets";
    std::string doc = fp_render::cairo_document(frame_.width, frame_.height, format == fp::VectorFormat::Pdf,
                                                recipe, &ctx, [&](cairo_t* cr) { draw_set_panel(cr); });
    if (doc.empty()) throw fp::InternalError("chaos-game: Cairo could not write the sets");
    ctx.progress(1);
    return doc;
}

fp::Image ChaosGame::render(fp::RenderContext& ctx, fp::RenderStats& stats) const {
    stats = fp::RenderStats{};
    if (sets_ == Sets::only) {
        // The sets alone: no chain runs.
        stats.samples = set_drawings_.size();
        stats.unit = "sets";
        fp::Image img;
        img.width = frame_.width;
        img.height = frame_.height;
        img.pixels =
            fp_render::cairo_raster(frame_.width, frame_.height, [&](cairo_t* cr) { draw_set_panel(cr); });
        ctx.progress(1);
        return img;
    }
    fp::Image img;
    img.width = frame_.width;
    img.height = frame_.height;
    img.channels = 3;
    const uint32_t H = uint32_t(hist_.height);
    fp::Histogram total;
    if (double_)
        render_t<double>(ctx, stats, total, &img.pixels, 0, H, colour_, colourer_->reads_hits_only());
    else
        render_t<float>(ctx, stats, total, &img.pixels, 0, H, colour_, colourer_->reads_hits_only());
    if (ctx.cancelled()) throw fp::Cancelled();
    if (ctx.shard()) {
        // A shard's histogram is what it makes: `fixpoint merge` sums the shards and finishes.
        if (ctx.keeps_histogram()) ctx.keep_histogram(total, 0, 0, total.height);
        return img;
    }
    if (ctx.rank() != 0) return img; // its share is in rank 0's histogram, which rank 0 resolves
    if (ctx.keeps_histogram()) ctx.keep_histogram(total, 0, 0, total.height);
    // (The image's buffer, made beside the chains, is the one image_of fills.)
    return image_of(total, ctx, std::move(img.pixels));
}

fp::HistogramShape ChaosGame::histogram_shape() const {
    if (sets_ == Sets::only) return {};
    return fp::HistogramShape{hist_.width, hist_.height, !colour_, colour_ && last_};
}

fp::Image ChaosGame::finish_histogram(const fp::Histogram& h, const fp::RenderStats&,
                                      fp::RenderContext& ctx) const {
    const fp::HistogramShape shape = histogram_shape();
    if (h.width != shape.width || h.height != shape.height || (!shape.hits_only && h.bins.empty()) ||
        (shape.last && h.last.size() != h.size()))
        throw fp::InternalError("chaos-game: a histogram of another shape to finish");
    // Hits alone for a colourer that reads more: bins with those hits and no colour (the sums
    // a render without colour makes).
    if (!h.hits.empty() && !colourer_->reads_hits_only()) {
        fp::Histogram bins;
        bins.width = h.width, bins.height = h.height;
        bins.bins.resize(h.hits.size());
        for (size_t i = 0; i < h.hits.size(); ++i) bins.bins[i].hits = h.hits[i];
        return image_of(bins, ctx, {});
    }
    return image_of(h, ctx, {});
}

double ChaosGame::density() const {
    // 1 / (points drawn * a histogram bin's area in the view's units), flam3's k2 but for its
    // constants (the points outside the view count, as flam3's samples do).
    if (!frame_.has_region) return 0;
    const fp::Box& v = frame_.region;
    const double bin = (v.xmax - v.xmin) * (v.ymax - v.ymin) / (double(hist_.width) * double(hist_.height));
    return 1.0 / (double(points_) * bin);
}

fp::Image ChaosGame::image_of(const fp::Histogram& total, fp::RenderContext& ctx,
                              std::vector<float> pixels) const {
    fp::Image img;
    img.width = frame_.width;
    img.height = frame_.height;
    img.channels = 3;
    img.pixels = std::move(pixels);
    img.pixels.resize(size_t(frame_.width) * size_t(frame_.height) * 3);
    // The summary with the density of the points drawn (flam3's tone reads it): resolve_rows
    // takes it, and gives resolve_parallel's bytes by its contract.
    fp::HistogramSummary whole = fp::HistogramSummary::of(total, &ctx);
    whole.density = density();
    if (finish_.active())
        fp::finish(finish_, *colourer_, total, 0, whole, frame_.width, 0, frame_.height, frame_.background,
                   img.pixels.data(), &ctx);
    else if (colourer_->resolves_rows())
        colourer_->resolve_rows(total, 0, whole, frame_.background, img.pixels.data(), ctx);
    else
        colourer_->resolve_parallel(total, frame_.background, img.pixels.data(), ctx);
    auto draw = [&](cairo_t* cr) {
        draw_sets(cr, set_drawings_, frame_.region, frame_.width, frame_.height, set_style_);
    };
    if (sets_ == Sets::over) fp_render::cairo_over(frame_.width, frame_.height, img.pixels.data(), draw);
    if (sets_ == Sets::beside) {
        // The sets on the left, the fractal's own pixels (unchanged) on the right.
        const std::vector<float> left =
            fp_render::cairo_raster(frame_.width, frame_.height, [&](cairo_t* cr) { draw_set_panel(cr); });
        const size_t row = size_t(frame_.width) * 3;
        std::vector<float> both(2 * row * size_t(frame_.height));
        for (size_t r = 0; r < size_t(frame_.height); ++r) {
            std::copy_n(left.data() + r * row, row, both.data() + 2 * r * row);
            std::copy_n(img.pixels.data() + r * row, row, both.data() + (2 * r + 1) * row);
        }
        img.pixels = std::move(both);
        img.width = 2 * frame_.width;
    }
    return img;
}

template <class T>
void ChaosGame::render_t(fp::RenderContext& ctx, fp::RenderStats& stats, fp::Histogram& total,
                         std::vector<float>* pixels, uint32_t row0, uint32_t rows, bool colour,
                         bool hits_total) const {
    const unsigned workers = std::max(1u, ctx.workers());
    const size_t px = size_t(hist_.width) * size_t(rows);
    const bool last = colour && last_;
    // Over several ranks (MPI), the blocks are cut the same way on every rank whatever its
    // thread count (as for 2 workers a rank), and rank r runs blocks r, r + N, r + 2N, ...;
    // each chain runs on exactly one rank, with its own stream, so the sums are the same.
    const unsigned rank = ctx.rank(), ranks = std::max(1u, ctx.ranks());
    std::vector<Span> spans = block_spans(chains_, ranks > 1 ? 2 * ranks : workers);
    if (ranks > 1) {
        std::vector<Span> mine;
        for (size_t b = rank; b < spans.size(); b += ranks) mine.push_back(spans[b]);
        spans = std::move(mine);
    }
    // A checkpointed render (`--checkpoint`, `--resume`; whole renders: the host refuses strips)
    // keeps the chains' final states and stops for each checkpoint. Over ranks, and in a shard,
    // each keeps its own share's: nothing in the rounds is collective.
    std::unique_ptr<Keeping> keeping;
    if (ctx.checkpointing() || ctx.resume_from()) {
        if (row0 != 0 || rows != uint32_t(hist_.height))
            throw fp::InputError("checkpoints are kept of a whole render (not in strips)");
        keeping = std::make_unique<Keeping>();
        keeping->finals.assign(chains_, ChainRec{0, 0, 0, 0, not_final, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
    }
    Keeping* keep = keeping.get();
    // The total as hit counts alone (8 bytes a bin, not 32): a quarter of the memory to fault
    // in, fold, summarise and shade.
    const bool hits8 = hits_total && !colour && !keep;
    std::vector<Task> work;
    // The bins' last writes a checkpoint has folded (pixel rule last), and the stats of the
    // work it holds.
    std::vector<LastWrite> folded_last;
    BlockResult base;
    const auto poll = [&ctx] {
        if (ctx.cancelled()) throw fp::Cancelled();
    };
    if (keep) {
        // The histogram first (a resumed one is read into it).
        total.width = hist_.width;
        total.height = int(rows);
        assign_huge(total.bins, px, poll);
        if (last) {
            assign_huge(total.last, px, poll);
            folded_last.assign(px, LastWrite{0, 0, 0, 0, 0, 0});
        }
    }
    if (fp::CheckpointSource* in = ctx.resume_from()) {
        resume<T>(*in, work, *keep, total, folded_last, base, spans);
        ctx.progress(keep->progress.load());
    } else {
        for (const Span& sp : spans) {
            Task t;
            t.c0 = sp.c0;
            t.nb = sp.nb;
            work.push_back(std::move(t));
        }
    }
    // Per worker: its block state and its histogram (one extra bin that takes the points not
    // plotted), both made by the worker itself on its first task (first touch).
    std::vector<std::unique_ptr<Scratch<T>>> scratch(workers);
    std::vector<WorkerHist> hists(workers);

    // One task per worker; each takes the next item of the work list until none is left, in
    // order: item 0 allocates the total histogram, item 1 the image (tens of MiB of fresh
    // pages: page faults and zeroing, serial work that would otherwise follow the chains on
    // one thread; first, so that two workers take one each), then the blocks, the large ones
    // first. Which worker runs which block does not change the image (exact merge). A
    // checkpointed render goes in rounds: when a checkpoint is due, each worker stops its block
    // at the next poll and takes no other; the workers' histograms are folded into the total,
    // the checkpoint written, and the next round continues the blocks where they stopped.
    for (bool first = true;; first = false) {
        std::atomic<size_t> next{0};
        const size_t head = first ? 2 : 0, items = work.size() + head;
        if (keep) keep->stop.store(false);
        ctx.parallel_for(workers, [&](size_t, unsigned w) {
            if (w >= workers) throw fp::InternalError("chaos-game: worker index out of range");
            for (size_t it; (it = next.fetch_add(1, std::memory_order_relaxed)) < items;) {
                if (ctx.cancelled()) throw fp::Cancelled();
                if (it == 0 && head) {
                    if (keep) continue; // (made above)
                    total.width = hist_.width;
                    total.height = int(rows);
                    if (hits8)
                        assign_huge(total.hits, px, poll);
                    else
                        assign_huge(total.bins, px, poll);
                    if (last) assign_huge(total.last, px, poll);
                    continue;
                }
                if (it == 1 && head) {
                    if (pixels) assign_huge(*pixels, size_t(frame_.width) * size_t(frame_.height) * 3, poll);
                    continue;
                }
                if (keep && keep->stop.load(std::memory_order_relaxed)) return;
                Task& t = work[it - head];
                if (t.done) continue;
                if (!scratch[w])
                    scratch[w] = std::make_unique<Scratch<T>>(maps_.size(), has_finals_, random_maps_);
                if (!hists[w].bins.get() && !hists[w].hits.get())
                    hists[w].alloc(px, colour, last, tallies_.get(), poll);
                t.done = run_block<T>(t, *scratch[w], hists[w], ctx, row0, rows, colour, keep);
                if (!t.done) return; // stopped for a checkpoint
            }
        });
        if (!keep) break;
        // Every task done: the last checkpoint holds the finished render (to continue to more
        // points); else the one that is due.
        fold(ctx, hists, total, folded_last, px);
        const bool finished = std::all_of(work.begin(), work.end(), [](const Task& t) { return t.done; });
        save<T>(ctx, work, *keep, total, folded_last, base);
        if (finished) break;
    }
    scratch.clear();

    stats.samples = base.plotted;
    stats.restarts = base.restarts;
    stats.bad_values = base.bad;
    for (const auto& t : work) {
        stats.samples += t.res.plotted;
        stats.restarts += t.res.restarts;
        stats.bad_values += t.res.bad;
    }
    stats.unit = "points";

    // (A checkpointed render folded them into the total for its last checkpoint.)
    if (keep) hists.clear();
    // Over several ranks with last colours: this rank's winning (step, chain) per bin, for the
    // ranks' merge by the same order.
    // A shard keeps their order in its histogram instead, for the merge (16 bytes a bin, not
    // 24 more beside it: fresh pages cost).
    std::vector<LastWrite> rank_last(ranks > 1 && !ctx.shard() && last ? px : 0);
    if (ctx.shard() && last) assign_huge(total.last_order, px, poll);
    sum_workers(ctx, stats, hists, total, folded_last, rows, hits8, last, rank_last);
    if (ranks > 1 && !ctx.shard()) combine_ranks(ctx, stats, total, rank_last);
}

void ChaosGame::sum_workers(fp::RenderContext& ctx, fp::RenderStats& stats, std::vector<WorkerHist>& hists,
                            fp::Histogram& total, const std::vector<LastWrite>& folded_last,
                            const uint32_t rows, const bool hits8, const bool last,
                            std::vector<LastWrite>& rank_last) const {
    const size_t px = size_t(hist_.width) * size_t(rows);
    const auto poll = [&ctx] {
        if (ctx.cancelled()) throw fp::Cancelled();
    };
    // Sum the workers' histograms (exact integer sums; rows in parallel).
    const size_t rows_per_task = 16;
    const size_t tasks = (size_t(rows) + rows_per_task - 1) / rows_per_task;
    // The hits of each task's rows, summed here rather than in a serial pass over the 32 MiB
    // of the total afterwards (part of the fixed cost that limits the speed-up on 2 threads).
    std::vector<uint64_t> drawn(tasks, 0);
    ctx.parallel_for(tasks, [&](size_t t, unsigned) {
        poll();
        const size_t b0 = t * rows_per_task * size_t(hist_.width);
        const size_t b1 = std::min(px, b0 + rows_per_task * size_t(hist_.width));
        if (hits8) {
            uint64_t* out = total.hits.data();
            for (auto& h : hists) h.add_hits_to(out, b0, b1);
            uint64_t d = 0;
            for (size_t i = b0; i < b1; ++i) d += out[i];
            drawn[t] = d;
            return;
        }
        fp::HistBin* out = total.bins.data();
        for (auto& h : hists) h.add_to(out, b0, b1, false);
        if (last) {
            // Each bin's last colour: the workers' entry with the largest (step, chain).
            for (size_t i = b0; i < b1; ++i) {
                LastWrite best = folded_last.empty() ? LastWrite{0, 0, 0, 0, 0, 0} : folded_last[i];
                for (const auto& h : hists) {
                    const LastWrite* lw = h.last.get();
                    if (!lw) continue;
                    const LastWrite& e = lw[i];
                    if (later(e, best)) best = e;
                }
                total.last[i] = fp::LastColour{best.r, best.g, best.b};
                if (!rank_last.empty()) rank_last[i] = best;
                if (!total.last_order.empty()) total.last_order[i] = fp::LastOrder{best.step, best.chain, 0};
            }
        }
        uint64_t d = 0;
        for (size_t i = b0; i < b1; ++i) d += out[i].hits;
        drawn[t] = d;
    });
    // The histogram holds exactly the points that landed in the image.
    stats.drawn = 0;
    for (uint64_t d : drawn) stats.drawn += d;
    for (const auto& h : hists) stats.drawn += h.add_spills_to(total.bins.data());
}

void ChaosGame::fold(fp::RenderContext& ctx, std::vector<WorkerHist>& hists, fp::Histogram& total,
                     std::vector<LastWrite>& last, size_t px) const {
    // Rows of bins in parallel, as the final sum; the spills and the flushed hits after.
    const size_t per = size_t(1) << 16;
    ctx.parallel_for((px + per - 1) / per, [&](size_t t, unsigned) {
        const size_t b0 = t * per, b1 = std::min(px, b0 + per);
        for (auto& h : hists) {
            h.add_to(total.bins.data(), b0, b1, true);
            if (LastWrite* lw = h.last.get()) {
                for (size_t i = b0; i < b1; ++i) {
                    if (later(lw[i], last[i])) last[i] = lw[i];
                    lw[i] = LastWrite{0, 0, 0, 0, 0, 0};
                }
            }
        }
    });
    for (auto& h : hists) {
        h.add_spills_to(total.bins.data());
        h.spills.clear();
        h.clear_dummy();
        h.since = 0;
    }
}

// The ranks' shares folded into rank 0's (RenderContext::combine): exact sums of the bins and
// the stats, and each bin's last colour from the rank with the largest (step, chain).
void ChaosGame::combine_ranks(fp::RenderContext& ctx, fp::RenderStats& stats, fp::Histogram& total,
                              std::vector<LastWrite>& rank_last) const {
    uint64_t counts[4] = {stats.samples, stats.restarts, stats.bad_values, stats.drawn};
    ctx.combine(counts, sizeof counts, sizeof(uint64_t), fp::fold::sum<uint64_t>, false);
    stats.samples = counts[0], stats.restarts = counts[1], stats.bad_values = counts[2],
    stats.drawn = counts[3];
    // (Folded as plain 64-bit counters: a sum does not care where a bin starts.)
    if (!total.hits.empty())
        ctx.combine(total.hits.data(), total.hits.size() * sizeof(uint64_t), sizeof(uint64_t),
                    fp::fold::sum<uint64_t>, false);
    else
        ctx.combine(total.bins.data(), total.bins.size() * sizeof(fp::HistBin), sizeof(uint64_t),
                    fp::fold::sum<uint64_t>, false);
    if (rank_last.empty()) return;
    ctx.combine(
        rank_last.data(), rank_last.size() * sizeof(LastWrite), sizeof(LastWrite),
        [](const void* in, void* inout, size_t n) {
            const auto* a = static_cast<const LastWrite*>(in);
            auto* b = static_cast<LastWrite*>(inout);
            for (size_t i = 0; i < n; ++i)
                if (later(a[i], b[i])) b[i] = a[i];
        },
        false);
    for (size_t i = 0; i < rank_last.size(); ++i)
        total.last[i] = fp::LastColour{rank_last[i].r, rank_last[i].g, rank_last[i].b};
}

template void ChaosGame::render_t<float>(fp::RenderContext&, fp::RenderStats&, fp::Histogram&,
                                         std::vector<float>*, uint32_t, uint32_t, bool, bool) const;
template void ChaosGame::render_t<double>(fp::RenderContext&, fp::RenderStats&, fp::Histogram&,
                                          std::vector<float>*, uint32_t, uint32_t, bool, bool) const;

} // namespace fp_chaos
