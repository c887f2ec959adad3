// chaos-game's memory: the bytes a whole render takes (the workers' histograms, the total, the
// image, the block state), and a render in strips when they do not fit the memory budget.
//
// Strips (an image whose histogram and pixels do not fit the memory budget,
// RenderContext::memory_budget: `fixpoint render --memory`, else what the machine has
// available; the host then calls render_rows): the image is cut into strips of rows, and every
// chain runs in full once per strip, binning only the points whose row is in the strip (the
// rest go to the dummy bin), so each strip's bins get exactly the sums one pass would give
// them. The colourer needs the whole histogram's summary (largest hit count, centre of mass,
// per-row extents: fp::HistogramSummary) before it shades any strip, so a first pass counts
// hits only, in strips of its own (4 bytes a bin per worker: usually far fewer strips), and
// adds up the summary; the second pass bins the colours strip by strip, shades each with
// Colourer::resolve_rows and hands its rows to the host, which encodes them into the output
// file as they come (fp::RowSink): neither the histogram nor the image is ever whole. Same
// bytes as one pass; the price is the chains run once per strip of each pass (plan). Ranks
// split every strip's chains as they split a whole render's. (Not with the sets drawn over or
// beside: those draw on the whole picture.)
#include "chaos-game/chains.hpp"
#include "chaos-game/histogram.hpp"
#include "chaos-game/renderer.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace fp_chaos {

uint64_t ChaosGame::work_units() const {
    if (sets_ == Sets::only) return 1;
    const uint64_t live = std::min(chains_, points_); // chains with at least one point
    return live * skip_ + points_;
}

uint64_t ChaosGame::strip_bytes(unsigned workers, uint64_t rows, bool colour, bool hits_total) const {
    const uint64_t px = uint64_t(hist_.width) * rows;
    // The workers' 32-bit histograms, the total, the spill lists (at most one entry per
    // 65536 points); hits only: 32-bit counters, and 64-bit ones once a worker could
    // have deposited hits_flush points, and a total of hit counts alone with hits_total.
    const uint64_t deposits = points_ + std::min(chains_, points_) * skip_;
    const uint64_t bins = tallies_ ? tally_bins(tallies_->k, px) : px + 1;
    const uint64_t hist =
        colour ? uint64_t(workers) * (bins * sizeof(Cnt4) + (2u << 20)) + px * sizeof(fp::HistBin) +
                     (points_ / spill_hits + uint64_t(workers) * 256) * 48
               : uint64_t(workers) * ((px + 1) * 4 + (2u << 20) + (deposits >= hits_flush ? px * 8 : 0)) +
                     px * (hits_total ? sizeof(uint64_t) : sizeof(fp::HistBin));
    // Last colours: the workers' last writes and the total's colours.
    const uint64_t last = colour && last_ ? uint64_t(workers) * ((px + 1) * sizeof(LastWrite) + (2u << 20)) +
                                                px * sizeof(fp::LastColour)
                                          : 0;
    return hist + last;
}

uint64_t ChaosGame::scratch_bytes(unsigned workers) const {
    return uint64_t(workers) * (double_ ? Scratch<double>::bytes(maps_.size(), has_finals_, random_maps_)
                                        : Scratch<float>::bytes(maps_.size(), has_finals_, random_maps_));
}

uint64_t ChaosGame::memory_bytes(unsigned workers) const {
    const uint64_t px = uint64_t(frame_.width) * uint64_t(frame_.height);
    // (The sets beside: a second picture of the same size, and the two side by side; and the
    // finishing stage's buffers.)
    const uint64_t image = px * 3 * sizeof(float) * (sets_ == Sets::beside ? 3 : 1) +
                           (finish_.active() ? finish_.bytes(frame_.width, frame_.height) : 0) +
                           picture_.rgb.size();
    // (A whole render's total counted as fp::HistBin bins even where it is hit counts alone: a
    // checkpointed render keeps the bins.)
    return strip_bytes(workers, uint64_t(hist_.height), colour_, false) + image + scratch_bytes(workers);
}

ChaosGame::Plan ChaosGame::plan(unsigned workers, uint64_t budget) const {
    // The summary pass's rows are the histogram's; the colour pass's the image's (with the
    // finishing stage, each strip's histogram is its N rows a row and the halo its filter and
    // estimator read: FinishSpec::halo).
    const uint32_t H = uint32_t(hist_.height), image_rows = uint32_t(frame_.height);
    const bool finishing = finish_.active();
    const uint64_t N = uint64_t(finish_.supersample), halo = finishing ? uint64_t(finish_.halo()) : 0;
    // The block state and the summary (two 32-bit columns per row) stay; the strips' bytes grow
    // linearly with their rows, in the colour pass with the strip's pixels (3 floats each).
    const uint64_t fixed = scratch_bytes(workers) + uint64_t(H) * 8;
    const uint64_t pixel_row = uint64_t(frame_.width) * 3 * sizeof(float);
    // The pass that counts hits (the summary) and the pass that shades (colour sums when the
    // colourer needs them, the finishing stage's buffers, and the strip's pixels).
    auto bytes = [&](uint64_t rows, bool shading) {
        if (!shading) return strip_bytes(workers, rows, false, true);
        const uint64_t hist_rows = finishing ? std::min<uint64_t>(H, rows * N + 2 * halo) : rows;
        return strip_bytes(workers, hist_rows, colour_, colourer_->reads_hits_only()) + rows * pixel_row +
               (finishing ? finish_.bytes(frame_.width, int(rows)) : 0);
    };
    auto rows_within = [&](bool shading) -> uint32_t {
        const uint64_t one = bytes(1, shading), per_row = bytes(2, shading) - one;
        if (budget < fixed + one) return 0;
        return uint32_t(std::min<uint64_t>(shading ? image_rows : H, 1 + (budget - fixed - one) / per_row));
    };
    const uint32_t summary_rows = rows_within(false), rows = rows_within(true);
    if (summary_rows == 0 || rows == 0) return {1, 1, fixed + std::max(bytes(1, false), bytes(1, true))};
    return {summary_rows, rows, fixed + std::max(bytes(summary_rows, false), bytes(rows, true))};
}

uint64_t ChaosGame::memory_within(unsigned workers, uint64_t budget) const {
    return streams_rows() ? plan(workers, budget).bytes : memory_bytes(workers);
}

namespace {
/// A pass of a render in strips as seen by its renderer: everything as the host's context, but
/// the progress scaled down by the number of passes, so that the bar runs once over all of them.
class PassOfStrips final : public fp::RenderContext {
public:
    PassOfStrips(fp::RenderContext& base, uint64_t passes)
        : base_(base), passes_(std::max<uint64_t>(passes, 1)) {}
    unsigned workers() const override { return base_.workers(); }
    void parallel_for(size_t n, const std::function<void(size_t, unsigned)>& task) override {
        base_.parallel_for(n, task);
    }
    void progress(uint64_t units) override {
        const uint64_t want = (in_.fetch_add(units, std::memory_order_relaxed) + units) / passes_;
        uint64_t had = out_.load(std::memory_order_relaxed);
        while (want > had && !out_.compare_exchange_weak(had, want, std::memory_order_relaxed)) {
        }
        if (want > had) base_.progress(want - had);
    }
    bool cancelled() const override { return base_.cancelled(); }
    unsigned rank() const override { return base_.rank(); }
    unsigned ranks() const override { return base_.ranks(); }
    void combine(void* data, size_t bytes, size_t record,
                 const std::function<void(const void*, void*, size_t)>& fold, bool everywhere) override {
        base_.combine(data, bytes, record, fold, everywhere);
    }
    uint64_t memory_budget() const override { return base_.memory_budget(); }
    bool shard() const override { return base_.shard(); }

private:
    fp::RenderContext& base_;
    uint64_t passes_;
    std::atomic<uint64_t> in_{0}, out_{0};
};
} // namespace

void ChaosGame::render_rows(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink) const {
    if (!streams_rows()) return fp::Renderer::render_rows(ctx, stats, sink);
    stats = fp::RenderStats{};
    const Plan pl = plan(std::max(1u, ctx.workers()), ctx.memory_budget());
    // (The host checked the budget; a caller that did not learns it here, before any work.)
    if (pl.bytes > ctx.memory_budget())
        throw fp::InputError("a " + std::to_string(frame_.width) + "x" + std::to_string(frame_.height) +
                             " render needs at least " + std::to_string(pl.bytes) +
                             " bytes of memory in strips of one row; the budget is " +
                             std::to_string(ctx.memory_budget()));
    if (double_)
        render_strips<double>(ctx, stats, sink, pl.summary_rows, pl.rows);
    else
        render_strips<float>(ctx, stats, sink, pl.summary_rows, pl.rows);
}

template <class T>
void ChaosGame::render_strips(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink,
                              uint32_t summary_rows, uint32_t rows) const {
    const uint32_t W = uint32_t(hist_.width), H = uint32_t(hist_.height),
                   image_rows = uint32_t(frame_.height);
    // (A shard finishes nothing, so it counts no summary.)
    const uint32_t summaries = ctx.shard() ? 0 : (H + summary_rows - 1) / summary_rows;
    PassOfStrips pass(ctx, summaries + (image_rows + rows - 1) / rows);
    // Rank 0 adds up the summary, shades the strips and hands their rows on; the others lend
    // their chains to each strip. A shard hands on its own rows and shades none.
    const bool root = ctx.rank() == 0 || ctx.shard();
    std::vector<float> pixels;
    fp::HistogramSummary whole;
    whole.begin(int(W), int(H));
    whole.density = density();
    for (uint32_t r0 = 0; summaries && r0 < H; r0 += summary_rows) {
        fp::Histogram part;
        fp::RenderStats st;
        render_t<T>(pass, st, part, nullptr, r0, std::min(summary_rows, H - r0), false, true);
        if (ctx.cancelled()) throw fp::Cancelled();
        if (root) whole.add(part, int(r0), &ctx);
    }
    // (With the finishing stage: strip r0's image rows from the histogram's rows of them and
    // their halo.)
    const bool finishing = finish_.active();
    const uint32_t N = uint32_t(finish_.supersample), halo = finishing ? uint32_t(finish_.halo()) : 0;
    for (uint32_t r0 = 0; r0 < image_rows; r0 += rows) {
        fp::Histogram part;
        fp::RenderStats st;
        const uint32_t on = std::min(rows, image_rows - r0);
        const uint32_t p0 = finishing ? r0 * N - std::min(r0 * N, halo) : r0;
        const uint32_t p1 = finishing ? std::min(H, (r0 + on) * N + halo) : r0 + on;
        render_t<T>(pass, st, part, nullptr, p0, p1 - p0, colour_, colourer_->reads_hits_only());
        // Every strip runs every chain: the counts of one, and the points drawn of all (in the
        // strip's own rows: its halo's are another strip's).
        const uint64_t drawn = r0 == 0 ? 0 : stats.drawn;
        if (r0 == 0) stats = st;
        const uint32_t n = finishing ? N : 1;
        uint64_t own = 0;
        for (size_t i = size_t(r0 * n - p0) * W, end = i + size_t(on * n) * W; i < end; ++i)
            own += part.hits_at(i);
        stats.drawn = drawn + own;
        if (ctx.cancelled()) throw fp::Cancelled();
        if (!root) continue;
        // The strip's own rows of the histogram, without its halo.
        if (ctx.keeps_histogram()) ctx.keep_histogram(part, int(p0), int(r0 * n), int(on * n));
        if (ctx.shard()) continue;
        pixels.resize(size_t(on) * size_t(frame_.width) * 3);
        if (finishing)
            fp::finish(finish_, *colourer_, part, int(p0), whole, frame_.width, int(r0), int(on),
                       frame_.background, pixels.data(), &ctx);
        else
            colourer_->resolve_rows(part, int(r0), whole, frame_.background, pixels.data(), ctx);
        sink.rows(int(r0), int(on), pixels.data());
    }
    const uint32_t strips = (image_rows + rows - 1) / rows;
    stats.how = "in " + std::to_string(strips) + " strips of " + std::to_string(rows) +
                (rows == 1 ? " row" : " rows") +
                (summaries ? " after " + std::to_string(summaries) + " pass" + (summaries == 1 ? "" : "es") +
                                 " counting hits"
                           : "");
}

template void ChaosGame::render_strips<float>(fp::RenderContext&, fp::RenderStats&, fp::RowSink&, uint32_t,
                                              uint32_t) const;
template void ChaosGame::render_strips<double>(fp::RenderContext&, fp::RenderStats&, fp::RowSink&, uint32_t,
                                               uint32_t) const;

} // namespace fp_chaos
