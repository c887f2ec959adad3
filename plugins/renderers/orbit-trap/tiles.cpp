// orbit-trap's tiles (orbit-trap.cpp's header: Performance, Bands; Checkpoints below): one tile's
// samples as a batch, iterated step by step with the traps tested after each; the whole image
// from the tiles, by bands of rows into a sink, or in rounds between checkpoints.
#include "orbit-trap/batch.hpp"
#include "orbit-trap/reduce.hpp"
#include "orbit-trap/renderer.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace fp_orbit_trap {

// One tile: pixels [t * tile_pixels, ...) in row-major order, all their samples in one batch.
template <class T>
TileStats OrbitTrap::tile(size_t t, Scratch<T>& s, float* image, size_t image_p0,
                          const fp::RenderContext& ctx) const {
    const size_t npix = size_t(frame_.width) * size_t(frame_.height);
    const size_t p0 = t * tile_pixels_, p1 = std::min(npix, p0 + tile_pixels_);
    const size_t ns = offsets_.size(), np = p1 - p0, b = np * ns;
    // The batch's start points (orbit-trap/kernels-inl.hpp, per target: plain loops the
    // compiler vectorises for each instruction set).
    const TileFrame tf{cx_,
                       hx_,
                       cy_,
                       hy_,
                       iw_,
                       ih_,
                       size_t(frame_.width),
                       size_t(frame_.height),
                       offsets_.data(),
                       ns,
                       max_iterations_};
    tile_starts(tf, s, p0, np);
    size_t live = b;
    // With a known trap the reduction's range is checked inline (test_retire) once a batch
    // reduction found every value in range (the map reduces itself, as the wallpaper maps under
    // Picard), until a block is found outside again (then the whole batch is reduced first).
    bool batch_reduce = true;
    for (uint32_t step = 0; step < max_iterations_ && live > 0; ++step) {
        // Polled within the tile, every 64 steps of the batch: orbits that are never caught run
        // the whole max_iterations (up to 10^8), far too long to wait for the next tile.
        if (step % 64 == 63 && ctx.cancelled()) throw fp::Cancelled();
        iteration_->step(*mapping_, fp::Points<T>{s.x.data(), s.y.data(), live}, nullptr, step);
        if (known_trap_) {
            if (batch_reduce) {
                batch_reduce = reduce_xy(s.x.data(), s.y.data(), live, reduction_);
            }
            const bool check = !batch_reduce && reduction_ != Reduction::none;
            bool outside = false;
            live = test_retire(circles(T{}), s, live, step + 1, reduction_, check, outside);
            batch_reduce = batch_reduce || outside;
            continue;
        }
        reduce_xy(s.x.data(), s.y.data(), live, reduction_);
        traps_->test(fp::Points<const T>{s.x.data(), s.y.data(), live}, s.caught.data(), s.ratio.data());
        live = retire(s, live, step + 1);
    }
    TileStats st;
    for (size_t i = 0; i < live; ++i) st.bad += !(std::isfinite(s.x[i]) && std::isfinite(s.y[i]));
    for (size_t k = 0; k < b; ++k) st.drawn += s.trap[k] >= 0;

    colourer_->colour_hits(s.trap.data(), s.ratio_out.data(), s.iteration.data(), b,
                           frame_.has_background ? &frame_.background : nullptr, s.rgb.data());
    // The mean of each pixel's samples (orbit-trap/kernels-inl.hpp, per target).
    tile_mean(s.rgb.data(), s.quant.data(), s.sum.data(), np, ns, image + 3 * (p0 - image_p0));
    return st;
}

// Checkpoints (`fixpoint render --checkpoint`, `--resume`): the tiles go in rounds; when a
// checkpoint is due, the tiles not yet begun wait, and the checkpoint holds which tiles are done,
// their counts and the image so far (tiles not done are +0.0). A resumed render renders the
// others: a tile's pixels depend on nothing but the tile, so the image is the same bytes.
namespace {
struct TilesHead {
    uint32_t version = 1, samples = 0;
    uint64_t width = 0, height = 0, tiles = 0, tile_pixels = 0;
};
static_assert(sizeof(TilesHead) == 40, "TilesHead is written as it is");
} // namespace

template <class T>
void OrbitTrap::run_checkpointed(fp::RenderContext& ctx, fp::Image& img, std::vector<TileStats>& per_tile,
                                 std::vector<Scratch<T>>& scratch) const {
    const size_t npix = size_t(frame_.width) * size_t(frame_.height), tiles = per_tile.size();
    TilesHead head;
    head.samples = uint32_t(offsets_.size());
    head.width = uint64_t(frame_.width), head.height = uint64_t(frame_.height);
    head.tiles = tiles, head.tile_pixels = tile_pixels_;
    std::vector<uint8_t> done(tiles, 0);
    const auto pixels_of = [&](size_t t) {
        return std::min(npix, (t + 1) * tile_pixels_) - t * tile_pixels_;
    };
    if (fp::CheckpointSource* in = ctx.resume_from()) {
        TilesHead was;
        in->read(&was, sizeof was);
        if (std::memcmp(&was, &head, sizeof head) != 0)
            throw fp::InputError("the checkpoint's payload does not fit this render (damaged?)");
        in->read(done.data(), tiles);
        in->read(per_tile.data(), tiles * sizeof(TileStats));
        in->read(img.pixels.data(), img.pixels.size() * sizeof(float));
        if (in->left() != 0)
            throw fp::InputError("the checkpoint's payload is longer than this render's state");
        uint64_t had = 0;
        for (size_t t = 0; t < tiles; ++t) {
            if (done[t] > 1) throw fp::InputError("the checkpoint's payload is damaged");
            had += done[t] ? pixels_of(t) : 0;
        }
        ctx.progress(had);
    }
    for (;;) {
        std::vector<size_t> todo;
        for (size_t t = 0; t < tiles; ++t)
            if (!done[t]) todo.push_back(t);
        std::atomic<bool> stop{false};
        ctx.parallel_for(todo.size(), [&](size_t i, unsigned worker) {
            if (ctx.cancelled()) throw fp::Cancelled();
            if (stop.load(std::memory_order_relaxed)) return;
            if (ctx.checkpoint_due()) {
                stop.store(true, std::memory_order_relaxed);
                return;
            }
            const size_t t = todo[i];
            per_tile[t] = tile<T>(t, scratch[worker], img.pixels.data(), 0, ctx);
            done[t] = 1;
            ctx.progress(pixels_of(t));
        });
        if (ctx.cancelled()) throw fp::Cancelled();
        ctx.write_checkpoint([&](fp::CheckpointSink& out) {
            out.write(&head, sizeof head);
            out.write(done.data(), tiles);
            out.write(per_tile.data(), tiles * sizeof(TileStats));
            out.write(img.pixels.data(), img.pixels.size() * sizeof(float));
        });
        if (!stop.load()) return; // every tile done: that was the last checkpoint
    }
}

template <class T>
fp::Image OrbitTrap::run(fp::RenderContext& ctx, fp::RenderStats& stats) const {
    const size_t npix = size_t(frame_.width) * size_t(frame_.height);
    const size_t tiles = (npix + tile_pixels_ - 1) / tile_pixels_;
    fp::Image img;
    img.width = frame_.width;
    img.height = frame_.height;
    img.channels = 3;
    img.pixels.assign(npix * 3, 0.0f);
    std::vector<Scratch<T>> scratch(std::max(1u, ctx.workers()));
    for (auto& s : scratch) s.resize(tile_pixels_ * offsets_.size(), tile_pixels_);
    std::vector<TileStats> per_tile(tiles);
    // Over several ranks (MPI), rank r renders tiles r, r + N, ... (tiles are cut by the recipe
    // alone); the others' pixels stay +0.0 (all bits zero), so a bitwise or gathers the image.
    const size_t rank = ctx.rank(), ranks = std::max(1u, ctx.ranks());
    const size_t mine = tiles > rank ? (tiles - rank + ranks - 1) / ranks : 0;
    if (ctx.checkpointing() || ctx.resume_from()) {
        if (ranks > 1)
            throw fp::InputError("checkpoints are kept of a render on one process (not over MPI ranks)");
        run_checkpointed<T>(ctx, img, per_tile, scratch);
    } else {
        ctx.parallel_for(mine, [&](size_t i, unsigned worker) {
            if (ctx.cancelled()) throw fp::Cancelled();
            const size_t t = rank + i * ranks;
            per_tile[t] = tile<T>(t, scratch[worker], img.pixels.data(), 0, ctx);
            const size_t p0 = t * tile_pixels_;
            ctx.progress(std::min(npix, p0 + tile_pixels_) - p0);
        });
    }
    if (ctx.cancelled()) throw fp::Cancelled();
    stats = fp::RenderStats{};
    stats.samples = uint64_t(npix) * offsets_.size();
    stats.drawn = 0;
    for (const auto& st : per_tile) stats.drawn += st.drawn, stats.bad_values += st.bad;
    if (ranks > 1) {
        static_assert(sizeof(float) == sizeof(uint32_t));
        uint64_t counts[2] = {stats.drawn, stats.bad_values};
        ctx.combine(counts, sizeof counts, sizeof(uint64_t), fp::fold::sum<uint64_t>, false);
        stats.drawn = counts[0], stats.bad_values = counts[1];
        ctx.combine(img.pixels.data(), img.pixels.size() * sizeof(float), sizeof(uint32_t),
                    fp::fold::bit_or<uint32_t>, false);
    }
    stats.unit = "pixel samples";
    stats.drawn_means = "were caught by a trap";
    return img;
}

fp::Image OrbitTrap::render(fp::RenderContext& ctx, fp::RenderStats& stats) const {
    return double_ ? run<double>(ctx, stats) : run<float>(ctx, stats);
}

template <class T>
void OrbitTrap::run_rows(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink,
                         size_t band_rows) const {
    const size_t W = size_t(frame_.width), H = size_t(frame_.height), npix = W * H, tp = tile_pixels_;
    std::vector<Scratch<T>> scratch(std::max(1u, ctx.workers()));
    for (auto& s : scratch) s.resize(tile_pixels_ * offsets_.size(), tile_pixels_);
    const size_t rank = ctx.rank(), ranks = std::max(1u, ctx.ranks());
    // Room for the largest band at once: a band that outgrew the last one would otherwise hold
    // both while it moves (twice the budget).
    std::vector<float> band;
    band.reserve((band_rows * W + 2 * tp) * 3);
    stats = fp::RenderStats{};
    stats.drawn = 0;
    size_t counted = 0; // the tiles before it are in the stats
    for (size_t y0 = 0; y0 < H; y0 += band_rows) {
        const size_t y1 = std::min(H, y0 + band_rows);
        // The tiles that cover the band's pixels; the first and the last may reach into the
        // bands beside it (tiles are runs of pixels, not of rows): those pixels are rendered
        // again there, to the same values.
        const size_t t0 = y0 * W / tp, t1 = (y1 * W + tp - 1) / tp, base = t0 * tp;
        band.assign((std::min(npix, t1 * tp) - base) * 3, 0.0f);
        // Tiles t with t = rank (mod ranks), as render() deals them.
        const size_t first = t0 + (rank + ranks - t0 % ranks) % ranks;
        const size_t mine = first < t1 ? (t1 - first + ranks - 1) / ranks : 0;
        std::vector<TileStats> st(t1 - t0);
        ctx.parallel_for(mine, [&](size_t i, unsigned worker) {
            if (ctx.cancelled()) throw fp::Cancelled();
            const size_t t = first + i * ranks;
            st[t - t0] = tile<T>(t, scratch[worker], band.data(), base, ctx);
            const size_t p0 = std::max(t * tp, y0 * W), p1 = std::min(std::min(npix, (t + 1) * tp), y1 * W);
            ctx.progress(p1 > p0 ? p1 - p0 : 0);
        });
        if (ctx.cancelled()) throw fp::Cancelled();
        for (size_t t = std::max(t0, counted); t < t1; ++t)
            stats.drawn += st[t - t0].drawn, stats.bad_values += st[t - t0].bad;
        counted = t1;
        if (ranks > 1)
            ctx.combine(band.data(), band.size() * sizeof(float), sizeof(uint32_t),
                        fp::fold::bit_or<uint32_t>, false);
        if (rank == 0) sink.rows(int(y0), int(y1 - y0), band.data() + 3 * (y0 * W - base));
    }
    stats.samples = uint64_t(npix) * offsets_.size();
    if (ranks > 1) {
        uint64_t counts[2] = {stats.drawn, stats.bad_values};
        ctx.combine(counts, sizeof counts, sizeof(uint64_t), fp::fold::sum<uint64_t>, false);
        stats.drawn = counts[0], stats.bad_values = counts[1];
    }
    stats.unit = "pixel samples";
    stats.drawn_means = "were caught by a trap";
    const size_t bands = (H + band_rows - 1) / band_rows;
    stats.how = "in " + std::to_string(bands) + " bands of " + std::to_string(band_rows) +
                (band_rows == 1 ? " row" : " rows");
}

void OrbitTrap::render_rows(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink) const {
    const size_t rows = band_rows(std::max(1u, ctx.workers()), ctx.memory_budget());
    // (The host checked the budget; a caller that did not learns it here, before any work.)
    if (rows == 0)
        throw fp::InputError(
            "a " + std::to_string(frame_.width) + "x" + std::to_string(frame_.height) +
            " render needs at least " + std::to_string(memory_within(std::max(1u, ctx.workers()), 0)) +
            " bytes of memory in bands of one row; the budget is " + std::to_string(ctx.memory_budget()));
    if (double_)
        run_rows<double>(ctx, stats, sink, rows);
    else
        run_rows<float>(ctx, stats, sink, rows);
}

} // namespace fp_orbit_trap
