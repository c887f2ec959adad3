// Renderer: turns a recipe into an image, on the host's thread pool.
#pragma once

#include <fixpoint/histogram.hpp>
#include <fixpoint/object.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace fp {

/// A float image, `channels` floats per pixel, row-major, top row first.
struct Image {
    int width = 0, height = 0, channels = 3;
    std::vector<float> pixels;
};

/// What a render did, for the CLI's summary line.
struct RenderStats {
    std::uint64_t samples = 0;    ///< points plotted or pixel samples taken
    std::uint64_t restarts = 0;   ///< chains restarted (no allowed map, bad values)
    std::uint64_t bad_values = 0; ///< NaN or infinite points met
    /// Of `samples`, those that reached the image (points inside the view, pixel samples
    /// that hit something); the CLI refuses to write an empty render and warns about a
    /// nearly empty one. unknown_count: the renderer does not count them.
    std::uint64_t drawn = unknown_count;
    static constexpr std::uint64_t unknown_count = ~std::uint64_t(0);
    std::string unit = "points";
    /// What `drawn` counts, for the CLI's messages ("of 500 points landed in the image").
    std::string drawn_means = "landed in the image";
    /// How the render was made when the summary line should say so ("in 3 strips of 342
    /// rows"); empty otherwise. (Added in ABI 11.)
    std::string how;
};

class CheckpointSink;
class CheckpointSource;

/// The host's side of a render. Called per task, never per point.
class RenderContext {
public:
    virtual ~RenderContext();
    /// Number of workers; a worker index passed to tasks is below it.
    virtual unsigned workers() const = 0;
    /// Run task(i, worker) for every i in [0, n) on the host's threads and wait. Results
    /// must not depend on which worker runs which task.
    virtual void parallel_for(std::size_t n, const std::function<void(std::size_t, unsigned)>& task) = 0;
    /// Report `units` more units of work done (of Renderer::work_units()); thread-safe.
    virtual void progress(std::uint64_t units) = 0;
    /// True once the user asked to stop (Ctrl-C); renderers poll it and throw fp::Cancelled
    /// within a fraction of a second.
    virtual bool cancelled() const = 0;

    // Distribution over processes: Open MPI ranks under `mpirun fixpoint render`, otherwise
    // one. A renderer that splits its work gives each rank a share chosen by the recipe alone
    // (never by timing), and folds the shares together with combine(), so the bytes do not
    // depend on the rank count. A renderer that ignores these runs whole on every rank, and
    // rank 0's image is the one written. (Added in ABI 10.)

    /// This process's rank, in [0, ranks()). Default: 0.
    virtual unsigned rank() const;
    /// Number of processes the render is split over. Default: 1.
    virtual unsigned ranks() const;
    /// Fold every rank's `bytes` bytes at `data` together, in pieces of whole `record`s:
    /// fold(in, inout, records) folds another rank's records into this rank's. The fold must
    /// be associative and commutative (exact integer sums, maxima, bitwise or), so that the
    /// result does not depend on the order in which ranks meet. Afterwards rank 0 holds the
    /// result, and with `everywhere` every rank does. Collective: every rank calls it, with the
    /// same sizes, in the same order. Default (one rank): nothing to do.
    virtual void combine(void* data, std::size_t bytes, std::size_t record,
                         const std::function<void(const void* in, void* inout, std::size_t records)>& fold,
                         bool everywhere);

    /// The memory this process's render may take, in bytes (`fixpoint render --memory`, else
    /// what the machine has available, shared by the ranks on it): a renderer that can work in
    /// less (strips) stays within it. Default: no limit. (Added in ABI 11.)
    virtual std::uint64_t memory_budget() const;

    // Checkpoints (added in ABI 12: `fixpoint render --checkpoint FILE`, `--resume FILE`), for a
    // renderer that keeps_checkpoints(). The host owns the file: its envelope (magic, versions,
    // the recipe, a checksum) and its atomic replacement; the renderer owns the payload.

    /// Whether the host keeps checkpoints of this render (`--checkpoint`, `--resume`): the
    /// renderer then keeps what they need. Default: false.
    virtual bool checkpointing() const;
    /// True when the host wants a checkpoint (`--checkpoint-every` has passed since the last
    /// one): the renderer brings its work to a point it can continue from, and calls
    /// write_checkpoint. Polled often and cheaply. Default: false.
    virtual bool checkpoint_due() const;
    /// Saves the render's state now: `body` writes the payload, in pieces, to the sink; the
    /// host replaces the checkpoint file with it atomically (a failed write throws fp::Error and
    /// leaves the last checkpoint whole). Called from the
    /// renderer's own thread, not from a task. Default: nothing is kept.
    virtual void write_checkpoint(const std::function<void(CheckpointSink&)>& body);
    /// The payload to continue from (`--resume`), positioned at its start, its envelope already
    /// checked against the recipe; null for a render from the beginning. Default: null.
    virtual CheckpointSource* resume_from();

    // Kept histograms (added in ABI 18: `fixpoint render --histogram FILE`, then `fixpoint tone
    // FILE`), for a renderer whose histogram_shape() is not empty. The host owns the file (its
    // envelope, the recipe, compression and checksum); the renderer hands over its bins.

    /// Whether the host keeps this render's histogram. Default: false.
    virtual bool keeps_histogram() const;
    /// Rows [row0, row0 + rows) of the render's whole histogram (of histogram_shape()), from
    /// `part`, which holds its rows from part_row0 on (a strip with its halo, or the whole):
    /// handed over by rank 0 after the ranks' sums (by a shard, its own share), before the rows
    /// are finished, in order from row 0 down, each row once. Called from the renderer's own thread. Default:
    /// nothing.
    virtual void keep_histogram(const Histogram& part, int part_row0, int row0, int rows);

    /// A shard (`fixpoint render --shard K/N`, added in ABI 21): this process renders share
    /// rank() of ranks() alone, as that MPI rank would, and nothing is combined. The renderer
    /// hands that share's own histogram to keep_histogram (with Histogram::last_order where it
    /// keeps last colours), so that `fixpoint merge` sums the shards into the whole; the image
    /// is not used, so it need not finish one. Default: false.
    virtual bool shard() const;
};

/// The histogram a renderer keeps (Renderer::histogram_shape): its size and what a bin holds.
struct HistogramShape {
    int width = 0, height = 0; ///< 0: the renderer keeps none
    /// A bin's hits alone (a colourer that reads hits only), else {hits, r, g, b}.
    bool hits_only = false;
    /// Each bin's last colour too (PixelRule::last).
    bool last = false;
};

/// Where a renderer writes its checkpoint's payload (RenderContext::write_checkpoint).
class CheckpointSink {
public:
    virtual ~CheckpointSink();
    virtual void write(const void* data, std::size_t bytes) = 0;
};

/// Where a renderer reads the payload it continues from (RenderContext::resume_from). read()
/// throws fp::InputError ("the checkpoint ends early") past the payload's end.
class CheckpointSource {
public:
    virtual ~CheckpointSource();
    virtual void read(void* data, std::size_t bytes) = 0;
    /// Bytes of the payload not yet read.
    virtual std::uint64_t left() const = 0;
};

/// Folds for RenderContext::combine, with `record` = sizeof(T).
namespace fold {
/// Element-wise sums of T (exact for integers).
template <class T>
void sum(const void* in, void* inout, std::size_t n) {
    const T* a = static_cast<const T*>(in);
    T* b = static_cast<T*>(inout);
    for (std::size_t i = 0; i < n; ++i) b[i] += a[i];
}
/// Element-wise bitwise or of T: gathers shares that are zero where another rank owns them.
template <class T>
void bit_or(const void* in, void* inout, std::size_t n) {
    const T* a = static_cast<const T*>(in);
    T* b = static_cast<T*>(inout);
    for (std::size_t i = 0; i < n; ++i) b[i] |= a[i];
}
} // namespace fold

/// Where a renderer that streams its image (Renderer::render_rows) puts its rows: the host
/// encodes and writes each band as it comes, so the whole image is never in memory.
class RowSink {
public:
    virtual ~RowSink();
    /// Rows [y0, y0 + rows) of the image: 3 floats per pixel (display values in [0, 1]),
    /// row-major, top row first. Called from the renderer's own thread (not from a task), for
    /// consecutive bands from row 0 down, each row once.
    virtual void rows(int y0, int rows, const float* rgb) = 0;
};

/// Vector formats a renderer may write (Renderer::render_vector).
enum class VectorFormat { Svg, Pdf };

class Renderer : public Object {
public:
    ~Renderer() override;

    virtual int width() const = 0;
    virtual int height() const = 0;
    /// Memory the render will need with `workers` workers, for the check before it starts.
    virtual std::uint64_t memory_bytes(unsigned workers) const = 0;
    // Renders beyond memory (added in ABI 11): a renderer whose image, or whose buffers, do not
    // fit the memory budget (RenderContext::memory_budget) streams the image by bands of rows.
    // The host calls render() when memory_bytes() fits the budget, else render_rows() when the
    // renderer streams_rows() and the output allows it (a raster image file), else refuses.

    /// Whether render_rows works. Default: false.
    virtual bool streams_rows() const;
    /// Memory render_rows will take with `workers` workers within `budget` bytes; the least it
    /// can do with when even that is over the budget (then the host refuses the render, naming
    /// it). Default: memory_bytes(workers).
    virtual std::uint64_t memory_within(unsigned workers, std::uint64_t budget) const;
    /// The image, band by band into `sink` (the same pixels render() gives), within
    /// ctx.memory_budget(). Collective under several ranks like render(); rank 0's sink is the
    /// one written. Default: throws fp::Error.
    virtual void render_rows(RenderContext& ctx, RenderStats& stats, RowSink& sink) const;
    /// Units of work reported through RenderContext::progress over a whole render.
    virtual std::uint64_t work_units() const = 0;
    virtual Image render(RenderContext& ctx, RenderStats& stats) const = 0;

    // Optional abilities (defaults: none). Added for paper 05's mfs renderer.

    /// Whether render_vector works; the host checks it before rendering to .svg or .pdf.
    virtual bool has_vector_output() const;
    /// The picture as a whole SVG or PDF document (its bytes), with `recipe` embedded where
    /// the format allows. The host writes it atomically. Default: throws fp::Error.
    virtual std::string render_vector(RenderContext& ctx, RenderStats& stats, VectorFormat format,
                                      const std::string& recipe) const;
    /// Paper 05's Algorithm 1: one line per polygon at `level` (-1: the last level), its
    /// address first. Throws fp::ParamError for a level that does not exist; default: throws
    /// fp::Error (the renderer draws no addressed polygons).
    virtual std::vector<std::string> polygon_addresses(std::int64_t level) const;
    /// The region of the plane the picture shows, when it shows one: the `view` or `area`
    /// given, or the one the renderer fitted (mfs's points' box, chaos-game's fit_view).
    /// `fixpoint serve` pans and zooms from it. Default: none.
    virtual std::optional<Box> region() const;

    /// Whether the renderer saves and resumes checkpoints (RenderContext::write_checkpoint,
    /// resume_from) in a render() on one process; the host refuses `--checkpoint` otherwise.
    /// A renderer that does promises the bytes of an uninterrupted render after any number of
    /// checkpoints and resumes, and, where its recipe has `points`, continues a finished render
    /// to more points with the bytes of a render of that many from the start. Default: false.
    /// (Added in ABI 12.)
    virtual bool keeps_checkpoints() const;

    /// The histogram this render accumulates and hands to RenderContext::keep_histogram, for
    /// `render --histogram`; empty (width 0) when it keeps none. Default: empty. (Added in ABI 18.)
    virtual HistogramShape histogram_shape() const;
    /// The image render() makes of the histogram `h` (of histogram_shape(); `stats`: the
    /// render's, as kept with it): the same bytes as a render of this recipe whose sums are
    /// `h`, with no iterating (`fixpoint tone`). Default: throws fp::Error.
    virtual Image finish_histogram(const Histogram& h, const RenderStats& stats, RenderContext& ctx) const;
};

} // namespace fp
