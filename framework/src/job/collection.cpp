// A collection (fixpoint/host/job/collection.hpp): its children planned and rendered by the
// render job, written all at once.
#include <fixpoint/host/core/ranks.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/host/job/collection.hpp>
#include <fixpoint/host/job/draft.hpp>
#include <fixpoint/text.hpp>

#include <charconv>
#include <filesystem>
#include <limits>

namespace fs = std::filesystem;

namespace fp::host {

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

std::string child_path(const std::string& sheet, std::size_t k) {
    const fs::path p(sheet);
    return (p.parent_path() / (p.stem().string() + "-" + std::to_string(k) + p.extension().string()))
        .string();
}

namespace {

// A collection holds every child's image and then the contact sheet in memory at once, on top
// of one render at a time: checked as a whole before the first render starts.
void check_collection_memory(const std::vector<RenderPlan>& plans, unsigned threads, int columns) {
    std::uint64_t render = 0, held = 0;
    std::vector<std::pair<int, int>> sizes;
    for (const auto& plan : plans) {
        const Renderer& R = *plan.pipeline.renderer;
        const int w = R.width(), h = R.height();
        render = std::max(render, R.memory_bytes(threads));
        held += std::uint64_t(w) * std::uint64_t(h) * 4 * sizeof(float); // an Image, RGBA at most
        sizes.emplace_back(w, h);
    }
    const SheetLayout L = contact_sheet_layout(sizes, columns);
    // The sheet is drawn in an OpenImageIO buffer and copied out: twice its RGB floats.
    const std::uint64_t sheet = 2 * std::uint64_t(L.width) * std::uint64_t(L.height) * 3 * sizeof(float);
    const std::uint64_t need = render + held + sheet, have = available_memory();
    if (need > have)
        throw InputError(plans[0].pipeline.renderer_mark.str() + ": renderer: a collection of " +
                         std::to_string(plans.size()) + " children and their " + std::to_string(L.width) +
                         "x" + std::to_string(L.height) + " contact sheet needs " + format_bytes(need) +
                         " of memory with " + std::to_string(threads) + " thread(s); this machine has " +
                         format_bytes(have) + " available");
}

// Under mpirun, rank 0 receives the others' children in order: a header, then the pixels.
void gather_children(std::vector<RenderResult>& children) {
    const unsigned me = ranks::rank(), nr = ranks::size();
    for (std::size_t k = 0; k < children.size(); ++k) {
        const unsigned owner = unsigned(k % nr);
        if (owner == 0 || (me != 0 && me != owner)) continue;
        double head[5];
        RenderResult& c = children[k];
        if (me == owner) {
            head[0] = c.image.width, head[1] = c.image.height, head[2] = c.image.channels;
            head[3] = double(c.stats.samples), head[4] = c.seconds;
            ranks::send(0, head, sizeof head);
            ranks::send(0, c.image.pixels.data(), c.image.pixels.size() * sizeof(float));
            c.image = Image{}; // sent: its memory is free again
        } else {
            ranks::recv(owner, head, sizeof head);
            c.image.width = int(head[0]), c.image.height = int(head[1]), c.image.channels = int(head[2]);
            c.stats.samples = std::uint64_t(head[3]), c.seconds = head[4];
            c.stats.unit = children[0].stats.unit; // (one renderer for every child; rank 0 ran child 0)
            c.image.pixels.resize(std::size_t(c.image.width) * std::size_t(c.image.height) *
                                  std::size_t(c.image.channels));
            ranks::recv(owner, c.image.pixels.data(), c.image.pixels.size() * sizeof(float));
        }
    }
}

} // namespace

void run_collection(const Registry& reg, const CollectionRequest& req, const RenderHooks& hooks) {
    const auto [path, values] = parse_vary(req.vary);
    const auto say = [&](const std::string& l) {
        if (req.info) req.info(l);
    };
    std::vector<Pipeline> pipes;
    for (const auto& v : values) {
        pipes.push_back(load_pipeline(reg, req.config, req.sets, path + "=" + v, req.allow_code));
        if (req.draft) {
            std::vector<std::string> sets = req.sets;
            for (auto& s : draft_overrides(pipes.back(), draft_factor)) sets.push_back(std::move(s));
            pipes.back() = load_pipeline(reg, req.config, sets, path + "=" + v, req.allow_code);
        }
    }
    if (req.warn)
        for (const auto& w : pipes[0].warnings) req.warn(w); // (every child has the same plugins)

    // The sheet's file, checked as a render's; then each child's beside it, as the sheet may be
    // written (named with -o, the sheet names them too). Every child is planned before the first
    // renders: its config, its memory, its file.
    RenderRequest sheet = req.sheet;
    sheet.keep_image = true;
    sheet.distributed = false; // (each child renders whole on one rank)
    sheet.raster_only = "--vary: {}: a collection is written as PNG, EXR or TIFF images and a contact sheet, "
                        "not as SVG or PDF";
    const RequestOutput first = request_output(pipes[0], sheet);
    check_output_request(sheet, first.path, first.mark);
    const std::string& out = first.path;
    std::vector<RenderPlan> plans;
    for (std::size_t k = 0; k < pipes.size(); ++k) {
        RenderRequest child = sheet;
        child.output = child_path(out, k + 1);
        child.named_replaces = !req.sheet.output.empty();
        child.defer_write = true; // all the files or none: written below
        child.output_mark = first.mark;
        plans.push_back(plan_render(pipes[k], child));
    }
    const unsigned threads = plans[0].threads;
    check_collection_memory(plans, threads, req.columns);
    if (hooks.cancel && hooks.cancel->load()) throw Cancelled(); // during the checks above
    std::string recipes;
    for (const auto& p : pipes) recipes += p.recipe;
    ranks::agree_checks(recipes);
    if (req.validate_only) {
        say(req.config + ": valid: a collection of " + std::to_string(pipes.size()) + " children to " + out);
        return;
    }

    // Every child is rendered and checked before anything is written: a failing child leaves
    // no files behind. Under mpirun, child k is rendered whole by rank k mod N (a child's bytes
    // do not depend on where it ran) and sent to rank 0, which writes.
    const unsigned me = ranks::rank(), nr = ranks::size();
    std::vector<RenderResult> children(pipes.size());
    RenderHooks quiet = hooks;
    quiet.progress_bar = hooks.progress_bar && me == 0;
    for (std::size_t k = me; k < pipes.size(); k += nr) {
        children[k] = run_render(plans[k], quiet);
        if (req.warn)
            for (const auto& w : children[k].warnings) req.warn(w);
    }
    if (nr > 1) {
        gather_children(children);
        if (me != 0) return;
        ranks::set_phase(ranks::Phase::free); // the others are done: rank 0's errors are its own
    }
    std::vector<std::string> captions;
    std::vector<Image> images;
    double total = 0;
    for (std::size_t k = 0; k < pipes.size(); ++k) {
        const RenderResult& c = children[k];
        total += c.seconds;
        char secs[32];
        std::snprintf(secs, sizeof secs, "%.2f", c.seconds);
        say(path + "=" + values[k] + ": " + std::to_string(c.stats.samples) + " " + c.stats.unit + " in " +
            secs + " s" +
            (nr > 1 ? " on rank " + std::to_string(k % nr)
                    : ", " + std::to_string(c.stats.restarts) + " restarted chains"));
        captions.push_back(path.substr(path.rfind('.') + 1) + " = " + values[k]);
    }
    // All the files or none: a Ctrl-C or a full disk half way removes those written.
    FileSet files(hooks.cancel);
    for (std::size_t k = 0; k < pipes.size(); ++k)
        files.image(children[k].image, plans[k].output, pipes[k].bit_depth, pipes[k].recipe, pipes[k].tiled);
    for (auto& c : children) images.push_back(std::move(c.image));
    bool text = true;
    const Image sheet_image = contact_sheet(images, captions, req.columns, &text);
    if (!text && req.warn) req.warn("no font found for the captions (install fonts-dejavu-core)");
    files.image(sheet_image, out, pipes[0].bit_depth,
                "# contact sheet: --vary " + req.vary + "; children " + child_path(out, 1) + " ... " +
                    child_path(out, pipes.size()) + "\n# the recipe of the first child:\n" + pipes[0].recipe);
    files.commit();
    char secs[32];
    std::snprintf(secs, sizeof secs, "%.2f", total);
    say(out + ": contact sheet of " + std::to_string(pipes.size()) + " children (" + child_path(out, 1) +
        " ... " + child_path(out, pipes.size()) + ") in " + secs + " s" +
        (nr > 1 ? " of render time over " + std::to_string(nr) + " ranks" : ""));
}

} // namespace fp::host
