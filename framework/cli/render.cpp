// The render family: render (one image, or a --vary collection), validate, animate, watch.
// Every render goes through the host's render job (host/job/render_job.hpp); this file only
// turns the command line into requests.
#include "cli.hpp"

#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/host/core/ranks.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/host/job/collection.hpp>
#include <fixpoint/host/job/draft.hpp>
#include <fixpoint/host/job/quality.hpp>
#include <fixpoint/host/tools/animate.hpp>
#include <fixpoint/host/tools/watch.hpp>
#include <fixpoint/text.hpp>

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <tuple>
#include <utility>

namespace fs = std::filesystem;

using namespace fp::host;

namespace fp::cli {

namespace {

// --draft: `sets` and the assignments that make the draft of the pipeline they give
// (host/job/draft.hpp).
std::vector<std::string> with_draft(std::vector<std::string> sets, const Pipeline& full) {
    for (auto& s : draft_overrides(full, draft_factor)) sets.push_back(std::move(s));
    return sets;
}

// --shard K/N: share K (1 to N) of N.
std::pair<unsigned, unsigned> parse_shard(const std::string& text) {
    const auto bad = [&] {
        return InputError(
            "--shard: " + quote(text, 100) +
            " is not K/N: the K-th of N equal shares of the chains, 1 <= K <= N <= 65536 (such as 2/8)");
    };
    const std::size_t slash = text.find('/');
    if (slash == std::string::npos || slash == 0 || slash + 1 == text.size() || text.size() > 13) throw bad();
    const std::string k = text.substr(0, slash), n = text.substr(slash + 1);
    if (k.find_first_not_of("0123456789") != std::string::npos ||
        n.find_first_not_of("0123456789") != std::string::npos)
        throw bad();
    const unsigned long K = std::stoul(k), N = std::stoul(n);
    if (K < 1 || N < 1 || K > N || N > 65536) throw bad();
    return {unsigned(K), unsigned(N)};
}

// The request of `render -o OUT ...`: the default file (the config's output.path or its name),
// replaced only when named with -o or with --force.
RenderRequest render_request(const Options& o) {
    RenderRequest r;
    r.output = o.out;
    r.default_file = true;
    r.force = o.force;
    r.draft_name = o.draft;
    r.source = o.config;
    r.threads = o.threads;
    r.memory = o.memory.empty() ? 0 : parse_size(o.memory, "--memory");
    r.distributed = true;
    r.print = o.print;
    r.checkpoint = o.checkpoint, r.checkpoint_every = o.checkpoint_every, r.resume = o.resume;
    r.histogram = o.histogram;
    r.strict = o.strict;
    if (!o.shard.empty()) std::tie(r.shard, r.shards) = parse_shard(o.shard);
    return r;
}

// render --quality Q: host/job/quality.hpp; the rounds' recipe is the config's with
// renderer.points doubled each round.
int cmd_quality(const Options& o) {
    const Registry reg = make_registry(o);
    QualityRequest q;
    q.target = o.quality;
    q.reload = [&](std::int64_t points) {
        std::vector<std::string> sets = o.sets;
        if (points > 0) sets.push_back("renderer.points=" + std::to_string(points));
        Pipeline p = load_for_print(reg, o.config, sets, o.print, o.allow_python);
        if (points == 0 && !o.strict) told(p);
        return p;
    };
    if (!o.quiet) q.info = [](const std::string& l) { spdlog::info("{}", l); };
    const QualityResult res = render_to_quality(q, render_request(o), render_hooks(o.quiet));
    tell(res.result.warnings);
    if (!o.quiet) {
        char level[160];
        std::snprintf(level, sizeof level,
                      "; quality %.2f (log2 of %.3g points per lit pixel; target %g) after %d round%s",
                      res.level, std::exp2(res.level), o.quality, res.rounds, res.rounds == 1 ? "" : "s");
        spdlog::info("{}{}", summary_line(res.plan, res.result), level);
    }
    return 0;
}

// tone: the image finished again from a kept histogram (host/core/histogram_file.hpp), with the
// finishing parameters --set changes; the render job checks that nothing else changed.
int cmd_tone(const Options& o) {
    install_sigint();
    if (!is_histogram_file(o.config))
        throw InputError("tone: " + quote(o.config, 200) +
                         " is not a histogram file: name one (.fph) that render --histogram wrote");
    const Registry reg = make_registry(o);
    // render's request (its output, threads, memory), finished whole on one process.
    RenderRequest r = render_request(o);
    r.distributed = false;
    r.may_stream = false;
    // The recipe first (its errors at their place), then the bins.
    Pipeline p = load_pipeline(reg, o.config, o.sets, "", o.allow_python);
    told(p);
    r.tone = std::make_shared<HistogramFile>(
        read_histogram_file(o.config, r.memory ? r.memory : available_memory()));
    RenderPlan plan = plan_render(p, std::move(r), &interrupted());
    const RenderResult res = run_render(plan, render_hooks(o.quiet));
    tell(res.warnings);
    if (!o.quiet) spdlog::info("{}", summary_line(plan, res));
    return 0;
}

// merge: the shards' histograms (render --shard K/N --histogram PART.fph) summed; into an image
// (finished as tone finishes a kept histogram: the bytes of the single render) or into a
// histogram file (a merge of some shards merges again).
int cmd_merge(const Options& o) {
    install_sigint();
    if (o.out.empty())
        throw InputError("merge: name the output with -o: an image (.png, .exr, .tif) or a histogram (.fph)");
    const std::uint64_t memory = o.memory.empty() ? available_memory() : parse_size(o.memory, "--memory");
    const std::string many = o.files.size() == 1
                                 ? o.files.front()
                                 : o.files.front() + " and " + std::to_string(o.files.size() - 1) + " more";
    if (is_histogram_file(o.out)) {
        if (!o.sets.empty())
            throw InputError("merge: --set changes the image's finish: not with -o " + quote(o.out, 200) +
                             ", a histogram (fixpoint tone finishes it)");
        std::error_code ec;
        for (const std::string& f : o.files)
            if (f == o.out || fs::equivalent(f, o.out, ec))
                throw InputError("merge: -o " + quote(o.out, 200) + " is one of the shards: name a new file");
        if (!o.force && fs::exists(fs::symlink_status(o.out, ec)))
            throw InputError("merge: " + quote(o.out, 200) + " exists: add --force to replace it");
        if (const fs::path dir = fs::path(o.out).parent_path(); !dir.empty() && !fs::is_directory(dir, ec))
            throw InputError("merge: cannot write " + quote(o.out, 200) + ": no folder " +
                             quote(dir.string(), 200));
        const auto t0 = std::chrono::steady_clock::now();
        const HistogramFile m = merge_histograms(o.files, memory, false);
        if (interrupted()) throw Cancelled();
        HistogramWriter w(o.out, m.header);
        w.rows(m.histogram, 0, 0, m.histogram.height);
        if (interrupted()) throw Cancelled();
        w.commit(m.stats);
        if (!o.quiet)
            spdlog::info("{}: merged {} ({}; {} points) in {:.3f} s", o.out, many,
                         m.header.shards.empty() ? std::string("the whole render")
                                                 : shards_named(m.header.shards),
                         m.stats.samples,
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        return 0;
    }
    const Registry reg = make_registry(o);
    RenderRequest r = render_request(o);
    r.source = o.files.front();
    r.distributed = false;
    r.may_stream = false;
    check_output_request(r, o.out);
    // The recipe first (its errors at their place), then the shards, then the image as tone
    // makes it.
    Pipeline p = load_pipeline(reg, o.files.front(), o.sets, "", o.allow_python);
    told(p);
    auto m = std::make_shared<HistogramFile>(merge_histograms(o.files, memory, true));
    m->path = many;
    r.tone = std::move(m);
    RenderPlan plan = plan_render(p, std::move(r), &interrupted());
    const RenderResult res = run_render(plan, render_hooks(o.quiet));
    tell(res.warnings);
    if (!o.quiet) spdlog::info("{}", summary_line(plan, res));
    return 0;
}

int cmd_collection(const Options& o, bool validate_only) {
    const Registry reg = make_registry(o);
    CollectionRequest c;
    c.config = o.config, c.sets = o.sets, c.vary = o.vary, c.columns = o.columns;
    c.allow_code = o.allow_python, c.draft = o.draft, c.validate_only = validate_only;
    c.sheet = render_request(o);
    c.sheet.memory = 0;
    if (!o.quiet) c.info = [](const std::string& l) { spdlog::info("{}", l); };
    c.warn = [](const std::string& w) { spdlog::warn("warning: {}", w); };
    run_collection(reg, c, render_hooks(o.quiet || ranks::rank() != 0));
    return 0;
}

int cmd_render(const Options& o, bool validate_only) {
    install_sigint();
    // Under mpirun: the checks below run on every rank and are agreed before the render.
    // (validate runs on rank 0 alone.)
    if (ranks::size() > 1 && !validate_only) ranks::set_phase(ranks::Phase::checking);
    // (validate has no --shard.)
    if (!o.shard.empty() && (!o.vary.empty() || !std::isnan(o.quality) || o.print.any() || o.draft))
        throw InputError(
            "--shard renders a share of one recipe's chains: not with --vary, --quality, --draft, "
            "--tile, --repeat, --dpi or --print-size");
    if (!o.vary.empty() && o.print.any())
        throw InputError("--tile, --repeat, --dpi and --print-size make one image: not with --vary");
    if (!o.vary.empty() && !o.memory.empty())
        throw InputError(
            "--memory bounds one render (in strips): not with --vary, whose children render whole");
    if (!o.vary.empty() && (!o.checkpoint.empty() || !o.resume.empty()))
        throw InputError("--checkpoint and --resume keep one render: not with --vary");
    if (!o.vary.empty() && !o.histogram.empty())
        throw InputError("--histogram keeps one render's histogram: not with --vary");
    if (!std::isnan(o.quality) && (!o.vary.empty() || o.draft))
        throw InputError("--quality renders one image to a sample level: not with --vary or --draft");
    if (!std::isnan(o.quality) && !validate_only) return cmd_quality(o);
    if (!o.vary.empty()) return cmd_collection(o, validate_only);
    if (o.draft && (o.print.dpi > 0 || !o.print.print_size.empty()))
        throw InputError("--draft: a quick small image: not with --dpi or --print-size");
    const Registry reg = make_registry(o);
    Pipeline p = load_for_print(reg, o.config, o.sets, o.print, o.allow_python);
    if (o.draft) p = load_for_print(reg, o.config, with_draft(o.sets, p), o.print, o.allow_python);
    if (!o.strict) told(p); // (with --strict, what may differ is the one error line)
    // validate checks the config, not the folder's state: an output that exists (the image of
    // the last render, most often) is noted, not refused; render would refuse it unless named
    // or forced.
    RenderRequest request = render_request(o);
    if (validate_only) request.force = true;
    RenderPlan plan = plan_render(p, request, &interrupted());
    if (validate_only) {
        // The animation's frames are checked before "valid" is said of anything.
        const std::string animation = validate_animation(reg, o.config, o.sets, &interrupted());
        if (!o.quiet) {
            spdlog::info("{}: valid: a {}x{} render to {}", o.config, p.renderer->width(),
                         p.renderer->height(), plan.output);
            if (!animation.empty()) spdlog::info("{}: valid: {}", o.config, animation);
            std::error_code ec;
            if (!o.force && o.out.empty() && !plan.output.empty() &&
                fs::exists(fs::symlink_status(plan.output, ec)))
                spdlog::info("{}: note: {} exists: render replaces it only when it is named with -o or "
                             "given --force",
                             o.config, quote(plan.output, 200));
        }
        return 0;
    }
    const RenderResult r = run_render(plan, render_hooks(o.quiet));
    if (!r.wrote) return 0; // a rank other than 0: rank 0 writes
    tell(r.warnings);
    if (!o.quiet) spdlog::info("{}", summary_line(plan, r));
    return 0;
}

// animate: host/tools/animate.hpp; each frame rendered by the job as render renders one.
int cmd_animate(const Options& o, AnimateOptions ao) {
    install_sigint();
    const Registry reg = make_registry(o);
    ao.config = o.config, ao.sets = o.sets, ao.quiet = o.quiet, ao.force = o.force;
    ao.threads = o.threads; // (0: the job's default, per frame)
    ao.info = [](const std::string& s) { spdlog::info("{}", s); };
    ao.warn = [](const std::string& s) { spdlog::warn("{}", s); };
    try {
        return animate(reg, ao, render_hooks(o.quiet));
    } catch (const Cancelled&) {
        std::fprintf(stderr, "fixpoint: interrupted; the frames written are kept: run again to continue\n");
        return 130;
    }
}

// watch: the lines go to stderr like render's; an error keeps the last good image.
int cmd_watch(const Options& o) {
    install_sigint();
    WatchOptions w;
    w.config = o.config;
    w.out = o.out;
    w.sets = o.sets;
    w.threads = o.threads; // (0: the job's default)
    w.no_draft = o.no_draft;
    const bool quiet = o.quiet;
    w.info = [quiet](const std::string& l) {
        if (!quiet) spdlog::info("{}", l);
    };
    w.error = [](const std::string& l) { spdlog::error("{}", l); };
    return watch(make_registry(o), w, interrupted());
}

} // namespace

void add_render_commands(CLI::App& app, Options& o, std::vector<Command>& table) {
    auto* render = app.add_subcommand("render", "Render a pipeline to an image");
    render
        ->add_option("config", o.config,
                     "Pipeline file (YAML), or an image fixpoint wrote: its recipe is rendered (without "
                     "its output.path)")
        ->required();
    render->add_option("-o,--output", o.out,
                       "Output image (.png, .exr, .tif; .svg or .pdf for renderers with vector output); "
                       "default: the config's output.path or <config>.png");
    add_sets(render, o.sets);
    add_threads(render, o.threads, "Worker threads (default: all cores); the image does not depend on it");
    render->add_option("--memory", o.memory,
                       "Memory the render may take, such as 8G or 512M (default: what the machine has "
                       "available); a chaos-game image over it renders in strips, with the same bytes");
    render->add_option("--checkpoint", o.checkpoint,
                       "Save the render's state to FILE every --checkpoint-every and when it ends, so that "
                       "--resume FILE continues it after a crash or a kill (chaos-game, orbit-trap)");
    render->add_option("--checkpoint-every", o.checkpoint_every,
                       "Time between checkpoints, such as 30s, 5m or 1h (default: 5m)");
    render->add_option("--resume", o.resume,
                       "Continue the render saved in FILE (the same bytes as one uninterrupted render), or a "
                       "finished one to more points with --set renderer.points=N; checkpoints go on in FILE "
                       "unless --checkpoint names another");
    render->add_option(
        "--quality", o.quality,
        "Go on until the sample level (log2 of the points drawn per lit pixel, Chaotica's "
        "measure) reaches Q: the points double from renderer.points each round, and the image's "
        "recipe holds the points it stopped at (chaos-game; docs/histograms.md)");
    render->add_option("--histogram", o.histogram,
                       "Keep the render's histogram in FILE.fph too, so that `fixpoint tone FILE.fph` "
                       "finishes it again with other tone, filter or density estimation, with no "
                       "iterating (chaos-game; docs/histograms.md)");
    render->add_option(
        "--shard", o.shard,
        "Render only the K-th of N equal shares of the chains (K/N, such as 3/8) into --histogram "
        "PART.fph, and no image: `fixpoint merge` sums the N shards into the bytes of the whole "
        "render (chaos-game; docs/cluster.md)");
    render->add_flag("-q,--quiet", o.quiet, "No progress bar, no summary");
    render->add_flag("--allow-python", o.allow_python,
                     "Run the Python of a python-scheme in a recipe read from an image (refused by default: "
                     "an image may come from anywhere)");
    render->add_flag("--strict", o.strict,
                     "Refuse a recipe whose image may differ from the one it was made of: one of an older "
                     "render version whose changes touch it, or made with another version of a plugin "
                     "(docs/render-versions.md)");
    render->add_flag("--force", o.force,
                     "Replace an existing output that was not named with -o (the config's output.path or "
                     "the default name)");
    render->add_flag("--draft", o.draft,
                     "A quick draft of the same recipe: width and height / 4, points / 16 (orbit-trap: 1 "
                     "sample per pixel); written to <output>-draft.png unless -o names the file");
    render->add_option("--vary", o.vary,
                       "Render a collection: one child per value (path.to.param=V1,V2,... or A..B), each to "
                       "OUT-<k>.png, and a contact sheet with captions to OUT");
    render->add_option("--columns", o.columns, "Columns of the contact sheet (default: about square)")
        ->check(CLI::Range(1, 1000));
    render->add_flag("--tile", o.print.tile,
                     "Render one period of a periodic pattern (orbit-trap with a wallpaper map, Picard), so "
                     "that copies join without a seam: the smallest rectangle of periods centred on the "
                     "area's centre, at the config's width, the height following (square pixels)");
    render->add_option("--repeat", o.print.repeat,
                       "With --tile: write the tile repeated NxM times (3x3), to see it join");
    render
        ->add_option("--dpi", o.print.dpi,
                     "Print resolution in pixels per inch, written into the image (TIFF and PNG); with "
                     "--print-size it sets the size in pixels")
        ->check(CLI::PositiveNumber);
    render->add_option("--print-size", o.print.print_size,
                       "Physical size, WIDTH or WIDTHxHEIGHT in mm, cm or in (30cm, 30cmx20cm): with --dpi "
                       "the size in pixels, alone the resolution written (pixels / size); a 16-bit TIFF "
                       "for print: -o out.tif --set output.bit_depth=16");
    table.push_back({render, [&o] { return cmd_render(o, false); }});

    auto* tone = app.add_subcommand(
        "tone", "Finish a kept histogram (render --histogram) into an image again, with other finishing "
                "parameters, with no iterating: the bytes of a render of that recipe");
    tone->add_option("histogram", o.config, "Histogram file (.fph) that render --histogram wrote")
        ->required();
    tone->add_option("-o,--output", o.out, "Output image (.png, .exr, .tif); default: <histogram>.png");
    add_sets(tone, o.sets,
             "Change a finishing parameter: renderer.filter=..., renderer.estimator_radius=..., "
             "renderer.background=..., renderer.colourer.gamma=... (repeatable; describe marks them)");
    add_threads(tone, o.threads, "Worker threads (default: all cores); the image does not depend on it");
    tone->add_option("--memory", o.memory, "Memory the histogram and image may take (as render --memory)");
    tone->add_flag("-q,--quiet", o.quiet, "No summary");
    tone->add_flag("--allow-python", o.allow_python,
                   "Build a python-scheme of the histogram's recipe (refused by default: "
                   "a file may come from anywhere)");
    tone->add_flag("--force", o.force, "Replace an existing output that was not named with -o");
    table.push_back({tone, [&o] { return cmd_tone(o); }});

    auto* merge = app.add_subcommand(
        "merge", "Sum the shards of a render (render --shard K/N --histogram PART.fph) into its image, the "
                 "bytes of the single render, or into a histogram file that merges again");
    merge->add_option("shards", o.files, "The shards' histogram files (.fph), in any order")->required();
    merge->add_option("-o,--output", o.out,
                      "The image (.png, .exr, .tif; every shard needed), or a histogram (.fph; any of them)");
    add_sets(merge, o.sets, "Change a finishing parameter of the image, as tone does (repeatable)");
    add_threads(merge, o.threads, "Worker threads (default: all cores); the image does not depend on it");
    merge->add_option("--memory", o.memory, "Memory the histograms and image may take (as render --memory)");
    merge->add_flag("-q,--quiet", o.quiet, "No summary");
    merge->add_flag("--allow-python", o.allow_python,
                    "Build a python-scheme of the shards' recipe (refused by default: a file may come from "
                    "anywhere)");
    merge->add_flag("--force", o.force, "Replace an existing histogram file");
    table.push_back({merge, [&o] { return cmd_merge(o); }});

    auto* validate = app.add_subcommand("validate", "Check everything a render would check; render nothing");
    validate->add_option("config", o.config, "Pipeline file (YAML)")->required();
    validate->add_option("-o,--output", o.out, "Output image to check");
    add_sets(validate, o.sets);
    add_threads(validate, o.threads, "Threads to check memory for");
    validate->add_option("--memory", o.memory, "Memory to check the render against (as render --memory)");
    validate->add_flag("-q,--quiet", o.quiet, "Print nothing when valid");
    validate->add_flag("--force", o.force, "Check as render --force would");
    validate->add_flag("--allow-python", o.allow_python,
                       "Run the Python of a python-scheme in a recipe read from an image (refused by "
                       "default: an image may come from anywhere)");
    validate->add_flag("--strict", o.strict, "Check as render --strict would");
    validate->add_option("--vary", o.vary, "Check every child of a collection (as render --vary)");
    table.push_back({validate, [&o] { return cmd_render(o, true); }});

    AnimateOptions& ao = o.animate;
    auto* animate_cmd = app.add_subcommand(
        "animate", "Render the frames of a config's animation: section, and a video with ffmpeg");
    animate_cmd->footer(animate_help());
    animate_cmd->add_option("config", o.config, "Pipeline file (YAML) with an animation: section")
        ->required();
    animate_cmd->add_option("-o,--output", ao.pattern,
                            "The frames' files, with one frame number: frames/%04d.png (.png, .exr, .tif); "
                            "the folder is made");
    animate_cmd->add_option("--frames", ao.frames, "Only frames A..B (or one frame K); default: all");
    animate_cmd->add_option("--video", ao.video,
                            "Assemble the frames (of --frames) into a video with ffmpeg: .mp4, .mkv, .mov "
                            "(H.264) or .gif");
    add_sets(animate_cmd, o.sets,
             "Override a value before the animation's: path.to.param=value (repeatable; "
             "--set animation.frames=3 too)");
    add_threads(animate_cmd, o.threads);
    animate_cmd->add_flag("--list", ao.list,
                          "Check every frame and print each frame's values as --set takes them; render "
                          "nothing");
    animate_cmd->add_flag("-q,--quiet", o.quiet, "No progress bar, no log");
    animate_cmd->add_flag("--force", o.force,
                          "Replace frame files made with another recipe, and an existing video");
    table.push_back({animate_cmd, [&o] { return cmd_animate(o, o.animate); }});

    auto* watch_cmd = app.add_subcommand(
        "watch", "Render a config again each time it is saved: a draft, then the full image (Ctrl-C stops)");
    watch_cmd->add_option("config", o.config, "Pipeline file (YAML)")->required();
    watch_cmd->add_option("-o,--output", o.out, "The image written (replaced at each save)")->required();
    add_sets(watch_cmd, o.sets);
    add_threads(watch_cmd, o.threads);
    watch_cmd->add_flag("--no-draft", o.no_draft, "The full image only, no draft first");
    watch_cmd->add_flag("-q,--quiet", o.quiet, "Print only errors");
    table.push_back({watch_cmd, [&o] { return cmd_watch(o); }});
}

} // namespace fp::cli
