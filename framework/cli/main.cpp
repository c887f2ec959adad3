// The `fixpoint` command line.
//
// Exit codes: 0 success, 2 bad input (config, parameters, command line), 1 internal
// failure or a check's "no" (`symmetry --group G`: G is not kept), 130 interrupted. Every
// error is one line on stderr.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/animate.hpp>
#include <fixpoint/host/build.hpp>
#include <fixpoint/host/checkpoint.hpp>
#include <fixpoint/host/conformance.hpp>
#include <fixpoint/host/converse.hpp>
#include <fixpoint/host/draft.hpp>
#include <fixpoint/host/explore.hpp>
#include <fixpoint/host/image_io.hpp>
#include <fixpoint/host/pipeline.hpp>
#include <fixpoint/host/print.hpp>
#include <fixpoint/host/progress.hpp>
#include <fixpoint/host/ranks.hpp>
#include <fixpoint/host/registry.hpp>
#include <fixpoint/host/runtime.hpp>
#include <fixpoint/host/serve.hpp>
#include <fixpoint/host/symmetry.hpp>
#include <fixpoint/host/tools/describe.hpp>
#include <fixpoint/host/watch.hpp>
#include <fixpoint/host/where.hpp>
#include <fixpoint/simd.hpp>
#include <fixpoint/version.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <array>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace fp;
using namespace fp::host;

namespace {

std::atomic<bool> g_interrupted{false};

// Under mpirun: the checks before a render failed on some rank; every rank learnt the first
// failing rank's error line (ranks::agree), which rank 0 prints.
struct AgreedFailure {
    ranks::Verdict verdict;
};

// Under mpirun, once every check before a render has passed on this rank: wait for the
// others' verdicts. A rank that failed makes every rank stop here with its error line, before
// any rank starts the work (and its collective calls).
void agree_checks(const std::string& recipes) {
    if (ranks::size() <= 1 || ranks::phase() != ranks::Phase::checking) return;
    const ranks::Verdict v = ranks::agree(0, "", ranks::fingerprint(recipes));
    ranks::set_phase(v.code ? ranks::Phase::free : ranks::Phase::rendering);
    if (v.code) throw AgreedFailure{v};
}

// An error line as the terminal shows it: one line whatever the input it echoes held
// (newlines, terminal escapes, bytes that are not UTF-8 become escapes), and of a readable
// length: a line longer than about 1000 characters keeps its start and its end (where the
// reason is) and says how much was cut (a 4 kB file name quoted twice).
std::string error_line(const std::string& raw) {
    const std::string line = excerpt(raw, std::string::npos);
    constexpr std::size_t keep = 480;
    if (line.size() <= 2 * keep + 64) return line;
    // Cut at UTF-8 character boundaries.
    std::size_t head = keep, tail = line.size() - keep;
    while (head > 0 && (static_cast<unsigned char>(line[head]) & 0xc0) == 0x80) --head;
    while (tail < line.size() && (static_cast<unsigned char>(line[tail]) & 0xc0) == 0x80) ++tail;
    return line.substr(0, head) + " [... " + std::to_string(tail - head) + " bytes cut ...] " +
           line.substr(tail);
}

// An error line and the exit code: as is on one process; under mpirun, as the rank's phase
// requires (host/ranks.hpp): agreed with the others during the checks, or ending the whole job
// during the render (the other ranks may be waiting for this one).
int report(int code, const std::string& raw) {
    const std::string line = error_line(raw);
    if (ranks::size() <= 1) {
        std::fprintf(stderr, "%s\n", line.c_str());
        return code;
    }
    switch (ranks::phase()) {
    case ranks::Phase::checking: {
        ranks::set_phase(ranks::Phase::free);
        const ranks::Verdict v = ranks::agree(code, line);
        if (ranks::rank() == 0) std::fprintf(stderr, "%s\n", v.message.c_str());
        return v.code;
    }
    case ranks::Phase::rendering:
        std::fprintf(stderr, "fixpoint: rank %u of %u: %s\n", ranks::rank(), ranks::size(), line.c_str());
        std::fflush(stderr);
        ranks::abort(code);
    case ranks::Phase::free: break;
    }
    if (ranks::rank() == 0) std::fprintf(stderr, "%s\n", line.c_str());
    return code;
}

// The temporary file a streamed render is writing (StreamedImage), removed by the signal
// handler too: a rank that fails mid-render ends the job with MPI_Abort, and mpirun then
// terminates rank 0 inside a collective, where no destructor runs. (unlink is safe in a
// handler; the path is written before the handler can see it, and cleared after.)
char g_partial_output[4096];
std::atomic<bool> g_has_partial_output{false};

extern "C" void on_sigint(int) {
    g_interrupted.store(true);
    if (g_has_partial_output.load()) ::unlink(g_partial_output);
}

void install_sigint() {
    struct sigaction sa {};
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

struct Options {
    std::vector<std::string> plugin_dirs;
    std::string config, out, image, name, transform, scheme = "{type: picard}", kind;
    std::vector<std::string> sets, files, where, maps;
    std::string vary, example, points;
    std::string memory; // --memory SIZE ("" : what the machine has available)
    // --checkpoint FILE, --checkpoint-every TIME ("": 5m), --resume FILE
    std::string checkpoint, checkpoint_every, resume;
    int columns = 0;
    unsigned threads = 0;
    bool quiet = false, force = false, check = false, verbose = false, draft = false, no_draft = false;
    bool allow_python = false; // --allow-python: a recipe read from an image may run its Python
    std::string steps = "1";
    long long level = -1;
    // symmetry
    std::string group, area, against;
    std::vector<std::string> images;
    std::vector<std::string> ops;
    double tolerance = SymmetryOptions{}.tolerance, threshold = SymmetryOptions{}.threshold;
    int smooth = SymmetryOptions{}.smooth;
    bool json = false;
    bool markdown = false; // describe --markdown
    PrintRequest print;    // --tile, --repeat, --dpi, --print-size
};

Registry make_registry(const Options& o) {
    Registry reg;
    for (const auto& d : Registry::default_dirs()) reg.load_dir(d);
    for (const auto& d : o.plugin_dirs) {
        std::error_code ec;
        if (!fs::is_directory(d, ec)) throw InputError("--plugin-dir: '" + d + "' is not a folder");
        reg.load_dir(d);
    }
    // A plugin file that did not load is skipped with one line each (`plugins --check` lists
    // them instead); a config that asks for a plugin it would have provided fails naming it.
    if (!o.check)
        for (const auto& r : reg.refused()) spdlog::warn("warning: plugin file skipped: {}", r.reason);
    return reg;
}

/// A pipeline's warnings (a plugin other than the recipe's), one line each.
const Pipeline& told(const Pipeline& p) {
    for (const auto& w : p.warnings) spdlog::warn("warning: {}", w);
    return p;
}

/// The error for a plugin name that is not loaded: the file that would have provided it and
/// why it did not load, or suggestions.
std::string default_output(const std::string& config) { return fs::path(config).stem().string() + ".png"; }

// Where a render writes, and what the user said about it.
struct Output {
    std::string path;
    bool named = false;         // -o on the command line: the user asked for this file
    const Mark* mark = nullptr; // output.path of the config, for messages
};

// A draft's name beside the full render's: fig4a.png -> fig4a-draft.png.
std::string draft_name(const std::string& path) {
    const fs::path p(path);
    return (p.parent_path() / (p.stem().string() + "-draft" + p.extension().string())).string();
}

Output resolve_output(const Options& o, const Pipeline& p) {
    if (!o.out.empty()) return {o.out, true, nullptr};
    if (!p.output_path.empty())
        return {o.draft ? draft_name(p.output_path) : p.output_path, false, &p.output_mark};
    const std::string d = default_output(o.config);
    return {o.draft ? draft_name(d) : d, false, nullptr};
}

// --draft: `sets` and the assignments that make the draft of the pipeline they give
// (host/draft.hpp); unchanged without --draft.
std::vector<std::string> with_draft(const Options& o, std::vector<std::string> sets, const Pipeline& full) {
    if (o.draft)
        for (auto& s : draft_overrides(full, draft_factor)) sets.push_back(std::move(s));
    return sets;
}

// check_output, plus the promises about existing files: the config itself is never written
// over; another existing file only when named with -o or with --force. Errors about a path
// from the config point at output.path.
void check_output_for(const Output& out, const Options& o) {
    try {
        std::error_code ec;
        if (fs::equivalent(out.path, o.config, ec))
            throw InputError("cannot write " + quote(out.path, 200) + ": it is the config being rendered");
        check_output(out.path);
        if (!out.named && !o.force && fs::exists(fs::symlink_status(out.path, ec)))
            throw InputError(quote(out.path, 200) + " exists: name it with -o to replace it, or add --force");
    } catch (const InputError& e) {
        if (out.mark) throw InputError(out.mark->str() + ": output.path: " + e.what());
        throw;
    }
}

// A render that drew almost nothing is written with a warning (check_drawn refuses one that
// drew nothing).
void warn_drawn(const Pipeline& p, const RenderStats& st) {
    if (const std::string w = check_drawn(p, st); !w.empty()) spdlog::warn("warning: {}", w);
}

// Run `body(runtime)` (a render of p) with a progress bar and time it; the render is checked
// (not empty, not interrupted). Errors a plugin raises during the render get the renderer's
// position; a failed write of the output (WriteError, from a streamed image) keeps its own.
//
// `distributed`: split over the MPI ranks (mpirun); rank 0 then holds the whole render's stats
// and shows the progress bar (its own share's progress).
// What `--checkpoint` and `--resume` ask of a render (plan_checkpoints).
struct Checkpoints {
    std::string path; ///< where checkpoints are written ("": none)
    double every_s = 300;
    CheckpointHeader header;
    std::unique_ptr<CheckpointFile> resume;
    unsigned written = 0; ///< checkpoints the render wrote
};

template <class Body>
void run_checked(const Pipeline& p, unsigned threads, bool quiet, RenderStats& stats, double& secs,
                 bool distributed, std::uint64_t budget, Body&& body, Checkpoints* ck = nullptr) {
    Runtime rt(threads, &g_interrupted, distributed);
    rt.set_memory_budget(budget);
    if (ck && !ck->path.empty()) rt.set_checkpoints(ck->path, ck->every_s, ck->header, std::move(ck->resume));
    const auto t0 = std::chrono::steady_clock::now();
    {
        const std::uint64_t units = p.renderer->work_units();
        ProgressBar bar(
            rt.ranks() > 1 ? (units + rt.ranks() - 1) / rt.ranks() : units, [&rt] { return rt.done(); },
            !quiet && ::isatty(2) && rt.rank() == 0);
        try {
            body(rt);
            if (ck) ck->written = rt.checkpoints_written();
        } catch (const WriteError&) {
            throw; // the output's, not the renderer's
        } catch (const InputError& e) {
            // Refused during the render (a plugin that can only tell at run time): point at
            // the renderer, the one place we know.
            throw InputError(p.renderer_mark.str() + ": renderer: " + e.what());
        }
    }
    secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (g_interrupted.load()) throw Cancelled();
    if (rt.rank() == 0) warn_drawn(p, stats);
}

// Render one pipeline's image (checked, not written); under mpirun with `distributed`, rank 0
// holds the image.
Image render_checked(const Pipeline& p, unsigned threads, bool quiet, RenderStats& stats, double& secs,
                     bool distributed = false, std::uint64_t budget = UINT64_MAX, Checkpoints* ck = nullptr) {
    Image img;
    run_checked(
        p, threads, quiet, stats, secs, distributed, budget,
        [&](Runtime& rt) { img = p.renderer->render(rt, stats); }, ck);
    return img;
}

// --checkpoint, --checkpoint-every, --resume: checked before the render (the checkpoint to
// resume read whole and compared with the recipe); an empty plan without them.
Checkpoints plan_checkpoints(const Options& o, const Pipeline& p, const std::string& out, bool vector,
                             bool stream) {
    Checkpoints ck;
    if (o.checkpoint.empty() && o.resume.empty()) {
        if (!o.checkpoint_every.empty())
            throw InputError("--checkpoint-every: checkpoints go to a file: add --checkpoint FILE");
        return ck;
    }
    const std::string opt = o.resume.empty() ? "--checkpoint" : "--resume";
    if (ranks::size() > 1)
        throw InputError(opt + ": checkpoints are kept of a render on one process, not under mpirun");
    if (!p.renderer->keeps_checkpoints() || vector)
        throw InputError(p.renderer_mark.str() + ": renderer: " + p.renderer_type +
                         (vector ? " draws this picture without points" : " keeps no checkpoints") + " (" +
                         opt + "; chaos-game and orbit-trap renders keep them)");
    if (stream)
        throw InputError(opt + ": this render is beyond the memory budget and streams in strips; checkpoints "
                               "are kept of a render that fits (see --memory)");
    ck.every_s = o.checkpoint_every.empty() ? 300 : parse_duration(o.checkpoint_every, "--checkpoint-every");
    // With --resume alone, the checkpoints go on in the file resumed.
    ck.path = o.checkpoint.empty() ? o.resume : o.checkpoint;
    ck.header = CheckpointHeader{FIXPOINT_VERSION, p.renderer_type, p.identity, p.points};
    std::error_code ec;
    // (Spelled differently, or not there yet: compared as absolute paths with . and .. resolved.)
    const auto same = [&ec](const std::string& a, const std::string& b) {
        if (fs::equivalent(a, b, ec)) return true;
        const fs::path ca = fs::weakly_canonical(fs::absolute(a), ec);
        if (ec || ca.empty()) return a == b; // (undecidable: only the same spelling)
        return ca == fs::weakly_canonical(fs::absolute(b), ec) && !ec;
    };
    for (const auto& [name, other] : {std::pair{"the output", out}, std::pair{"the config", o.config}})
        if (same(ck.path, other))
            throw InputError(opt + ": " + quote(ck.path, 200) + " is " + name +
                             ": a checkpoint needs a file of its own");
    if (!o.resume.empty()) {
        ck.resume = std::make_unique<CheckpointFile>(o.resume);
        ck.resume->check_against(ck.header);
    } else if (!o.force && fs::exists(fs::symlink_status(ck.path, ec))) {
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
    return ck;
}

/// The rows of a rank other than 0 in a streamed render: rank 0 writes the image.
class DiscardedRows final : public RowSink {
public:
    void rows(int, int, const float*) override {}
};

// A render streamed by bands of rows into `sink` (Renderer::render_rows: the whole image does
// not fit the budget), split over the MPI ranks.
void render_streamed(const Pipeline& p, unsigned threads, bool quiet, RenderStats& stats, double& secs,
                     std::uint64_t budget, RowSink& sink) {
    run_checked(p, threads, quiet, stats, secs, true, budget,
                [&](Runtime& rt) { p.renderer->render_rows(rt, stats, sink); });
}

// The vector document of a renderer with vector output (SVG, PDF), checked like an image.
std::string render_vector_checked(const Pipeline& p, unsigned threads, Format f, RenderStats& stats,
                                  double& secs) {
    Runtime rt(threads, &g_interrupted, true);
    std::string doc;
    const auto t0 = std::chrono::steady_clock::now();
    try {
        doc = p.renderer->render_vector(rt, stats, f == Format::Svg ? VectorFormat::Svg : VectorFormat::Pdf,
                                        p.recipe);
    } catch (const InputError& e) {
        throw InputError(p.renderer_mark.str() + ": renderer: " + e.what());
    }
    secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (g_interrupted.load()) throw Cancelled();
    if (rt.rank() == 0) warn_drawn(p, stats);
    return doc;
}

// Paper 05's Algorithm 1: the addresses of a renderer's polygons at a level, one per line.
int cmd_addresses(const Options& o) {
    for (const auto& w : o.where) parse_where(w); // bad conditions before the work
    const Registry reg = make_registry(o);
    const Pipeline p = told(load_pipeline(reg, o.config, o.sets, "", o.allow_python));
    std::vector<std::string> lines;
    try {
        lines = p.renderer->polygon_addresses(o.level);
    } catch (const InputError& e) {
        throw InputError(p.renderer_mark.str() + ": renderer: " + e.what());
    } catch (const Error& e) {
        throw InputError(p.renderer_mark.str() + ": renderer: " + e.what());
    }
    // --where: only the polygons that pass every condition (checked before anything is listed).
    std::vector<PolygonTest> tests;
    for (const auto& w : o.where) tests.push_back(parse_where(w));
    for (const auto& l : lines) {
        const auto vs = address_line_vertices(l);
        if (std::all_of(tests.begin(), tests.end(), [&](const PolygonTest& t) { return t(vs); }))
            std::printf("%s\n", l.c_str());
    }
    return 0;
}

// --vary PATH=V1,V2,... or PATH=A..B (integers): the values, split at top-level commas.
std::pair<std::string, std::vector<std::string>> parse_vary(const std::string& spec) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0)
        throw InputError(excerpt("--vary " + spec, 80) + ": expected path.to.param=V1,V2,... or A..B");
    const std::string path = spec.substr(0, eq), rest = spec.substr(eq + 1);
    std::vector<std::string> values;
    const std::string shown = excerpt("--vary " + spec, 80);
    const auto dots = rest.find("..");
    long long a = 0, b = 0;
    // A..B with whole numbers A and B (from_chars: no overflow, no trailing text).
    const auto whole = [](std::string_view t, long long& v) {
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        return !t.empty() && ec == std::errc() && end == t.data() + t.size();
    };
    const bool is_range =
        dots != std::string::npos && rest.find_first_not_of("0123456789-+.") == std::string::npos;
    if (is_range) {
        if (!whole(std::string_view(rest).substr(0, dots), a) ||
            !whole(std::string_view(rest).substr(dots + 2), b))
            throw InputError(shown + ": a range A..B takes whole numbers from " +
                             std::to_string(std::numeric_limits<long long>::min()) + " to " +
                             std::to_string(std::numeric_limits<long long>::max()));
        // b - a could overflow: compare in unsigned arithmetic after ordering.
        if (b < a || static_cast<unsigned long long>(b) - static_cast<unsigned long long>(a) >= 1000)
            throw InputError(shown + ": a range A..B with A <= B, at most 1000 values");
        for (long long v = a;; ++v) {
            values.push_back(std::to_string(v));
            if (v == b) break;
        }
    } else {
        int depth = 0;
        std::string cur;
        for (char c : rest) {
            depth += (c == '[' || c == '{') - (c == ']' || c == '}');
            if (c == ',' && depth == 0)
                values.push_back(cur), cur.clear();
            else
                cur += c;
        }
        values.push_back(cur);
        for (auto& v : values)
            if (v.find_first_not_of(' ') == std::string::npos) throw InputError(shown + ": an empty value");
    }
    if (values.size() > 1000) throw InputError(shown + ": at most 1000 values");
    return {path, values};
}

// A collection holds every child's image and then the contact sheet in memory at once, on top
// of one render at a time: checked as a whole before the first render starts.
void check_collection_memory(const std::vector<Pipeline>& pipes, unsigned threads, int columns) {
    std::uint64_t render = 0, held = 0;
    std::vector<std::pair<int, int>> sizes;
    for (const auto& p : pipes) {
        const int w = p.renderer->width(), h = p.renderer->height();
        render = std::max(render, p.renderer->memory_bytes(threads));
        held += std::uint64_t(w) * std::uint64_t(h) * 4 * sizeof(float); // an Image, RGBA at most
        sizes.emplace_back(w, h);
    }
    const SheetLayout L = contact_sheet_layout(sizes, columns);
    // The sheet is drawn in an OpenImageIO buffer and copied out: twice its RGB floats.
    const std::uint64_t sheet = 2 * std::uint64_t(L.width) * std::uint64_t(L.height) * 3 * sizeof(float);
    const std::uint64_t need = render + held + sheet, have = available_memory();
    if (need > have)
        throw InputError(pipes[0].renderer_mark.str() + ": renderer: a collection of " +
                         std::to_string(pipes.size()) + " children and their " + std::to_string(L.width) +
                         "x" + std::to_string(L.height) + " contact sheet needs " + format_bytes(need) +
                         " of memory with " + std::to_string(threads) + " thread(s); this machine has " +
                         format_bytes(have) + " available");
}

std::string child_path(const std::string& sheet, std::size_t k) {
    const fs::path p(sheet);
    return (p.parent_path() / (p.stem().string() + "-" + std::to_string(k) + p.extension().string()))
        .string();
}

// A collection: one render per value of --vary, each written to its own file, and a contact
// sheet of them all with a caption per child. Every variant is validated before the first
// render starts.
int cmd_collection(const Options& o, bool validate_only) {
    const Registry reg = make_registry(o);
    const auto [path, values] = parse_vary(o.vary);
    std::vector<Pipeline> pipes;
    for (const auto& v : values) {
        pipes.push_back(load_pipeline(reg, o.config, o.sets, path + "=" + v, o.allow_python));
        if (o.draft)
            pipes.back() = load_pipeline(reg, o.config, with_draft(o, o.sets, pipes.back()), path + "=" + v,
                                         o.allow_python);
    }
    told(pipes[0]); // (every child has the same plugins: told once)
    const unsigned threads = o.threads ? o.threads : hardware_threads();
    for (const auto& p : pipes) check_memory(p, threads);
    check_collection_memory(pipes, threads, o.columns);
    const Output output = resolve_output(o, pipes[0]);
    const std::string& out = output.path;
    check_output_for(output, o);
    if (is_vector(format_for(out)))
        throw InputError("--vary: '" + out +
                         "': a collection is written as PNG, EXR or TIFF images and a contact "
                         "sheet, not as SVG or PDF");
    // The children's names come from the sheet's: named with -o, the sheet names them too.
    for (std::size_t k = 0; k < pipes.size(); ++k) {
        check_output_for({child_path(out, k + 1), output.named, output.mark}, o);
        check_tiled(pipes[k], child_path(out, k + 1));
    }
    if (g_interrupted.load()) throw Cancelled(); // during the checks above
    std::string recipes;
    for (const auto& p : pipes) recipes += p.recipe;
    agree_checks(recipes);
    if (validate_only) {
        if (!o.quiet)
            spdlog::info("{}: valid: a collection of {} children to {}", o.config, pipes.size(), out);
        return 0;
    }

    // Every child is rendered and checked before anything is written: a failing child
    // leaves no files behind. Under mpirun, child k is rendered whole by rank k mod N (a
    // child's bytes do not depend on where it ran) and sent to rank 0, which writes.
    const unsigned me = ranks::rank(), nr = ranks::size();
    std::vector<Image> children(pipes.size());
    std::vector<RenderStats> stats(pipes.size());
    std::vector<double> secs(pipes.size(), 0.0);
    for (std::size_t k = me; k < pipes.size(); k += nr)
        children[k] = render_checked(pipes[k], threads, o.quiet || me != 0, stats[k], secs[k]);
    if (nr > 1) {
        // Rank 0 receives the others' children in order: a header, then the pixels.
        for (std::size_t k = 0; k < pipes.size(); ++k) {
            const unsigned owner = unsigned(k % nr);
            if (owner == 0 || (me != 0 && me != owner)) continue;
            double head[5];
            if (me == owner) {
                const Image& c = children[k];
                head[0] = c.width, head[1] = c.height, head[2] = c.channels;
                head[3] = double(stats[k].samples), head[4] = secs[k];
                ranks::send(0, head, sizeof head);
                ranks::send(0, c.pixels.data(), c.pixels.size() * sizeof(float));
                children[k] = Image{}; // sent: its memory is free again
            } else {
                ranks::recv(owner, head, sizeof head);
                Image& c = children[k];
                c.width = int(head[0]), c.height = int(head[1]), c.channels = int(head[2]);
                stats[k].samples = std::uint64_t(head[3]), secs[k] = head[4];
                stats[k].unit = stats[0].unit; // (one renderer for every child; rank 0 ran child 0)
                c.pixels.resize(std::size_t(c.width) * std::size_t(c.height) * std::size_t(c.channels));
                ranks::recv(owner, c.pixels.data(), c.pixels.size() * sizeof(float));
            }
        }
        if (me != 0) return 0;
        ranks::set_phase(ranks::Phase::free); // the others are done: rank 0's errors are its own
    }
    std::vector<std::string> captions;
    double total = 0;
    for (std::size_t k = 0; k < pipes.size(); ++k) {
        total += secs[k];
        if (!o.quiet)
            spdlog::info("{}={}: {} {} in {:.2f} s{}", path, values[k], stats[k].samples, stats[k].unit,
                         secs[k],
                         nr > 1 ? " on rank " + std::to_string(k % nr)
                                : ", " + std::to_string(stats[k].restarts) + " restarted chains");
        captions.push_back(path.substr(path.rfind('.') + 1) + " = " + values[k]);
    }
    // All the files or none: a Ctrl-C or a full disk half way removes those written.
    FileSet files(&g_interrupted);
    for (std::size_t k = 0; k < pipes.size(); ++k)
        files.image(children[k], child_path(out, k + 1), pipes[k].bit_depth, pipes[k].recipe, pipes[k].tiled);
    bool text = true;
    const Image sheet = contact_sheet(children, captions, o.columns, &text);
    if (!text) spdlog::warn("warning: no font found for the captions (install fonts-dejavu-core)");
    files.image(sheet, out, pipes[0].bit_depth,
                "# contact sheet: --vary " + o.vary + "; children " + child_path(out, 1) + " ... " +
                    child_path(out, pipes.size()) + "\n# the recipe of the first child:\n" + pipes[0].recipe);
    files.commit();
    if (!o.quiet)
        spdlog::info("{}: contact sheet of {} children ({} ... {}) in {:.2f} s{}", out, pipes.size(),
                     child_path(out, 1), child_path(out, pipes.size()), total,
                     nr > 1 ? " of render time over " + std::to_string(nr) + " ranks" : "");
    return 0;
}

int cmd_render(const Options& o, bool validate_only) {
    // Caught from the start, so that a Ctrl-C while plugins load and the config is checked is
    // not lost: a background job of a script starts with SIGINT ignored, and the handler
    // replaces that. The flag is checked once the checks are done and polled by the render.
    install_sigint();
    // Under mpirun: the checks below run on every rank and are agreed before the render.
    // (validate runs on rank 0 alone.)
    if (ranks::size() > 1 && !validate_only) ranks::set_phase(ranks::Phase::checking);
    if (!o.vary.empty() && o.print.any())
        throw InputError("--tile, --repeat, --dpi and --print-size make one image: not with --vary");
    if (!o.vary.empty() && !o.memory.empty())
        throw InputError(
            "--memory bounds one render (in strips): not with --vary, whose children render whole");
    if (!o.vary.empty() && (!o.checkpoint.empty() || !o.resume.empty()))
        throw InputError("--checkpoint and --resume keep one render: not with --vary");
    if (!o.vary.empty()) return cmd_collection(o, validate_only);
    if (o.draft && (o.print.dpi > 0 || !o.print.print_size.empty()))
        throw InputError("--draft: a quick small image: not with --dpi or --print-size");
    const Registry reg = make_registry(o);
    Pipeline p = load_for_print(reg, o.config, o.sets, o.print, o.allow_python);
    if (o.draft) p = load_for_print(reg, o.config, with_draft(o, o.sets, p), o.print, o.allow_python);
    told(p);
    const unsigned threads = o.threads ? o.threads : hardware_threads();
    const std::uint64_t requested = o.memory.empty() ? 0 : parse_size(o.memory, "--memory");
    if (const Repeat r = parse_repeat(o.print); r.across * r.down > 1) {
        // The repeated image is made after the render, beside the tile: check both now.
        const std::uint64_t repeated = std::uint64_t(p.renderer->width()) * std::uint64_t(r.across) *
                                       std::uint64_t(p.renderer->height()) * std::uint64_t(r.down) * 3 *
                                       sizeof(float);
        const std::uint64_t need = p.renderer->memory_bytes(threads) + repeated, have = available_memory();
        if (need > have)
            throw InputError("--repeat " + o.print.repeat + ": the tile and its repeated image need " +
                             format_bytes(need) + " of memory; this machine has " + format_bytes(have) +
                             " available");
    }
    const Output output = resolve_output(o, p);
    const std::string& out = output.path;
    check_output_for(output, o);
    const bool vector = check_vector_output(p, out);
    if (!vector) check_tiled(p, out);
    const std::uint64_t held =
        vector ? 0 : StreamedImage::held_bytes(out, p.renderer->width(), p.renderer->height(), p.tiled);
    // Beyond the budget, a raster image streams band by band (not when --repeat needs it whole).
    const MemoryPlan memory =
        check_memory_within(p, threads, requested,
                            !vector && parse_repeat(o.print).across * parse_repeat(o.print).down == 1, held);
    Checkpoints checkpoints = plan_checkpoints(o, p, out, vector, memory.stream);
    if (g_interrupted.load()) throw Cancelled(); // during the checks above
    agree_checks(p.recipe);
    if (validate_only) {
        // The animation's frames are checked before "valid" is said of anything.
        const std::string animation = validate_animation(reg, o.config, o.sets, &g_interrupted);
        if (!o.quiet) {
            spdlog::info("{}: valid: a {}x{} render to {}", o.config, p.renderer->width(),
                         p.renderer->height(), out);
            if (!animation.empty()) spdlog::info("{}: valid: {}", o.config, animation);
        }
        return 0;
    }

    RenderStats stats;
    double secs = 0;
    if (vector) {
        const std::string doc = render_vector_checked(p, threads, format_for(out), stats, secs);
        if (ranks::rank() != 0) return 0; // rank 0 writes
        ranks::set_phase(ranks::Phase::free);
        FileSet file(&g_interrupted); // (a Ctrl-C while it is written: no document)
        file.bytes(doc, out);
        file.commit();
    } else if (memory.stream) {
        // Rank 0 encodes the rows as they come, into a file that takes the output's name only
        // once it is whole; the other ranks' rows go nowhere.
        std::unique_ptr<RowSink> sink;
        if (ranks::rank() == 0) {
            auto image = std::make_unique<StreamedImage>(
                out, p.renderer->width(), p.renderer->height(), p.bit_depth, p.recipe,
                print_resolution(o.print, p.renderer->width(), p.renderer->height()), p.tiled);
            const std::string tmp = image->temporary_path();
            if (tmp.size() < sizeof g_partial_output) {
                std::memcpy(g_partial_output, tmp.c_str(), tmp.size() + 1);
                g_has_partial_output.store(true);
            }
            sink = std::move(image);
        } else {
            sink = std::make_unique<DiscardedRows>();
        }
        render_streamed(p, threads, o.quiet, stats, secs, memory.budget, *sink);
        if (ranks::rank() != 0) return 0;
        ranks::set_phase(ranks::Phase::free);
        g_has_partial_output.store(false);
        static_cast<StreamedImage&>(*sink).finish();
    } else {
        const Image img = render_checked(p, threads, o.quiet, stats, secs, true, memory.budget, &checkpoints);
        if (ranks::rank() != 0) return 0; // rank 0 writes
        ranks::set_phase(ranks::Phase::free);
        const Repeat r = parse_repeat(o.print);
        const std::string recipe = r.across * r.down == 1
                                       ? p.recipe
                                       : "# the tile repeated " + o.print.repeat +
                                             " (--repeat); the recipe renders one tile\n" + p.recipe;
        FileSet file(&g_interrupted); // (a Ctrl-C while it is encoded and written: no image)
        file.image(repeat_image(img, r), out, p.bit_depth, recipe, p.tiled,
                   print_resolution(o.print, img.width, img.height));
        file.commit();
    }
    if (!o.quiet)
        spdlog::info("{}: {} {} in {:.2f} s ({:.3g} {}/s, {}{} thread{}, {}), {} restarted chain{}, {} bad "
                     "value{}{}{}",
                     out, stats.samples, stats.unit, secs, double(stats.samples) / std::max(secs, 1e-9),
                     stats.unit, ranks::size() > 1 ? std::to_string(ranks::size()) + " ranks x " : "",
                     threads, threads == 1 ? "" : "s", fp::simd::active_target(), stats.restarts,
                     stats.restarts == 1 ? "" : "s", stats.bad_values, stats.bad_values == 1 ? "" : "s",
                     stats.how.empty() ? "" : ", " + stats.how,
                     checkpoints.path.empty()
                         ? ""
                         : "; " + std::to_string(checkpoints.written) + " checkpoint" +
                               (checkpoints.written == 1 ? "" : "s") + " to " + checkpoints.path);
    return 0;
}

// validate: the config as render takes it, and every frame of its animation: section if any.
// validate: render's checks, and an animation's frames (cmd_render's validate_only).
int cmd_validate(const Options& o) { return cmd_render(o, true); }

// animate: framework/src/animate.cpp; each frame rendered as render renders one.
int cmd_animate(const Options& o, AnimateOptions ao) {
    install_sigint();
    const Registry reg = make_registry(o);
    ao.config = o.config, ao.sets = o.sets, ao.quiet = o.quiet, ao.force = o.force;
    ao.threads = o.threads ? o.threads : hardware_threads();
    ao.info = [](const std::string& s) { spdlog::info("{}", s); };
    ao.warn = [](const std::string& s) { spdlog::warn("{}", s); };
    try {
        return animate(
            reg, ao,
            [&](const Pipeline& p, RenderStats& stats, double& secs) {
                return render_checked(p, ao.threads, o.quiet, stats, secs);
            },
            &g_interrupted);
    } catch (const Cancelled&) {
        std::fprintf(stderr, "fixpoint: interrupted; the frames written are kept: run again to continue\n");
        return 130;
    }
}

constexpr long long max_eval_steps = 1'000'000'000'000;

// watch: the lines go to stderr like render's; an error keeps the last good image.
int cmd_watch(const Options& o) {
    install_sigint();
    WatchOptions w;
    w.config = o.config;
    w.out = o.out;
    w.sets = o.sets;
    w.threads = o.threads ? o.threads : hardware_threads();
    w.no_draft = o.no_draft;
    const bool quiet = o.quiet;
    w.info = [quiet](const std::string& l) {
        if (!quiet) spdlog::info("{}", l);
    };
    w.error = [](const std::string& l) { spdlog::error("{}", l); };
    return watch(make_registry(o), w, g_interrupted);
}

std::string range_of(const ParamSpec& s) {
    return std::isfinite(s.lo) || std::isfinite(s.hi) ? declared_range(s) : "";
}

void print_params(const ParamSpec* ps, std::size_t n, const std::string& indent) {
    for (std::size_t i = 0; i < n; ++i) {
        const ParamSpec& s = ps[i];
        std::string type(param_type_name(s.type));
        if (s.type == ParamType::Object || s.type == ParamType::Objects)
            type += " (" + std::string(kind_name(s.kind)) + ")";
        if (s.choices) type += " {" + std::string(s.choices) + "}";
        if (s.count) type += " x" + std::to_string(s.count);
        std::string def = s.default_yaml ? std::string("default ") + s.default_yaml
                          : s.optional   ? "optional"
                                         : "required";
        const std::string range = range_of(s);
        std::printf("%s%-16s %s; %s%s%s\n", indent.c_str(), s.name, type.c_str(), def.c_str(),
                    range.empty() ? "" : "; range ", range.c_str());
        std::printf("%s%-16s %s\n", indent.c_str(), "", s.doc ? s.doc : "");
        if (s.type == ParamType::Objects && s.n_item_params) {
            std::printf("%s%-16s each item also takes:\n", indent.c_str(), "");
            print_params(s.item_params, s.n_item_params, indent + "    ");
        }
    }
}

int cmd_plugins(const Options& o) {
    const Registry reg = make_registry(o);
    std::optional<Kind> kind;
    if (!o.kind.empty()) {
        std::vector<std::string> names;
        for (int k = 0; k < kind_count; ++k) {
            names.emplace_back(kind_name(Kind(k)));
            if (o.kind == kind_name(Kind(k))) kind = Kind(k);
        }
        if (!kind) {
            const auto near = suggest(o.kind, names);
            throw InputError("--kind: unknown kind " + quote(o.kind) +
                             (near.empty() ? "" : " (did you mean '" + near[0] + "'?)"));
        }
    }
    if (o.check) {
        // Every plugin file of the folders: loaded (with its plugin) or refused (with why).
        std::vector<std::pair<std::string, std::string>> lines;
        for (const auto* e : reg.all(kind))
            lines.emplace_back(e->file.string(), "ok       " + std::string(e->desc->name));
        // (A refused file's kind is not known: listed whatever --kind says.)
        for (const auto& r : reg.refused()) lines.emplace_back(r.file.string(), "refused  " + r.reason);
        std::sort(lines.begin(), lines.end());
        for (const auto& [file, what] : lines) std::printf("%s: %s\n", file.c_str(), what.c_str());
        return reg.refused().empty() ? 0 : 1;
    }
    for (const auto* e : reg.all(kind))
        std::printf("%-17s %-20s %-7s %s\n", std::string(kind_name(e->desc->kind)).c_str(), e->desc->name,
                    e->desc->version, e->desc->summary);
    return 0;
}

int cmd_describe(const Options& o) {
    if (o.name.empty() && !o.markdown) throw InputError("fixpoint: name is required (see fixpoint --help)");
    const Registry reg = make_registry(o);
    if (o.markdown) { // the reference of docs/plugins.md (describe.cpp)
        std::fputs((o.name.empty() ? markdown_reference(reg) : markdown_plugin(reg.get(o.name), 1)).c_str(),
                   stdout);
        return 0;
    }
    const PluginEntry* e = &reg.get(o.name);
    const auto& d = *e->desc;
    std::printf("%s (%s, version %s)\n  %s\n  file: %s\n", d.name, std::string(kind_name(d.kind)).c_str(),
                d.version, d.summary, e->file.c_str());
    if (d.runs_code)
        std::printf("  runs the code its parameters carry: refused in a recipe read from an image unless "
                    "--allow-python, and by serve unless started with it\n");
    if (d.n_params) {
        std::printf("parameters:\n");
        print_params(d.params, d.n_params, "  ");
    } else {
        std::printf("no parameters\n");
    }
    return 0;
}

int cmd_eval(const Options& o) {
    const Registry reg = make_registry(o);
    auto t = std::dynamic_pointer_cast<const Transform>(
        build_from_text(reg, Kind::Transform, o.transform, "<transform>", "transform"));
    auto s = std::dynamic_pointer_cast<const IterationScheme>(
        build_from_text(reg, Kind::IterationScheme, o.scheme, "<scheme>", "scheme"));
    // Parsed here rather than by CLI11, which clamped an out-of-range count to the largest one.
    long long steps = 0;
    const auto [end, ec] = std::from_chars(o.steps.data(), o.steps.data() + o.steps.size(), steps);
    if (ec != std::errc() || end != o.steps.data() + o.steps.size() || steps < 0 || steps > max_eval_steps)
        throw InputError("--steps: expected a whole number from 0 to " + std::to_string(max_eval_steps) +
                         ", got " + quote(o.steps));
    std::vector<double> xs, ys;
    std::string line;
    for (long lineno = 1; std::getline(std::cin, line); ++lineno) {
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        CNode a, b;
        std::istringstream in(line);
        std::string sx, sy, extra;
        in >> sx >> sy;
        const bool bad = !in || (in >> extra, !extra.empty());
        double x = 0, y = 0;
        char* end1 = nullptr;
        char* end2 = nullptr;
        if (!bad) {
            x = std::strtod(sx.c_str(), &end1);
            y = std::strtod(sy.c_str(), &end2);
        }
        if (bad || *end1 || *end2 || !std::isfinite(x) || !std::isfinite(y))
            throw InputError("<stdin>:" + std::to_string(lineno) +
                             ": expected two finite numbers 'x y', got " + quote(line));
        xs.push_back(x);
        ys.push_back(y);
    }
    Points<double> pts{xs.data(), ys.data(), xs.size()};
    // No points, nothing to step (a huge --steps once spun here for ever on empty input).
    if (!xs.empty())
        for (long long n = 0; n < steps; ++n) s->step(*t, pts, nullptr, std::uint64_t(n));
    for (std::size_t i = 0; i < xs.size(); ++i) std::printf("%.17g %.17g\n", xs[i], ys[i]);
    return 0;
}

// Paper 05's converse construction: affine maps to subdivision maps on a triangle, printed as
// the YAML items an mfs config's IFS takes.
int cmd_to_subdivision(const Options& o) {
    const CNode pts = parse_yaml(o.points, "--points");
    std::array<Vec2, 3> p;
    bool ok = pts.is_seq() && pts.items.size() == 3;
    for (std::size_t j = 0; ok && j < 3; ++j) {
        const CNode& q = pts.items[j];
        ok = q.is_seq() && q.items.size() == 2 && q.items[0].is_scalar() && q.items[1].is_scalar();
        char* e0 = nullptr;
        char* e1 = nullptr;
        if (ok) {
            p[j] = {std::strtod(q.items[0].scalar.c_str(), &e0), std::strtod(q.items[1].scalar.c_str(), &e1)};
            ok = !*e0 && !*e1 && !q.items[0].scalar.empty() && !q.items[1].scalar.empty() &&
                 std::isfinite(p[j].x) && std::isfinite(p[j].y);
        }
    }
    if (!ok) throw InputError("--points: expected three points [[x1, y1], [x2, y2], [x3, y3]] (a triangle)");
    const Registry reg = make_registry(o);
    const auto mats = subdivision_matrices(reg, p, o.maps);
    std::string pts_text = "[";
    for (std::size_t j = 0; j < 3; ++j)
        pts_text += std::string(j ? ", " : "") + "[" + number_text(p[j].x) + ", " + number_text(p[j].y) + "]";
    pts_text += "]";
    for (const auto& s : mats) {
        std::string m;
        for (std::size_t k = 0; k < 9; ++k) m += std::string(k ? ", " : "") + number_text(s[k]);
        std::printf("- {type: subdivision, points: %s, S: [%s]}\n", pts_text.c_str(), m.c_str());
    }
    return 0;
}

// Which plane-group operations an image keeps (host/symmetry.hpp). The inputs are checked
// before a config is loaded and rendered.
int cmd_symmetry(const Options& o) {
    install_sigint();
    if (!o.group.empty() && !known_group(o.group)) {
        std::vector<std::string> names;
        for (const auto* list : {&wallpaper_groups(), &rosette_groups()})
            for (const auto& g : *list) names.push_back(g.name);
        const auto near = suggest(o.group, names);
        throw InputError(
            "--group: unknown group " + quote(o.group) +
            (near.empty() ? "" : " (did you mean '" + near[0] + "'?)") +
            ": a wallpaper group p1, p2, pm, pg, cm, pmm, cmm, pmg, pgg, p4, p4m, p4g, p3, p3m1, "
            "p31m, p6, p6m or a point group C1, C2, C3, C4, C6, D1, D2, D3, D4, D6");
    }
    std::vector<PlaneOp> extra;
    for (std::size_t k = 0; k < o.ops.size(); ++k)
        extra.push_back(parse_op(o.ops[k], "op" + std::to_string(k + 1)));
    std::optional<Box> area;
    if (!o.area.empty()) area = parse_area(o.area);
    const auto is_config = [](const std::string& path) {
        const std::string ext = fs::path(path).extension().string();
        return ext == ".yaml" || ext == ".yml";
    };
    if (!o.sets.empty() && std::none_of(o.images.begin(), o.images.end(), is_config))
        throw InputError("--set: only with a config (.yaml), not an image");
    SymmetryOptions so;
    so.tolerance = o.tolerance;
    so.threshold = o.threshold;
    so.smooth = o.smooth;

    // An image and its frame: a config rendered in memory (as `render` would, with the same
    // checks; never written), or an image file with its recipe's region (paper 04's area about
    // the centre when it has none).
    std::string note;
    std::unique_ptr<Registry> reg; // loaded once, for the first config
    const auto load = [&](const std::string& path, const std::vector<std::string>& sets, const char* what,
                          const std::optional<Box>& region) {
        std::pair<Image, PixelFrame> out;
        auto& [img, frame] = out;
        if (is_config(path)) {
            if (!reg) reg = std::make_unique<Registry>(make_registry(o));
            const Pipeline p = told(load_pipeline(*reg, path, sets));
            const unsigned threads = o.threads ? o.threads : hardware_threads();
            check_memory(p, threads);
            if (!region) frame = frame_from_recipe(p.recipe, p.renderer->width(), p.renderer->height(), path);
            RenderStats stats;
            double secs = 0;
            img = render_checked(p, threads, o.quiet, stats, secs);
        } else {
            img = read_image(path);
            std::string recipe;
            try {
                if (!region) recipe = read_recipe(path);
            } catch (const InputError&) {
                // No recipe: paper 04's area about the image's centre.
            }
            if (region) {
                frame.width = img.width, frame.height = img.height;
                frame.region = *region;
                frame.endpoints = true;
            } else if (recipe.empty()) {
                frame = default_frame(img.width, img.height);
                note += std::string(what) + " " + quote(path, 200) +
                        " has no recipe: its region is taken as [-2 pi, 2 pi] across its width, about its "
                        "centre\n";
            } else {
                frame = frame_from_recipe(recipe, img.width, img.height, path);
            }
        }
        if (img.width < 2 || img.height < 2)
            throw InputError(path + ": an image of " + std::to_string(img.width) + "x" +
                             std::to_string(img.height) + " pixels has no symmetry to measure");
        return out;
    };
    // Every file there before any work starts.
    std::vector<std::string> files = o.images;
    if (!o.against.empty()) files.push_back(o.against);
    for (const auto& f : files) {
        std::error_code ec;
        if (!fs::is_regular_file(f, ec))
            throw InputError("cannot read " + quote(f, 200) + ": " +
                             (fs::exists(f, ec) ? "not a file" : "no such file"));
    }
    // Every config checked, its memory too, before the first render: a bad second config must
    // not stop the run with the first one's report already printed.
    for (const auto& f : files) {
        if (!is_config(f)) continue;
        if (!reg) reg = std::make_unique<Registry>(make_registry(o));
        const bool is_against = !o.against.empty() && &f == &files.back();
        check_memory(load_pipeline(*reg, f, is_against ? std::vector<std::string>{} : o.sets),
                     o.threads ? o.threads : hardware_threads());
    }
    std::optional<std::pair<Image, PixelFrame>> against;
    if (!o.against.empty()) against = load(o.against, {}, "--against", std::nullopt);
    bool all_kept = true;
    if (o.json && o.images.size() > 1) std::fputs("[\n", stdout);
    for (std::size_t k = 0; k < o.images.size(); ++k) {
        const std::string& path = o.images[k];
        note.clear();
        auto [img, frame] =
            load(path, is_config(path) ? o.sets : std::vector<std::string>{}, "the image", area);
        if (area)
            frame.width = img.width, frame.height = img.height, frame.region = *area, frame.endpoints = true;
        const SymmetryReport r =
            measure_symmetry(img, frame, so, o.group, extra, against ? &against->first : nullptr,
                             against ? &against->second : nullptr);
        if (o.json) {
            std::string j = symmetry_json(r, frame, so, o.group, path);
            if (o.images.size() > 1 && k + 1 < o.images.size()) j.insert(j.size() - 1, ",");
            std::fputs(j.c_str(), stdout);
        } else {
            if (o.images.size() > 1) std::printf("%s== %s\n", k ? "\n" : "", path.c_str());
            std::fputs(note.c_str(), stdout);
            std::fputs(symmetry_text(r, frame, so, o.group).c_str(), stdout);
        }
        std::fflush(stdout);
        all_kept = all_kept && (o.group.empty() || group_kept(r, o.group));
    }
    if (o.json && o.images.size() > 1) std::fputs("]\n", stdout);
    return all_kept ? 0 : 1;
}

int cmd_recipe(const Options& o) {
    std::fputs(read_recipe(o.image).c_str(), stdout);
    return 0;
}

int cmd_conformance(const Options& o) {
    Registry reg = make_registry(o);
    std::vector<const PluginEntry*> targets;
    // A plugin file (a path, or a name ending in .so), or the name of a plugin found in the
    // plugin folders (an unknown one gets the "did you mean" of describe).
    for (const auto& f : o.files)
        targets.push_back(f.find('/') == std::string::npos && !f.ends_with(".so") ? &reg.get(f)
                                                                                  : &reg.load_file(f));
    if (o.files.empty()) targets = reg.all();
    if (!o.example.empty()) {
        // Bad input, refused as such (exit 2) before any check runs, not reported as a failed check.
        if (targets.size() != 1) throw InputError("--example: name the one plugin it is an example of");
        const CNode ex = parse_yaml(o.example, "--example");
        if (!ex.is_map() && ex.type != CNode::Type::Null)
            throw InputError(ex.mark.str() + ": expected a mapping of parameters, got " + ex.describe());
    }
    int failed = 0, passed = 0;
    for (const auto* e : targets) {
        const auto report = conformance_report(reg, *e, o.example.empty() ? nullptr : &o.example);
        const auto& findings = report.findings;
        if (findings.empty()) {
            ++passed;
            std::printf("PASS %s (%s)\n", e->desc->name, e->file.c_str());
        } else {
            ++failed;
            std::printf("FAIL %s (%s)\n", e->desc->name, e->file.c_str());
            for (const auto& f : findings) std::printf("  - %s\n", f.c_str());
        }
        if (o.verbose)
            for (const auto& c : report.checks)
                std::printf("    %s %s\n", c.passed ? "PASS" : "FAIL", c.name.c_str());
    }
    std::printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}

} // namespace

int main(int argc, char** argv) {
    // A file-size limit (ulimit -f) must make a write fail with EFBIG, reported and cleaned up
    // like a full disk, not kill the process with its temporary file left behind.
    std::signal(SIGXFSZ, SIG_IGN);
    auto logger = spdlog::stderr_logger_st("fixpoint");
    logger->set_pattern("%v");
    spdlog::set_default_logger(logger);
    // Under mpirun: one process per rank (host/ranks.hpp); rank 0 speaks for the job.
    try {
        ranks::init(&argc, &argv);
    } catch (const InputError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    }
    struct Finalize {
        ~Finalize() { ranks::finalize(); }
    } finalize_at_exit;
    if (ranks::rank() != 0) spdlog::set_level(spdlog::level::off);

    CLI::App app{"fixpoint " FIXPOINT_VERSION
                 " - renders fractal and symmetric patterns from YAML pipelines"};
    app.set_version_flag("--version", FIXPOINT_VERSION);
    app.require_subcommand(1);
    Options o;
    app.add_option("--plugin-dir", o.plugin_dirs, "Also load plugins from this folder (repeatable)");
    std::string simd;
    app.add_option(
           "--simd", simd,
           "Instruction set of the vectorised kernels (default: the best this CPU has; the image "
           "does not depend on it): one of " +
               [] {
                   std::string l;
                   for (const auto& t : fp::simd::supported_targets()) l += (l.empty() ? "" : ", ") + t;
                   return l;
               }())
        ->envname("FIXPOINT_SIMD");

    auto* render = app.add_subcommand("render", "Render a pipeline to an image");
    render
        ->add_option("config", o.config,
                     "Pipeline file (YAML), or an image fixpoint wrote: its recipe is rendered (without "
                     "its output.path)")
        ->required();
    render->add_option("-o,--output", o.out,
                       "Output image (.png, .exr, .tif; .svg or .pdf for renderers with vector output); "
                       "default: the config's output.path or <config>.png");
    render->add_option("--set", o.sets, "Override a value: path.to.param=value (repeatable)");
    render
        ->add_option("--threads", o.threads,
                     "Worker threads (default: all cores); the image does not depend on it")
        ->check(CLI::Range(1u, 4096u));
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
    render->add_flag("-q,--quiet", o.quiet, "No progress bar, no summary");
    render->add_flag("--allow-python", o.allow_python,
                     "Run the Python of a python-scheme in a recipe read from an image (refused by default: "
                     "an image may come from anywhere)");
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

    ExploreOptions ex;
    auto* explore = app.add_subcommand(
        "explore", "Search parameters of a config for good patterns: score quick drafts, keep the best");
    explore->add_option("config", ex.config, "Pipeline file (YAML)")->required();
    explore
        ->add_option("-o,--output", ex.out_dir,
                     "Folder of best-k.yaml, best-k.png, sheet.png, candidates.tsv")
        ->required();
    explore->add_option("--param", ex.params,
                        "A parameter and its range: PATH=A..B, PATH=a+bq..c+dq, 'PATH=a|b|c'");
    explore->add_option("--random", ex.random,
                        "Every ranged parameter of the plugin at this path (repeatable)");
    explore->add_option("--set", ex.sets, "Override a value first: path.to.param=value (repeatable)");
    explore->add_option(
        "--weights", ex.weights,
        "Weights of the measures (default coverage=1,entropy=1,dimension=2,lyapunov=1,symmetry=0)");
    explore->add_option("--seed", ex.seed, "Seed of the search (default 1)");
    explore
        ->add_option("--candidates", ex.candidates,
                     "Candidates of the random phase and of each generation (default 24)")
        ->check(CLI::Range(1, 100000));
    explore->add_option("--keep", ex.keep, "Best candidates kept, rendered and written (default 6)")
        ->check(CLI::Range(1, 1000));
    explore
        ->add_option("--generations", ex.generations,
                     "Evolutionary generations after the random phase (default 0)")
        ->check(CLI::Range(0, 10000));
    explore->add_option("--draft-size", ex.draft_size, "Larger side of a draft in pixels (default 160)")
        ->check(CLI::Range(8, 4096));
    explore->add_option("--draft-points", ex.draft_points, "Most points of a draft (default 100000)")
        ->check(CLI::Range(1LL, 1000000000LL));
    explore->add_option("--columns", ex.columns, "Columns of the contact sheet (default: about square)")
        ->check(CLI::Range(1, 1000));
    explore
        ->add_option("--threads", ex.threads,
                     "Worker threads (default: all cores); the result does not depend on it")
        ->check(CLI::Range(1u, 4096u));
    explore->add_flag("-q,--quiet", o.quiet, "No summary lines");
    explore->add_flag("--force", ex.force, "Replace existing files in the folder");
    explore->add_flag("--allow-python", ex.allow_python,
                      "Run the Python of a python-scheme in a recipe read from an image (refused by default: "
                      "an image may come from anywhere)");
    explore->footer(explore_help);

    auto* validate_cmd =
        app.add_subcommand("validate", "Check everything a render would check; render nothing");
    validate_cmd->add_option("config", o.config, "Pipeline file (YAML)")->required();
    validate_cmd->add_option("-o,--output", o.out, "Output image to check");
    validate_cmd->add_option("--set", o.sets, "Override a value: path.to.param=value (repeatable)");
    validate_cmd->add_option("--threads", o.threads, "Threads to check memory for")
        ->check(CLI::Range(1u, 4096u));
    validate_cmd->add_option("--memory", o.memory, "Memory to check the render against (as render --memory)");
    validate_cmd->add_flag("-q,--quiet", o.quiet, "Print nothing when valid");
    validate_cmd->add_flag("--force", o.force, "Check as render --force would");
    validate_cmd->add_flag("--allow-python", o.allow_python,
                           "Run the Python of a python-scheme in a recipe read from an image (refused by "
                           "default: an image may come from anywhere)");
    validate_cmd->add_option("--vary", o.vary, "Check every child of a collection (as render --vary)");

    AnimateOptions ao;
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
    animate_cmd->add_option("--set", o.sets,
                            "Override a value before the animation's: path.to.param=value (repeatable; "
                            "--set animation.frames=3 too)");
    animate_cmd->add_option("--threads", o.threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1u, 4096u));
    animate_cmd->add_flag("--list", ao.list,
                          "Check every frame and print each frame's values as --set takes them; render "
                          "nothing");
    animate_cmd->add_flag("-q,--quiet", o.quiet, "No progress bar, no log");
    animate_cmd->add_flag("--force", o.force,
                          "Replace frame files made with another recipe, and an existing video");

    auto* watch_cmd = app.add_subcommand(
        "watch", "Render a config again each time it is saved: a draft, then the full image (Ctrl-C stops)");
    watch_cmd->add_option("config", o.config, "Pipeline file (YAML)")->required();
    watch_cmd->add_option("-o,--output", o.out, "The image written (replaced at each save)")->required();
    watch_cmd->add_option("--set", o.sets, "Override a value: path.to.param=value (repeatable)");
    watch_cmd->add_option("--threads", o.threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1u, 4096u));
    watch_cmd->add_flag("--no-draft", o.no_draft, "The full image only, no draft first");
    watch_cmd->add_flag("-q,--quiet", o.quiet, "Print only errors");

    auto* plugins = app.add_subcommand("plugins", "List the plugins found");
    plugins->add_option("--kind", o.kind, "Only this kind (shape, transform, iteration-scheme, ...)");
    plugins->add_flag("--check", o.check,
                      "List every plugin file with its plugin or why it was refused (exit 1 if any was)");

    auto* describe = app.add_subcommand("describe", "Show a plugin's parameters");
    describe->add_option("name", o.name, "Plugin name (with --markdown: every plugin when none)");
    describe->add_flag("--markdown", o.markdown, "Markdown, as docs/plugins.md is");

    auto* eval = app.add_subcommand("eval", "Apply a transform to points read from stdin ('x y' per line)");
    eval->add_option("transform", o.transform,
                     "Transform as a YAML flow mapping, e.g. '{type: inversion, shape: {type: circle}}'")
        ->required();
    eval->add_option("--scheme", o.scheme,
                     "Iteration scheme as a YAML flow mapping (default {type: picard})");
    eval->add_option("--steps", o.steps,
                     "Steps per point (default 1, at most 10^12); step index n counts from 0");

    auto* to_sub = app.add_subcommand(
        "to-subdivision", "Paper 05's converse construction: affine maps as subdivision maps on a triangle");
    to_sub
        ->add_option("maps", o.maps,
                     "Affine maps as YAML flow mappings, e.g. '{type: affine, coefficients: [...]}'")
        ->required();
    to_sub->add_option("--points", o.points, "The control points [[x1, y1], [x2, y2], [x3, y3]]")->required();

    auto* recipe = app.add_subcommand("recipe", "Print the recipe embedded in an image");
    recipe->add_option("image", o.image, "Image written by fixpoint")->required();

    auto* addresses = app.add_subcommand(
        "addresses", "List the addresses of a renderer's polygons at a level (paper 05, Algorithm 1)");
    addresses->add_option("config", o.config, "Pipeline file (YAML)")->required();
    addresses->add_option("--level", o.level, "Level to list (default: the last)")
        ->check(CLI::Range(0LL, 1000LL));
    addresses->add_option("--set", o.sets, "Override a value: path.to.param=value (repeatable)");
    addresses->add_flag("--allow-python", o.allow_python,
                        "Run the Python of a python-scheme in a recipe read from an image (refused by "
                        "default: an image may come from anywhere)");
    addresses->add_option(
        "--where", o.where,
        "Only polygons that pass: 'centre in [x0, x1, y0, y1]', 'inside [...]' or 'meets [...]' "
        "(repeatable: all must pass)");

    auto* symmetry = app.add_subcommand("symmetry", "Measure which plane-group operations an image keeps "
                                                    "(rotations, mirrors, glides, lattice translations) "
                                                    "and the largest wallpaper group they allow");
    symmetry->footer(
        "The operations act about the origin of the plane, on paper 04's lattices (square 2 pi Z^2 for p1 "
        "... p4g, "
        "hexagonal 2 pi (1, 0), 2 pi (1/2, sqrt 3/2) for p3 ... p6m); the image's recipe says which region "
        "of "
        "the plane it shows (renderer.area: pixel 0 at xmin, W - 1 at xmax; renderer.view: pixel cells). An "
        "image without a recipe is taken as [-2 pi, 2 pi] across its width about its centre, or --area.\n"
        "Score: on the picture smoothed by --smooth, the fraction of pixels p, among those whose image g(p) "
        "lies in the picture, whose colour is within --tolerance (each channel, of full scale) of the "
        "picture at g(p) (bilinear, or one of the four "
        "pixels around g(p): edges seldom fall on pixel centres). Kept: score >= --threshold. An operation "
        "that keeps fewer than 100 pixels inside the picture is n/a, and groups that need it are undecided.\n"
        "With the paper's reduction (fmod, on the square lattice) the hexagonal maps keep their 3- and "
        "6-fold rotations for about 97 % of a pattern's pixels (the default threshold allows it); with "
        "reduction: hexagonal the rotations score 0.999.\n"
        "Largest group: the kept group with the most operations per unit area; the point group is the "
        "largest rosette (C1 ... D6) about the origin.\n"
        "Exit: 0; with --group 0 when every image keeps it, 1 when one does not; 2 bad input.\n"
        "Example: fixpoint symmetry configs/orbit-trap/fig5e.yaml --set renderer.width=161 --set "
        "renderer.height=161 (cm: the map's p3m1 broken by the traps)\n");
    symmetry
        ->add_option("images", o.images,
                     "Images (PNG, EXR, TIFF; the recipe gives the region) or configs (.yaml), rendered in "
                     "memory first; several: one report each (a JSON list with --json)")
        ->required();
    symmetry->add_option("--group", o.group,
                         "Check only this group's operations (p1 ... p6m, or a point group C1 ... D6; every "
                         "orientation and lattice of that name); exit 1 when it is not kept");
    symmetry
        ->add_option("--op", o.ops,
                     "Also score the map p -> [a b; c d] p + t of the plane: '[a, b, c, d]' or "
                     "'[a, b, c, d, tx, ty]' (repeatable), e.g. a self-similarity '[2, 0, 0, 2]'")
        ->allow_extra_args(false); // one list per --op: CLI11 would split "[...]" into values
    symmetry->add_option(
        "--area", o.area,
        "The region the image shows, [xmin, xmax, ymin, ymax] (pixel 0 at xmin, pixel W - 1 at "
        "xmax); default: the recipe's");
    symmetry->add_option(
        "--against", o.against,
        "Score each image's pixels against the picture at g(p) in this image or config (its own "
        "region) instead of in IMAGE: e.g. a zoom against a wider render, for self-similarity");
    symmetry
        ->add_option("--tolerance", o.tolerance, "Colour tolerance per channel, of full scale (default 0.1)")
        ->check(CLI::Range(0.0, 1.0));
    symmetry->add_option("--threshold", o.threshold, "Score from which an operation is kept (default 0.85)")
        ->check(CLI::Range(0.0, 1.0));
    symmetry
        ->add_option("--smooth", o.smooth,
                     "Passes of a [1 2 1] / 4 filter over the picture before scoring (default 1; 0: none)")
        ->check(CLI::Range(0, 16));
    symmetry->add_option("--set", o.sets,
                         "With a config: override a value, path.to.param=value (repeatable)");
    symmetry->add_option("--threads", o.threads, "Worker threads to render a config with")
        ->check(CLI::Range(1u, 4096u));
    symmetry->add_flag("--json", o.json, "Print the scores and groups as JSON");
    symmetry->add_flag("-q,--quiet", o.quiet, "No progress bar while a config renders");

    ServeOptions so;
    auto* serve_cmd = app.add_subcommand("serve", "Serve the live preview page: edit a config, see it render "
                                                  "(docs/serve-api.md)");
    serve_cmd->add_option("config", so.config, "Pipeline file (YAML) the page opens, inside --root");
    serve_cmd->add_option("--port", so.port, "Port (default 8420; 0: any free port)")
        ->check(CLI::Range(0, 65535));
    serve_cmd->add_option("--host", so.host,
                          "Address to listen on (default 127.0.0.1); any other needs the token printed in "
                          "the address");
    serve_cmd->add_option("--root", so.root,
                          "The only folder the page reads and writes (default: the current one)");
    serve_cmd->add_option("--threads", so.threads, "Render threads (default: all cores)")
        ->check(CLI::Range(1u, 4096u));
    serve_cmd->add_flag("--allow-python", so.allow_python,
                        "Accept configs with a python-scheme (its Python code runs when the page checks "
                        "the config)");

    auto* conformance = app.add_subcommand("conformance", "Run the plugin conformance suite");
    conformance->add_option("files", o.files, "Plugin files or names (default: every plugin found)");
    conformance->add_flag("-v,--verbose", o.verbose, "List every check run and its result");
    conformance->add_option("--example", o.example,
                            "Parameters to check the plugin with instead of its own example (a YAML mapping, "
                            "as '{file: my_scheme.py}' for a python-scheme)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "fixpoint: %s (see fixpoint --help)\n", e.what());
        return 2;
    }

    if (!simd.empty() && !fp::simd::force_target(simd)) {
        std::string l;
        for (const auto& t : fp::simd::supported_targets()) l += (l.empty() ? "" : ", ") + t;
        std::fprintf(stderr, "fixpoint: --simd: %s is not an instruction set of this CPU (it has: %s)\n",
                     quote(simd).c_str(), l.c_str());
        return 2;
    }

    // Only `render` is split over ranks; any other command runs once, on rank 0.
    if (ranks::rank() != 0 && !*render) return 0;
    try {
        if (*render) return cmd_render(o, false);
        if (*validate_cmd) return cmd_validate(o);
        if (*animate_cmd) return cmd_animate(o, ao);
        if (*watch_cmd) return cmd_watch(o);
        if (*plugins) return cmd_plugins(o);
        if (*describe) return cmd_describe(o);
        if (*eval) return cmd_eval(o);
        if (*recipe) return cmd_recipe(o);
        if (*conformance) return cmd_conformance(o);
        if (*addresses) return cmd_addresses(o);
        if (*to_sub) return cmd_to_subdivision(o);
        if (*symmetry) return cmd_symmetry(o);
        if (*serve_cmd) {
            install_sigint(); // Ctrl-C stops the server: serve() polls the flag
            so.plugin_dirs = o.plugin_dirs;
            so.on_listen = [](const std::string& url) {
                std::printf("fixpoint serve: open %s\n", url.c_str());
                std::fflush(stdout);
            };
            return serve(make_registry(o), so, g_interrupted);
        }
        if (*explore) {
            install_sigint();
            ex.cancel = &g_interrupted;
            if (!o.quiet) ex.info = [](const std::string& l) { spdlog::info("{}", l); };
            return run_explore(make_registry(o), ex);
        }
    } catch (const AgreedFailure& f) {
        if (ranks::rank() == 0) std::fprintf(stderr, "%s\n", f.verdict.message.c_str());
        return f.verdict.code;
    } catch (const Cancelled&) {
        return report(130, "fixpoint: interrupted; no image written");
    } catch (const InputError& e) {
        return report(2, e.what());
    } catch (const InternalError& e) {
        return report(1, std::string("fixpoint: internal error: ") + e.what());
    } catch (const std::bad_alloc&) {
        return report(1, "fixpoint: out of memory");
    } catch (const std::exception& e) {
        return report(1, "fixpoint: internal error: " + excerpt(e.what(), 400));
    } catch (...) {
        // A plugin may throw anything; it must not abort the process without a word.
        return report(1, "fixpoint: internal error: an exception that is not a std::exception (thrown by "
                         "a plugin?)");
    }
    return 1;
}
