// The render job (fixpoint/host/job/render_job.hpp): plan_render's checks, in the order the
// header gives them.
#include <fixpoint/host/core/progress.hpp>
#include <fixpoint/host/core/ranks.hpp>
#include <fixpoint/host/core/render_version.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/host/job/render_job.hpp>
#include <fixpoint/simd.hpp>
#include <fixpoint/text.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>

namespace fs = std::filesystem;

namespace fp::host {

std::string draft_name(const std::string& path) {
    const fs::path p(path);
    return (p.parent_path() / (p.stem().string() + "-draft" + p.extension().string())).string();
}

// ---------------------------------------------------------------- the output
RequestOutput request_output(const Pipeline& p, const RenderRequest& r) {
    if (!r.output.empty()) return {r.output, r.output_mark};
    if (!r.default_file) return {};
    RequestOutput o;
    if (!p.output_path.empty()) {
        o.path = p.output_path;
        o.mark = p.output_mark;
    } else if (!r.source.empty()) {
        o.path = fs::path(r.source).stem().string() + ".png";
    } else {
        return {};
    }
    if (r.draft_name) o.path = draft_name(o.path);
    return o;
}

// The promises about existing files: the config itself is never written over; another existing
// file only when named (where the front end lets a name replace it) or with force. Errors about
// a path from the config point at output.path.
void check_output_request(const RenderRequest& r, const std::string& out, const std::optional<Mark>& mark) {
    try {
        if (r.check_path) r.check_path(out, mark ? &*mark : nullptr);
        std::error_code ec;
        if (!r.source.empty() && fs::equivalent(out, r.source, ec))
            throw InputError("cannot write " + quote(out, 200) + ": it is the config being rendered");
        check_output(out, r.make_folder);
        if (!r.raster_only.empty() && is_vector(format_for(out))) {
            std::string m = r.raster_only;
            if (const auto at = m.find("{}"); at != std::string::npos) m.replace(at, 2, quote(out, 200));
            throw InputError(m);
        }
        const bool named = !r.output.empty() && r.named_replaces;
        if (!named && !r.force && fs::exists(fs::symlink_status(out, ec)))
            throw InputError(quote(out, 200) + " exists: " + r.replace_hint);
    } catch (const InputError& e) {
        if (mark) throw InputError(mark->str() + ": output.path: " + e.what());
        throw;
    }
}

namespace {

// Raster or vector, and the tiles of a raster file.
void check_format(RenderPlan& plan) {
    const Pipeline& p = plan.pipeline;
    const RenderRequest& r = plan.request;
    if (r.encode) {
        plan.format = *r.encode;
        plan.vector = is_vector(plan.format);
        if (plan.vector) throw InternalError("the render job encodes raster images only");
        return;
    }
    if (plan.output.empty()) return;
    plan.format = format_for(plan.output);
    plan.vector = check_vector_output(p, plan.output);
    if (!plan.vector) check_tiled(p, plan.output);
}

// --repeat: the repeated image is made after the render, beside the tile.
void check_repeat(RenderPlan& plan) {
    const PrintRequest& print = plan.request.print;
    plan.repeat = parse_repeat(print);
    if (plan.repeat.across * plan.repeat.down == 1) return;
    const Renderer& R = *plan.pipeline.renderer;
    const std::uint64_t repeated = std::uint64_t(R.width()) * std::uint64_t(plan.repeat.across) *
                                   std::uint64_t(R.height()) * std::uint64_t(plan.repeat.down) * 3 *
                                   sizeof(float);
    const std::uint64_t need = R.memory_bytes(plan.threads) + repeated, have = available_memory();
    if (need > have)
        throw InputError("--repeat " + print.repeat + ": the tile and its repeated image need " +
                         format_bytes(need) + " of memory; this machine has " + format_bytes(have) +
                         " available");
}

// The memory: whole, or streamed in strips where the output allows it (a raster file that is
// not repeated, with nothing that needs the whole image in memory).
void check_memory_plan(RenderPlan& plan) {
    const RenderRequest& r = plan.request;
    const Pipeline& p = plan.pipeline;
    // (A shard streams no image: its strips' rows go nowhere, their histogram to its file.)
    const bool can_stream = r.may_stream && (!plan.output.empty() || r.shards) && !plan.vector &&
                            !r.keep_image && !r.encode && plan.repeat.across * plan.repeat.down == 1 &&
                            !r.serial;
    const std::uint64_t held =
        can_stream && !r.shards
            ? StreamedImage::held_bytes(plan.output, p.renderer->width(), p.renderer->height(), p.tiled)
            : 0;
    plan.memory = check_memory_within(p, plan.threads, r.memory, can_stream, held);
    if (plan.vector) plan.memory.stream = false;
}

// ---------------------------------------------------------------- checkpoints
// The same file, spelled differently or not there yet: compared as absolute paths with . and ..
// resolved.
bool same_file(const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::equivalent(a, b, ec)) return true;
    const fs::path ca = fs::weakly_canonical(fs::absolute(a), ec);
    if (ec || ca.empty()) return a == b; // (undecidable: only the same spelling)
    return ca == fs::weakly_canonical(fs::absolute(b), ec) && !ec;
}

// Rank K-1 of N's checkpoint under mpirun: FILE.K-of-N.
std::string rank_file(const std::string& base) {
    return base + "." + std::to_string(ranks::rank() + 1) + "-of-" + std::to_string(ranks::size());
}

// A rank's checkpoint to resume that is not there: perhaps the job ran on another rank count,
// which the other files say.
void check_rank_file(const std::string& base, const std::string& mine) {
    std::error_code ec;
    if (fs::exists(mine, ec)) return;
    const fs::path b(base);
    const fs::path dir = b.parent_path().empty() ? fs::path(".") : b.parent_path();
    const std::string stem = b.filename().string() + ".";
    std::string other;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string name = e.path().filename().string();
        const std::size_t of = name.rfind("-of-");
        if (name.compare(0, stem.size(), stem) == 0 && of != std::string::npos && of > stem.size() &&
            name.find_first_not_of("0123456789", of + 4) == std::string::npos && of + 4 < name.size())
            other = name.substr(of + 4);
    }
    throw InputError("--resume: no checkpoint " + quote(mine, 200) + " of rank " +
                     std::to_string(ranks::rank() + 1) + " of " + std::to_string(ranks::size()) +
                     (other.empty() ? std::string(": each rank resumes its own (FILE.K-of-N)")
                                    : ": " + quote(base, 200) + " was checkpointed on " + other +
                                          " ranks: resume it with mpirun -np " + other));
}

// --checkpoint, --checkpoint-every, --resume: checked before the render (the checkpoint to resume
// read whole and compared with the recipe); an empty plan without them.
void check_checkpoints(RenderPlan& plan) {
    const RenderRequest& r = plan.request;
    const Pipeline& p = plan.pipeline;
    CheckpointPlan& ck = plan.checkpoints;
    if (r.checkpoint_memory) {
        // In memory, in this process: the rounds of one render (--quality), same recipe but points.
        if (!r.checkpoint.empty() || !r.resume.empty())
            throw InternalError("render job: checkpoints in memory and in a file at once");
        if (ranks::size() > 1 || !p.renderer->keeps_checkpoints() || plan.vector || plan.memory.stream)
            throw InternalError("render job: checkpoints in memory of a render that cannot keep them");
        ck.memory = r.checkpoint_memory;
        ck.every_s = 1e9;
        ck.header = checkpoint_header(p);
        // (The payload moves to the resume, which reads it whole before the render saves again.)
        if (!ck.memory->empty())
            ck.resume = std::make_unique<MemoryCheckpoint>(
                std::make_shared<const std::string>(std::move(*ck.memory)));
        ck.memory->clear();
        return;
    }
    if (r.checkpoint.empty() && r.resume.empty()) {
        if (!r.checkpoint_every.empty())
            throw InputError("--checkpoint-every: checkpoints go to a file: add --checkpoint FILE");
        return;
    }
    const std::string opt = r.resume.empty() ? "--checkpoint" : "--resume";
    // Under mpirun, each rank keeps its own share's state (as a shard does), in FILE.K-of-N for
    // rank K-1 of N: a job resumes on the rank count it was checkpointed with.
    const bool per_rank = r.distributed && ranks::size() > 1;
    if (ranks::size() > 1 && !per_rank)
        throw InputError(opt + ": checkpoints are kept of a render on one process, or of each rank's share "
                               "under mpirun");
    if (!p.renderer->keeps_checkpoints() || plan.vector)
        throw InputError(p.renderer_mark.str() + ": renderer: " + p.renderer_type +
                         (plan.vector ? " draws this picture without points" : " keeps no checkpoints") +
                         " (" + opt + "; chaos-game and orbit-trap renders keep them)");
    if (plan.memory.stream)
        throw InputError(opt + ": this render is beyond the memory budget and streams in strips; checkpoints "
                               "are kept of a render that fits (see --memory)");
    ck.every_s = r.checkpoint_every.empty() ? 300 : parse_duration(r.checkpoint_every, "--checkpoint-every");
    // With --resume alone, the checkpoints go on in the file resumed.
    const std::string resume = per_rank && !r.resume.empty() ? rank_file(r.resume) : r.resume;
    ck.path = r.checkpoint.empty() ? resume : per_rank ? rank_file(r.checkpoint) : r.checkpoint;
    ck.header = checkpoint_header(p);
    // A shard's checkpoint continues that shard alone, a rank's that rank's share.
    if (r.shards)
        ck.header.identity += "# shard " + std::to_string(r.shard) + "/" + std::to_string(r.shards) + "\n";
    if (per_rank)
        ck.header.identity +=
            "# rank " + std::to_string(ranks::rank() + 1) + " of " + std::to_string(ranks::size()) + "\n";
    if (per_rank && !resume.empty()) check_rank_file(r.resume, resume);
    for (const auto& [name, other] :
         {std::pair{"the output", plan.output}, std::pair{"the config", r.source}})
        if (!other.empty() && same_file(ck.path, other))
            throw InputError(opt + ": " + quote(ck.path, 200) + " is " + name +
                             ": a checkpoint needs a file of its own");
    std::error_code ec;
    if (!r.resume.empty()) {
        auto file = std::make_unique<CheckpointFile>(resume);
        file->check_against(ck.header);
        ck.resume = std::move(file);
    } else if (!r.force && fs::exists(fs::symlink_status(ck.path, ec))) {
        throw InputError("--checkpoint: " + quote(ck.path, 200) +
                         " exists: continue it with --resume, or add --force to start over");
    }
    // A checkpoint that cannot be written is better found now than after the first period.
    const fs::path dir = fs::path(ck.path).parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw InputError(opt + ": cannot write " + quote(ck.path, 200) + ": no folder " +
                         quote(dir.string(), 200));
    if (::access(dir.empty() ? "." : dir.c_str(), W_OK) != 0)
        throw InputError(opt + ": cannot write " + quote(ck.path, 200) + ": " + std::strerror(errno));
}

// --histogram FILE.fph (the histogram kept beside the image) and tone (the image finished from a
// kept histogram, with no iterating): checked before the render.
void check_histograms(RenderPlan& plan) {
    const RenderRequest& r = plan.request;
    const Pipeline& p = plan.pipeline;
    const HistogramShape shape = p.renderer->histogram_shape();
    const auto none = [&](const std::string& opt) {
        return InputError(p.renderer_mark.str() + ": renderer: " + p.renderer_type +
                          (plan.vector ? " draws this picture without points" : " keeps no histogram") +
                          " (" + opt + "; chaos-game renders keep one)");
    };
    if (r.tone) {
        const HistogramFile& h = *r.tone;
        const std::string who = quote(h.path, 200);
        if (plan.vector || shape.width == 0) throw none("tone");
        if (h.header.version != render_version_tag())
            throw InputError(who + " was made by render version " + h.header.version + "; this fixpoint is " +
                             render_version_tag() + ", which may finish other bytes: render it again");
        if (h.header.renderer != p.renderer_type)
            throw InputError(who + " is a histogram of a " + h.header.renderer + " render, not of this " +
                             p.renderer_type + " one");
        if (!h.header.shards.empty())
            throw InputError(who + " holds " + shards_named(h.header.shards) + " of a render: merge " +
                             (h.header.shards.size() == 1 ? "it" : "every shard") +
                             " into the image with fixpoint merge");
        if (h.header.identity != p.histogram_identity)
            throw InputError(who + " is a histogram of another recipe (" +
                             recipe_difference(h.header.identity, p.histogram_identity) +
                             "); tone changes only the finishing parameters (describe marks them)");
        const HistogramShape& had = h.header.shape;
        if (had.width != shape.width || had.height != shape.height || had.hits_only != shape.hits_only ||
            had.last != shape.last)
            throw InputError(who + ": its histogram is not the one this recipe keeps (damaged?)");
        if (!r.histogram.empty()) throw InputError("--histogram: tone keeps no histogram; it reads one");
        if (plan.memory.stream)
            throw InputError("tone: this image is beyond the memory budget (see --memory); tone finishes a "
                             "whole image");
        return;
    }
    // (The preview keeps one where the renderer has one, and says nothing where it has none.)
    if (r.keep_histogram && !plan.vector && shape.width > 0) {
        plan.histogram =
            HistogramFileHeader{render_version_tag(), p.renderer_type, p.histogram_identity, p.recipe, shape};
        // (A shard kept in memory: the temporal samples of a blurred frame, animate.)
        if (r.shards) plan.histogram.shards = shard_string(r.shard - 1, r.shards);
    }
    if (r.histogram.empty() && r.shards && !r.keep_histogram)
        throw InputError(
            "--shard: name the shard's file with --histogram PART.fph (fixpoint merge sums them)");
    if (r.histogram.empty()) return;
    if (plan.vector || shape.width == 0) throw none(r.shards ? "--shard" : "--histogram");
    if (!is_histogram_file(r.histogram))
        throw InputError("--histogram: " + quote(r.histogram, 200) + ": name the file NAME.fph");
    for (const auto& [name, other] : {std::pair{"the output", plan.output}, std::pair{"the config", r.source},
                                      std::pair{"the checkpoint", plan.checkpoints.path}})
        if (!other.empty() && same_file(r.histogram, other))
            throw InputError("--histogram: " + quote(r.histogram, 200) + " is " + name +
                             ": a histogram needs a file of its own");
    std::error_code ec;
    if (!r.force && fs::exists(fs::symlink_status(r.histogram, ec)))
        throw InputError("--histogram: " + quote(r.histogram, 200) + " exists: add --force to replace it");
    const fs::path dir = fs::path(r.histogram).parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw InputError("--histogram: cannot write " + quote(r.histogram, 200) + ": no folder " +
                         quote(dir.string(), 200));
    if (::access(dir.empty() ? "." : dir.c_str(), W_OK) != 0)
        throw InputError("--histogram: cannot write " + quote(r.histogram, 200) + ": " +
                         std::strerror(errno));
    plan.histogram =
        HistogramFileHeader{render_version_tag(), p.renderer_type, p.histogram_identity, p.recipe, shape};
    if (r.shards) plan.histogram.shards = shard_string(r.shard - 1, r.shards);
}

// --shard K/N: one process's share of the render, into a histogram file and no image.
void check_shard(const RenderRequest& r) {
    if (!r.shards) return;
    if (r.shard < 1 || r.shard > r.shards || r.shards > (1u << 16))
        throw InternalError("render job: a shard out of its plan");
    if (r.distributed && ranks::size() > 1)
        throw InputError("--shard: a shard is one process's share of a render: not under mpirun");
    if (!r.output.empty())
        throw InputError("--shard: a shard makes a histogram, not an image: not with -o " +
                         quote(r.output, 200) + " (fixpoint merge makes the image of every shard)");
    if (r.tone || r.checkpoint_memory)
        throw InternalError("render job: a shard of a tone or of a quality round");
}

} // namespace

RenderPlan plan_render(const Pipeline& pipeline, RenderRequest request, const std::atomic<bool>* cancel) {
    RenderPlan plan;
    plan.pipeline = pipeline;
    plan.request = std::move(request);
    const RenderRequest& r = plan.request;
    // --strict: a recipe renders its own bytes or not at all (render_version.hpp).
    if (r.strict && !plan.pipeline.may_differ.empty())
        throw InputError(plan.pipeline.recipe_mark.str() + ": " + plan.pipeline.may_differ.front() +
                         "; refused (--strict)");
    // A pipeline whose batches run one at a time (python-scheme) takes one thread unless asked:
    // on more its threads wait for each other (1.7 times slower on 2 cores), and the summary
    // line says why.
    plan.threads = r.serial                            ? 1
                   : r.threads                         ? r.threads
                   : !plan.pipeline.one_thread.empty() ? 1
                                                       : hardware_threads();
    check_shard(r);
    RequestOutput out = request_output(plan.pipeline, r);
    plan.output = r.shards ? std::string() : std::move(out.path);
    plan.output_mark = r.shards ? std::nullopt : std::move(out.mark);
    if (!plan.output.empty()) check_output_request(plan.request, plan.output, plan.output_mark);
    check_format(plan);
    check_repeat(plan);
    // (Of the tile, not of its repeated image: --print-size is the tile's.)
    if (!plan.output.empty())
        plan.resolution =
            print_resolution(r.print, plan.pipeline.renderer->width(), plan.pipeline.renderer->height());
    check_memory_plan(plan);
    check_checkpoints(plan);
    check_histograms(plan);
    if (cancel && cancel->load()) throw Cancelled(); // during the checks above
    if (r.distributed) ranks::agree_checks(plan.pipeline.recipe);
    return plan;
}

} // namespace fp::host

// ---------------------------------------------------------------- the render
namespace fp::host {

namespace {

/// The rows of a rank other than 0 in a streamed render: rank 0 writes the image.
class DiscardedRows final : public RowSink {
public:
    void rows(int, int, const float*) override {}
};

/// A plugin's refusal during the render (one that can only tell at run time) is blamed on the
/// renderer, the one place known; a failed write of the output (WriteError, from a streamed
/// image) keeps its own words, and so does everything else.
template <class Body>
void blamed(const Pipeline& p, Body&& body) {
    try {
        body();
    } catch (const WriteError&) {
        throw;
    } catch (const InputError& e) {
        throw InputError(p.renderer_mark.str() + ": renderer: " + e.what());
    }
}

/// The folder of a file the request lets the job make, made just before the file is written.
void make_folder_of(const std::string& path) {
    const fs::path dir = fs::path(path).parent_path();
    std::error_code ec;
    if (dir.empty() || fs::is_directory(dir, ec)) return;
    fs::create_directories(dir, ec);
    if (ec) throw InputError("cannot make the folder " + quote(dir.string(), 200) + ": " + ec.message());
}

/// The recipe a file carries: a repeated tile says so (its recipe renders one tile).
std::string file_recipe(const RenderPlan& plan) {
    if (plan.repeat.across * plan.repeat.down == 1) return plan.pipeline.recipe;
    return "# the tile repeated " + plan.request.print.repeat + " (--repeat); the recipe renders one tile\n" +
           plan.pipeline.recipe;
}

} // namespace

std::uint64_t plan_work_units(const RenderPlan& plan) {
    const std::uint64_t units = plan.pipeline.renderer->work_units();
    const unsigned n = plan.request.shards        ? plan.request.shards
                       : plan.request.distributed ? ranks::size()
                                                  : 1;
    return n > 1 ? (units + n - 1) / n : units;
}

RenderResult run_render(RenderPlan& plan, const RenderHooks& hooks) {
    const Pipeline& p = plan.pipeline;
    const RenderRequest& r = plan.request;
    const Renderer& R = *p.renderer;
    Runtime rt(plan.threads, hooks.cancel, r.distributed, r.serial);
    if (r.shards) rt.set_shard(r.shard - 1, r.shards);
    // The process that writes: rank 0, or a shard (which writes its histogram alone).
    const bool writes = rt.rank() == 0 || rt.shard();
    rt.set_memory_budget(plan.memory.budget);
    if (hooks.done) rt.count_progress_in(hooks.done);
    CheckpointPlan& ck = plan.checkpoints;
    if (!ck.path.empty() || ck.memory)
        rt.set_checkpoints(ck.path, ck.every_s, ck.header, std::move(ck.resume));
    if (ck.memory) rt.keep_checkpoints_in(ck.memory);

    // The kept histogram: rank 0 writes it, to a temporary file that takes its name once the
    // render is done.
    std::unique_ptr<HistogramWriter> kept;
    if (!r.histogram.empty() && plan.histogram.shape.width > 0 && writes) {
        kept = std::make_unique<HistogramWriter>(r.histogram, plan.histogram);
        rt.keep_histogram_in(kept.get());
    }
    std::shared_ptr<HistogramFile> in_memory;
    if (hooks.histogram_rows && rt.rank() == 0) rt.keep_histogram_in(hooks.histogram_rows);
    if (r.keep_histogram && plan.histogram.shape.width > 0 && writes) {
        in_memory = std::make_shared<HistogramFile>();
        in_memory->header = plan.histogram;
        rt.keep_histogram_in(&in_memory->histogram, plan.histogram.shape, r.shards != 0);
    }

    // A streamed image: rank 0 encodes the rows as they come, into a file that takes the
    // output's name only once it is whole; the other ranks' rows go nowhere.
    std::unique_ptr<StreamedImage> streamed;
    DiscardedRows discarded;
    if (plan.memory.stream && rt.rank() == 0 && !r.shards) {
        if (r.make_folder) make_folder_of(plan.output);
        streamed = std::make_unique<StreamedImage>(plan.output, R.width(), R.height(), p.bit_depth, p.recipe,
                                                   plan.resolution, p.tiled);
        if (hooks.partial) hooks.partial(streamed->temporary_path());
    }

    RenderResult res;
    Image img;
    std::string doc;
    const auto t0 = std::chrono::steady_clock::now();
    {
        ProgressBar bar(
            plan_work_units(plan), [&rt] { return rt.done(); }, hooks.progress_bar && writes,
            hooks.progress_label);
        blamed(p, [&] {
            if (plan.vector)
                doc = R.render_vector(rt, res.stats,
                                      plan.format == Format::Svg ? VectorFormat::Svg : VectorFormat::Pdf,
                                      p.recipe);
            else if (r.tone)
                img = R.finish_histogram(r.tone->histogram, res.stats = r.tone->stats, rt);
            else if (plan.memory.stream)
                R.render_rows(rt, res.stats, streamed ? static_cast<RowSink&>(*streamed) : discarded);
            else
                img = R.render(rt, res.stats);
        });
        res.checkpoints_written = rt.checkpoints_written();
    }
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (rt.cancelled()) throw Cancelled();
    if (!writes) return res; // rank 0 holds the image and writes
    res.width = plan.vector || plan.memory.stream ? R.width() : img.width;
    res.height = plan.vector || plan.memory.stream ? R.height() : img.height;
    // (A shard's few points are no sign of an empty picture: merge tells of the whole.)
    if (!r.allow_empty && !r.shards)
        if (std::string w = check_drawn(p, res.stats); !w.empty()) res.warnings.push_back(std::move(w));
    // The other ranks are done: rank 0's errors from here on are its own.
    if (rt.ranks() > 1) ranks::set_phase(ranks::Phase::free);
    // (A streamed --quality round that falls short: its temporary files are removed.)
    const bool keep = !streamed || !hooks.keep_files || hooks.keep_files();
    if (kept && keep) kept->commit(res.stats);
    if (in_memory) {
        in_memory->stats = res.stats;
        res.kept = std::move(in_memory);
    }
    if (r.shards) { // its histogram is what it makes
        res.wrote = kept != nullptr;
        return res;
    }

    if (streamed) {
        if (hooks.partial) hooks.partial("");
        if (keep) streamed->finish(); // (else its destructor removes the temporary file)
        res.wrote = keep;
        return res;
    }
    if (r.encode) res.bytes = encode_image(img, plan.format, p.bit_depth, p.recipe, plan.resolution, p.tiled);
    if (!plan.output.empty() && !r.defer_write) {
        if (plan.vector) {
            if (r.make_folder) make_folder_of(plan.output);
            FileSet file(hooks.cancel);
            file.bytes(doc, plan.output);
            file.commit();
        } else {
            write_render(plan, img, hooks);
        }
        res.wrote = true;
    }
    if (r.keep_image) res.image = std::move(img);
    return res;
}

void write_render(const RenderPlan& plan, const Image& img, const RenderHooks& hooks) {
    const Pipeline& p = plan.pipeline;
    if (plan.request.make_folder) make_folder_of(plan.output);
    FileSet file(hooks.cancel); // (a Ctrl-C while it is encoded and written: no file)
    file.image(repeat_image(img, plan.repeat), plan.output, p.bit_depth, file_recipe(plan), p.tiled,
               plan.resolution);
    file.commit();
}

std::string summary_line(const RenderPlan& plan, const RenderResult& r) {
    const RenderStats& st = r.stats;
    const auto plural = [](std::uint64_t n, const char* one) {
        return std::to_string(n) + " " + one + (n == 1 ? "" : "s");
    };
    if (plan.request.tone && !plan.request.tone->path.empty()) {
        // No iterating: what the histogram holds, and the time of the finish alone.
        char took[64];
        std::snprintf(took, sizeof took, "%.3f s", r.seconds);
        return (plan.output.empty() ? std::string("tone") : plan.output) + ": finished from " +
               plan.request.tone->path + " (" + std::to_string(st.samples) + " " + st.unit + ") in " + took +
               " (" + plural(plan.threads, "thread") + ", no iterating)";
    }
    char rate[160];
    std::snprintf(rate, sizeof rate, "%.2f s (%.3g %s/s, ", r.seconds,
                  double(st.samples) / std::max(r.seconds, 1e-9), st.unit.c_str());
    const unsigned nr = plan.request.distributed ? ranks::size() : 1;
    const RenderRequest& q = plan.request;
    const std::string who =
        q.shards ? q.histogram + ": shard " + std::to_string(q.shard) + "/" + std::to_string(q.shards) + ","
        : plan.output.empty() ? std::string("render:")
                              : plan.output + ":";
    std::string line = who + " " + std::to_string(st.samples) + " " + st.unit + " in " + rate +
                       (nr > 1 ? std::to_string(nr) + " ranks x " : "") + plural(plan.threads, "thread") +
                       ", " + simd::active_target() + "), " + plural(st.restarts, "restarted chain") + ", " +
                       plural(st.bad_values, "bad value") + (st.how.empty() ? "" : ", " + st.how);
    if (!q.threads && !q.serial && !plan.pipeline.one_thread.empty())
        line += "; 1 thread, as " + plan.pipeline.one_thread + " (--threads N for more)";
    if (!plan.checkpoints.path.empty())
        line += "; " + plural(r.checkpoints_written, "checkpoint") + " to " + plan.checkpoints.path +
                (nr > 1 ? " (each rank to its own)" : "");
    if (!q.histogram.empty() && !q.shards) line += "; histogram to " + q.histogram;
    return line;
}

} // namespace fp::host
