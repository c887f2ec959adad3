// The render job: how a validated pipeline becomes an image, a file or encoded bytes, for
// every front end alike (the CLI's render, validate, --vary and symmetry, serve's render and
// preview, watch, animate, explore, the Python module). No front end keeps its own copy of a
// rule: each says what it wants (RenderRequest), plan_render makes every check before any
// work, and run_render does the work.
//
//   RenderPlan plan = plan_render(pipeline, request);   // throws fp::InputError at the config
//   RenderResult r = run_render(plan, hooks);           // renders, blames, writes or encodes
//
// plan_render checks, in this order: the output (its name: -o, else the config's output.path,
// else the config's stem + ".png"; never the config itself; an existing file only when named
// or forced; its folder and format; a front end's own rule, such as serve's root), raster or
// vector (SVG and PDF only from a renderer with vector output), tiles (output.tiled for the
// file's format), --repeat and the print size, the memory (whole, or in strips where the
// output allows), checkpoints and resume (the checkpoint read whole and compared with the
// recipe), the kept histogram (--histogram) or the one finished again (tone), and under mpirun
// the agreement of every rank. run_render renders on a Runtime of the
// planned threads, polls the cancel flag, blames a plugin's refusal during the render on the
// renderer in one place, refuses an image that drew nothing, and writes atomically (whole, as a
// streamed image in strips, or a vector document) or returns the encoded bytes.
#pragma once

#include <fixpoint/host/core/checkpoint.hpp>
#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/job/print.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace fp::host {

/// What a front end asks of one render.
struct RenderRequest {
    // ---- where the result goes
    /// The file to write, as the user named it (-o, a request's "output", Python's output=).
    /// Empty: the config's output.path, else `source`'s stem + ".png" (with `default_file`), else
    /// no file.
    std::string output;
    /// Without `output`, write the default file (the CLI, serve's render). False: no file unless
    /// `output` names one (Python, the preview, explore's drafts, a collection's children).
    bool default_file = false;
    bool force = false; ///< replace an existing file, named or not
    /// A named `output` may replace an existing file (the CLI's -o, Python, watch); serve asks
    /// for force whatever the name.
    bool named_replaces = true;
    /// Where a named `output` stands in the config, for messages (a collection's child, named
    /// beside its sheet's output.path).
    std::optional<Mark> output_mark;
    bool draft_name = false; ///< the default file's name gets "-draft" (render --draft)
    /// The config file rendered: never written over; its stem names the default file. Empty for
    /// a text (a page's editor, a Python dict).
    std::string source;
    /// How a refusal of an existing default file tells the user to replace it.
    std::string replace_hint = "name it with -o to replace it, or add --force";
    /// The file's folder may be missing: the job makes it just before writing (animate's
    /// frames/%04d.png), once the nearest folder that exists is found writable.
    bool make_folder = false;
    /// A front end's own rule for a path it would write (serve: inside --root); throws
    /// fp::InputError. `mark`: where the path stands in the config, null for a named one.
    std::function<void(const std::string& path, const Mark* mark)> check_path;
    /// Only raster files (.png, .exr, .tif): `what` refuses SVG and PDF in its own words (watch,
    /// Python). Empty: vector documents allowed where the renderer has them.
    std::string raster_only;
    /// Keep the float image in the result (Python's array, explore, a collection's children).
    bool keep_image = false;
    /// Return the file's bytes in this format instead of writing one (serve's preview).
    std::optional<Format> encode;
    /// The file is checked, and the caller writes it (a collection writes all its files or none).
    bool defer_write = false;
    /// An image that drew nothing is a result, not an error (explore's drafts score it).
    bool allow_empty = false;
    /// Refuse a recipe whose image may differ from the one it was made of (--strict: an older
    /// render version whose changes touch it, another version of a plugin; Pipeline::may_differ).
    bool strict = false;

    // ---- the work
    unsigned threads = 0;     ///< 0: every core
    std::uint64_t memory = 0; ///< --memory in bytes; 0: what the machine has available
    /// Beyond the memory budget, a raster file may be streamed in strips (where the renderer can).
    /// False: the whole render must fit, else it is refused (watch: an interactive loop does not
    /// start a render of hours).
    bool may_stream = true;
    /// On this thread alone, without a thread pool (explore's drafts, rendered side by side).
    bool serial = false;
    /// Split over the MPI ranks (render under mpirun); the others send their share to rank 0,
    /// which writes.
    bool distributed = false;
    PrintRequest print; ///< --repeat, --dpi, --print-size (--tile was applied when loading)

    // ---- checkpoints (--checkpoint FILE, --checkpoint-every TIME, --resume FILE)
    std::string checkpoint, checkpoint_every, resume;
    /// Checkpoints kept in memory instead (render --quality's rounds): written into it, and,
    /// when it holds one, the render resumes from it.
    std::shared_ptr<std::string> checkpoint_memory;

    // ---- kept histograms (host/core/histogram_file.hpp)
    /// --histogram FILE.fph: the render's histogram is kept there too.
    std::string histogram;
    /// `fixpoint tone`: no iterating; the image is finished from this histogram (read and
    /// checked), which must be one of this pipeline's (its histogram identity).
    std::shared_ptr<const HistogramFile> tone;
    /// Keep the histogram in memory too (RenderResult::kept): the preview re-tones from it.
    bool keep_histogram = false;
    /// --shard K/N: render share `shard` (1 to `shards`) of the render alone, into --histogram
    /// (no image; `fixpoint merge` sums the shards). 0: the whole render.
    unsigned shard = 0, shards = 0;
};

/// What --checkpoint and --resume ask of a render, checked (plan_render).
struct CheckpointPlan {
    std::string path; ///< where checkpoints are written ("": none)
    double every_s = 300;
    CheckpointHeader header;
    std::unique_ptr<CheckpointSource> resume; ///< the checkpoint continued (null: from the start)
    std::shared_ptr<std::string> memory;      ///< RenderRequest::checkpoint_memory
};

/// A render checked and ready to run.
struct RenderPlan {
    Pipeline pipeline;
    RenderRequest request;
    unsigned threads = 1;
    std::string output;              ///< the file written; empty: none
    std::optional<Mark> output_mark; ///< where the file's name stands in the config, if there
    Format format = Format::Png;     ///< of the file or of the encoded bytes
    bool vector = false;             ///< an SVG or PDF document
    MemoryPlan memory;               ///< the budget; whether the image streams in strips
    Repeat repeat;
    Resolution resolution; ///< what the file declares (--dpi, --print-size)
    CheckpointPlan checkpoints;
    /// What --histogram writes or keep_histogram keeps (its shape: width 0 for neither).
    HistogramFileHeader histogram;
};

/// What a front end hears of a running render.
struct RenderHooks {
    /// Polled by the render; set by a signal handler or a newer request (fp::Cancelled).
    const std::atomic<bool>* cancel = nullptr;
    /// Where the render counts its work units (of plan_work_units); the caller may poll it from
    /// another thread (Python's progress callback). Null: counted inside.
    std::atomic<std::uint64_t>* done = nullptr;
    /// Draw a progress bar on stderr (the CLI on a terminal, rank 0), after `progress_label`.
    bool progress_bar = false;
    std::string progress_label;
    /// Hears the histogram's rows as the renderer hands them over (RenderContext::keep_histogram:
    /// the part, its first row, the rows' first and their number), where the renderer keeps one;
    /// render --quality counts its sample level so.
    std::function<void(const Histogram&, int, int, int)> histogram_rows;
    /// The temporary file a streamed image is written to, when it is opened, and "" once it has
    /// its name (a signal handler removes it: under mpirun no destructor may run).
    std::function<void(const std::string& tmp)> partial;
    /// Asked once a streamed render (strips) is done, before its image and kept histogram take
    /// their names: false drops both (a --quality round that falls short). Null: kept.
    std::function<bool()> keep_files;
};

/// What a render did and made.
struct RenderResult {
    RenderStats stats;
    double seconds = 0;
    /// Things to tell the user after the render (it drew almost nothing), without "warning:".
    std::vector<std::string> warnings;
    int width = 0, height = 0; ///< of the image made (rank 0)
    Image image;               ///< with keep_image
    std::string bytes;         ///< with encode
    unsigned checkpoints_written = 0;
    bool wrote = false; ///< this process wrote the file (rank 0)
    /// With keep_histogram: the render's histogram, as a histogram file would hold it (no path).
    std::shared_ptr<const HistogramFile> kept;
};

/// Every check before a render (above). Throws fp::InputError at the config's place (output.path,
/// output.tiled, the renderer) or naming the option; under mpirun the ranks agree first
/// (ranks::Refused when another rank failed).
/// `cancel` is polled once the checks are done, before the ranks agree (a Ctrl-C while a large
/// checkpoint was read).
RenderPlan plan_render(const Pipeline& pipeline, RenderRequest request,
                       const std::atomic<bool>* cancel = nullptr);

/// The file a request writes and where its name stands: the one named, else the config's
/// output.path, else the config's stem + ".png" (a draft's with "-draft"); an empty path for none.
struct RequestOutput {
    std::string path;
    std::optional<Mark> mark;
};
RequestOutput request_output(const Pipeline& p, const RenderRequest& r);

/// The checks of a request's file that need no pipeline (its name, the config, the format, an
/// existing file): plan_render's, for a front end that must check its output before it has a
/// pipeline (watch starts on a config that may not load yet). `mark`: where the name stands in
/// the config, if there.
void check_output_request(const RenderRequest& r, const std::string& out,
                          const std::optional<Mark>& mark = {});

/// The render of a plan. Throws fp::Cancelled when cancelled (nothing written, a file there
/// before kept), fp::InputError for a refusal during the render (at the renderer) or a failed
/// write (WriteError, naming the file). Under mpirun with `distributed`, only rank 0's result
/// holds the image and only rank 0 writes.
RenderResult run_render(RenderPlan& plan, const RenderHooks& hooks = {});

/// Writes `img` as run_render writes a plan's raster image: atomically, repeated as --repeat
/// asks, with the plan's recipe (--quality writes its last round's image so).
void write_render(const RenderPlan& plan, const Image& img, const RenderHooks& hooks);

/// Units of work this process reports over the plan's render (its rank's share).
std::uint64_t plan_work_units(const RenderPlan& plan);

/// The summary line of a finished render: "out.png: 1000000 points in 0.52 s (1.9e+06 points/s,
/// 2 threads, AVX2), 0 restarted chains, 0 bad values[, in 3 strips ...][; 2 checkpoints to F]".
std::string summary_line(const RenderPlan& plan, const RenderResult& r);

/// fig4a.png -> fig4a-draft.png
std::string draft_name(const std::string& path);

} // namespace fp::host
