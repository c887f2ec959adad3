// `fixpoint explore CONFIG`: a seeded search for good parameters (issue 17, item 1).
//
// Design.
// - The searched parameters are named with ranges: `--param PATH=A..B` (a real parameter,
//   uniform; an integer parameter with whole A and B, uniform over A..B), `--param
//   PATH=a+bq..c+dq` (a sequence parameter such as an iteration's alpha, as a q-number drawn
//   componentwise; a plain A..B on a sequence draws a real), `--param 'PATH=a|b|c'` (choices, any
//   parameter: each choice is YAML text, checked against the config before the search), or
//   `--random PLUGIN-PATH` (every real, integer, vector [a, b] and constant sequence parameter of that
//   plugin: over its declared range when both ends are finite and, for an integer, it holds
//   at most 64 values; else over v +- |v|/2, or +- 0.5 around 0, for the config's value v,
//   within the declared range: the plugins declare few two-ended ranges). PATH is
//   the path of `--set` (renderer.maps[0].shape.radius); the parameter may be one the config
//   leaves at its default. A path that is not a parameter, a bad range, a range outside the
//   declared one or a parameter kind a range does not fit is one line of error (exit 2).
// - Each candidate is the config with --set and then its values applied, validated like any
//   config (a candidate the validator refuses is counted as invalid and not ranked). Every
//   candidate of a phase is validated before any of them is rendered. It is rendered as a
//   draft: its larger side --draft-size pixels (the aspect kept), at most --draft-points points
//   (renderers with `points`), one sample per pixel (renderers with `samples`).
// - Measures (measures.hpp; each mapped to a score in [0, 1]): coverage, grey-level entropy and
//   box-counting dimension of the draft, and the largest Lyapunov exponent of the map for the
//   chaos-game renderer (Gumowski–Mira maps, inversions, affine IFS; absent for other renderers,
//   and its weight then ignored). The total is the weighted mean of the scores of the measures
//   present (--weights, default coverage=1,entropy=1,dimension=2,lyapunov=1,symmetry=0; for
//   orbit-trap, whose patterns fill the image, colour_entropy, edge_entropy, spectrum, group and
//   contrast 1 and the others 0: measures.hpp, wallpaper_measures.cpp). The
//   symmetry measure is `fixpoint symmetry`'s (symmetry.hpp): the best score of a rotation or
//   mirror about the origin, computed only when weighted. Adding a measure is one entry of
//   measure_table().
// - Search: --candidates N drawn at random, candidate i from fp::chain_stream(seed, i); then
//   --generations G, each of N children of the best K so far (two parents drawn from them,
//   uniform crossover of the values, each value mutated with probability 1/2 by a Gaussian step
//   of a tenth of its range, clamped, integers rounded; choices redrawn), child i of generation
//   g from chain_stream(seed, 2^32 g + i). A child equal to a candidate already scored is not
//   scored again. The best K distinct candidates of all generations are kept (elitism). Drafts
//   are rendered by --threads worker threads, one candidate per thread at a time, each renderer
//   run serially: the scores (and so the ranking and every file) do not depend on the thread
//   count.
// - Output (-o DIR, created if missing): best-1.yaml ... best-K.yaml (the config with --set and
//   the values applied, the scores in a comment), best-k.png (the full render, with its recipe),
//   sheet.png (a ranked contact sheet, captions: rank, score, values) and candidates.tsv (every
//   candidate: rank, scores, values, or why it was refused). An existing file among them is
//   replaced only with --force.
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/host/job/render_job.hpp>
#include <fixpoint/host/tools/explore.hpp>

#include "genes.hpp"
#include "scores.hpp"
#include <fixpoint/host/tools/measures.hpp>
#include <fixpoint/host/tools/symmetry.hpp>
#include <fixpoint/iteration.hpp>
#include <fixpoint/rng.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/transform.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

namespace fs = std::filesystem;

namespace fp::host {

const char* const explore_help = R"(Ranges (--param PATH=RANGE, PATH as in --set):
  A..B         a real parameter: uniform in [A, B]; an integer parameter: whole A..B
  a+bq..c+dq   a sequence parameter (an iteration's alpha): a q-number, componentwise
  'a|b|c'      choices, for any parameter (each a YAML value)
  --random P   every real, integer, vector ([a, b], each component) and constant sequence
               parameter of the plugin at path P
               (renderer.iteration, renderer.maps[0].shape): over its declared range when
               both ends are finite (integers: at most 64 values), else over v +- |v|/2 (+- 0.5
               around 0) for the config's value v, within the declared range; a renderer's
               size and quality (width, height, points, chains, samples, ...) are kept
Measures, each scored in [0, 1] on a draft (--draft-size, --draft-points):
  coverage   fraction of pixels not of the background; score: 0 at <= 0.2% (dust), rising
             log-linearly to 1 at 2%, 1 up to 60%, falling linearly to 0 at 100% (a blob)
  entropy    entropy of the grey-level histogram in bits (0..8); score: bits / 6, at most 1
  dimension  box-counting dimension of the lit pixels (least-squares slope over boxes of 2 to
             64 pixels, at most a quarter of the lit extent); score: 1 in [1.3, 1.8], linear
             to 0 at 0.5 and at 2 (a filled blob measures 1.9 to 2)
  lyapunov   largest Lyapunov exponent of the map (chaos-game only: finite differences along
             32 orbits of the maps drawn by weight, through the iteration scheme); score:
             1 / (1 + exp(-L / 0.05)), chaos near 1, regular orbits 0.5; absent for other
             renderers, and its weight ignored
  symmetry   the best symmetry about the origin: the highest score of `fixpoint symmetry`
             (fraction of pixels that agree) over the rotations by 180, 90, 120, 60 degrees
             and the mirrors in the axes and the diagonal; score: 0 at 0.5, linear to 1 at 1;
             weight 0 by default (the background agrees with itself: on a sparse picture
             everything scores high, so weight it beside coverage); absent with fit_view
  For patterns that fill the image (orbit-trap's wallpapers, where every candidate's coverage is 1
  and dimension 2) these five, each weighted 1 by default there and 0 elsewhere, calibrated on
  paper 04's Figs. 5 to 9 against random coefficients of their groups (scores linear between
  the two values given):
  colour_entropy  entropy of the colours (16 levels a channel), 0..12 bits; score 2 .. 6.5
  edge_entropy    entropy of the gradient's size (Sobel, 32 bins), 0..5 bits; score 2 .. 4.9
  spectrum        spread of the spatial spectrum: entropy of the power in 32 rings of radial
                  frequency over its largest (smooth: near 0, noise: near 1); score 0.6 .. 1
  group           the declared group's rotations and mirrors about the origin (their lowest
                  symmetry score) against the others (their highest): accidental extra
                  symmetry, or a flat picture, gives near 0; score 0 .. 0.8
  contrast        standard deviation of the grey level, 0..0.5; score 0.05 .. 0.3
  The score of a candidate is the weighted mean over the measures present (--weights).
Search: --candidates random ones (candidate i from chain_stream(seed, i)), then --generations
  of as many children of the best --keep (uniform crossover, Gaussian mutation of a tenth of
  the range, elitism). The same seed gives the same files on any number of threads.
Writes to -o DIR: best-1.yaml ... (the configs, their scores in a comment), best-k.png (full
  renders), sheet.png (ranked contact sheet) and candidates.tsv (every candidate's scores).
)";

namespace {

using namespace explore_detail;

/// The wallpaper group of an orbit-trap recipe's mapping (paper 04), or "".
std::string declared_group(const TObject& r) {
    const TParam* m = param_of(r, "mapping");
    if (!m || !m->object) return "";
    const TParam* g = param_of(*m->object, "group");
    const auto* name = g ? std::get_if<std::string>(&g->value) : nullptr;
    return name ? *name : "";
}

// ---- candidates --------------------------------------------------------------------------

struct Candidate {
    std::uint64_t id = 0; ///< order of creation (the tie-break of the ranking)
    int generation = 0;
    std::vector<Gene> genes;
    std::vector<std::string> overrides; ///< PATH=VALUE
    std::string key;
    bool valid = false;
    std::string why; ///< why refused
    std::vector<std::optional<double>> raw;
    std::vector<double> scores;
    double total = 0;
    // Between validation and scoring: the draft's render, planned.
    std::shared_ptr<RenderPlan> plan;
    std::unique_ptr<TObject> typed;
    Rgb background;
    std::optional<PixelFrame> frame;
    std::string group; ///< the wallpaper group its recipe declares (the group measure)
};

struct Search {
    const Registry& reg;
    const ExploreOptions& o;
    CNode base;                          ///< the config with --set applied
    std::vector<std::string> draft_sets; ///< the draft's overrides
    std::vector<Dim> dims;
    std::vector<double> weights;
    std::vector<Candidate> all;
    std::set<std::string> seen;
    unsigned threads = 1;

    void make(Candidate c) {
        for (std::size_t j = 0; j < dims.size(); ++j) {
            c.overrides.push_back(dims[j].path + "=" + gene_text(dims[j], c.genes[j]));
            c.key += c.overrides.back() + "\n";
        }
        if (!seen.insert(c.key).second) return; // scored already
        all.push_back(std::move(c));
    }

    // Validate every new candidate (serially), then render and measure them in parallel.
    void score(std::size_t from) {
        for (std::size_t i = from; i < all.size(); ++i) {
            Candidate& c = all[i];
            try {
                CNode root = base;
                for (const auto& s : c.overrides) apply_override(root, s, "--param");
                for (const auto& s : draft_sets) apply_override(root, s, "--draft");
                c.typed = validate(reg, Kind::Renderer, *root.find("renderer"), "renderer");
                const Pipeline dp = load_pipeline(reg, root);
                // On its own thread alone (the parallelism is over candidates); an empty draft
                // scores low rather than failing.
                RenderRequest draft;
                draft.keep_image = true;
                draft.serial = true;
                draft.allow_empty = true;
                c.plan = std::make_shared<RenderPlan>(plan_render(dp, draft));
                // The draft's frame in the plane, for the symmetry measure: none with fit_view
                // (the recipe's view is not the one drawn) or without a view or area.
                const TParam* fit = param_of(*c.typed, "fit_view");
                if (!(fit && std::holds_alternative<bool>(fit->value) && std::get<bool>(fit->value))) try {
                        c.frame = frame_from_recipe(dp.recipe, dp.renderer->width(), dp.renderer->height(),
                                                    "draft");
                    } catch (const InputError&) {
                    }
                c.group = declared_group(*c.typed);
                if (const TParam* bg = param_of(*c.typed, "background"))
                    if (const auto* rgb = std::get_if<Rgb>(&bg->value)) c.background = *rgb;
                c.valid = true;
            } catch (const InputError& e) {
                c.valid = false;
                c.why = e.what();
            }
        }
        std::atomic<std::size_t> next{from};
        std::mutex m;
        std::exception_ptr failure;
        auto work = [&] {
            for (;;) {
                const std::size_t i = next.fetch_add(1);
                if (i >= all.size()) return;
                Candidate& c = all[i];
                if (!c.valid) continue;
                try {
                    if (o.cancel && o.cancel->load()) throw Cancelled();
                    RenderHooks hooks;
                    hooks.cancel = o.cancel;
                    const Image img = run_render(*c.plan, hooks).image;
                    Draft d{&img,
                            c.background,
                            chaos_game_lyapunov(reg, *c.typed, o.seed, c.id),
                            c.frame ? &*c.frame : nullptr,
                            weights[symmetry_index()] > 0,
                            c.group,
                            weights[measure_index("group")] > 0};
                    double sw = 0, s = 0;
                    for (std::size_t k = 0; k < measure_table().size(); ++k) {
                        const auto& md = measure_table()[k];
                        c.raw.push_back(md.raw(d));
                        c.scores.push_back(c.raw.back() ? md.score(*c.raw.back()) : 0);
                        if (c.raw.back()) sw += weights[k], s += weights[k] * c.scores.back();
                    }
                    c.total = sw > 0 ? s / sw : 0;
                } catch (const InputError& e) {
                    c.valid = false;
                    c.why = e.what();
                } catch (...) {
                    const std::lock_guard<std::mutex> lock(m);
                    if (!failure) failure = std::current_exception();
                    next.store(all.size());
                }
                c.plan.reset();
                c.typed.reset();
            }
        };
        std::vector<std::thread> pool;
        for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
        work();
        for (auto& t : pool) t.join();
        if (failure) std::rethrow_exception(failure);
    }

    /// Valid candidates, best first (ties: the earlier).
    std::vector<const Candidate*> ranking() const {
        std::vector<const Candidate*> r;
        for (const auto& c : all)
            if (c.valid) r.push_back(&c);
        std::stable_sort(r.begin(), r.end(), [](const Candidate* a, const Candidate* b) {
            if (a->total != b->total) return a->total > b->total;
            return a->id < b->id;
        });
        return r;
    }
};

std::string fixed(double v, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

std::string measures_line(const Candidate& c) {
    std::string s;
    for (std::size_t k = 0; k < measure_table().size(); ++k) {
        s += std::string(s.empty() ? "" : ", ") + measure_table()[k].name + " ";
        s += c.raw[k] ? fixed(*c.raw[k], 4) + " (score " + fixed(c.scores[k], 3) + ")" : "absent";
    }
    return s;
}

std::string short_name(const std::string& path) {
    const auto dot = path.rfind('.');
    return dot == std::string::npos ? path : path.substr(dot + 1);
}

} // namespace

int run_explore(const Registry& reg, const ExploreOptions& o) {
    auto say = [&](const std::string& s) {
        if (o.info) o.info(s);
    };
    if (o.params.empty() && o.random.empty())
        throw InputError(
            "explore: name the parameters to search with --param PATH=RANGE or --random PLUGIN-PATH");
    Search S{reg, o, {}, {}, {}, {}, {}, {}, 1};
    S.threads = o.threads ? o.threads : hardware_threads();

    // The config with --set, validated as a whole first.
    // A config, or an image fixpoint wrote (its recipe); either without output.path, so that a
    // best-k.yaml rendered without -o does not write where the original did.
    S.base = load_config(o.config, o.allow_python);
    if (CNode* out = S.base.find("output"); out && out->is_map())
        for (std::size_t i = 0; i < out->keys.size(); ++i)
            if (out->keys[i].first == "path") {
                out->keys.erase(out->keys.begin() + std::ptrdiff_t(i));
                out->key_marks.erase(out->key_marks.begin() + std::ptrdiff_t(i));
                break;
            }
    for (const auto& s : o.sets) apply_override(S.base, s);
    const Pipeline base_pipe = load_pipeline(reg, S.base);
    const auto typed = validate(reg, Kind::Renderer, *S.base.find("renderer"), "renderer");
    // Patterns that fill the image are ranked by the wallpaper measures by default.
    const bool wallpaper = std::string(typed->plugin->desc->name) == "orbit-trap";
    S.weights = parse_weights(o.weights, wallpaper);
    Index idx;
    idx.add(*typed);

    std::set<std::string> taken;
    for (const auto& p : o.params) {
        S.dims.push_back(parse_param(reg, S.base, idx, p, o.config));
        if (!taken.insert(S.dims.back().path).second)
            throw InputError(excerpt("--param " + p, 100) + ": " + quote(S.dims.back().path, 100) +
                             " is named twice");
    }
    for (const auto& r : o.random)
        for (auto& d : random_dims(idx, r, o.config, taken)) {
            taken.insert(d.path);
            S.dims.push_back(std::move(d));
        }

    // The draft: the larger side draft_size pixels, few points, one sample per pixel.
    {
        const TParam* w = param_of(*typed, "width");
        const TParam* h = param_of(*typed, "height");
        if (w && h && std::holds_alternative<std::int64_t>(w->value) &&
            std::holds_alternative<std::int64_t>(h->value)) {
            const double W = double(std::get<std::int64_t>(w->value)),
                         H = double(std::get<std::int64_t>(h->value));
            const double f = std::min(1.0, double(o.draft_size) / std::max(W, H));
            S.draft_sets.push_back("renderer.width=" + std::to_string(std::max(1LL, std::llround(W * f))));
            S.draft_sets.push_back("renderer.height=" + std::to_string(std::max(1LL, std::llround(H * f))));
        }
        if (const TParam* p = param_of(*typed, "points");
            p && std::holds_alternative<std::int64_t>(p->value)) {
            const long long pts = std::min<long long>(std::get<std::int64_t>(p->value), o.draft_points);
            S.draft_sets.push_back("renderer.points=" + std::to_string(pts));
            if (const TParam* c = param_of(*typed, "chains");
                c && std::holds_alternative<std::int64_t>(c->value))
                if (std::get<std::int64_t>(c->value) > pts)
                    S.draft_sets.push_back("renderer.chains=" + std::to_string(pts));
        }
        if (const TParam* p = param_of(*typed, "samples");
            p && std::holds_alternative<std::int64_t>(p->value))
            S.draft_sets.push_back("renderer.samples=1");
    }

    // Every file written, checked before the search.
    const fs::path dir(o.out_dir);
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw InputError("-o " + quote(o.out_dir, 200) + ": not a folder");
    std::vector<std::string> files = {(dir / "sheet.png").string(), (dir / "candidates.tsv").string()};
    for (int k = 1; k <= o.keep; ++k) {
        files.push_back((dir / ("best-" + std::to_string(k) + ".yaml")).string());
        files.push_back((dir / ("best-" + std::to_string(k) + ".png")).string());
    }
    if (!o.force)
        for (const auto& f : files)
            if (fs::exists(fs::symlink_status(f, ec)))
                throw InputError(quote(f, 200) + " exists: add --force to replace it");
    check_memory(base_pipe, S.threads);

    // Random phase.
    for (int i = 0; i < o.candidates; ++i) {
        Rng r = chain_stream(o.seed, std::uint64_t(i));
        Candidate c;
        c.id = std::uint64_t(i);
        for (const auto& d : S.dims) c.genes.push_back(draw(d, r));
        S.make(std::move(c));
    }
    S.score(0);
    auto summary = [&](const char* what) {
        const auto r = S.ranking();
        std::size_t invalid = 0;
        for (const auto& c : S.all) invalid += !c.valid;
        say(std::string(what) + ": " + std::to_string(S.all.size()) + " candidates, " +
            std::to_string(invalid) + " invalid; best " +
            (r.empty() ? std::string("none") : fixed(r[0]->total, 4)));
    };
    summary("random phase");
    if (o.cancel && o.cancel->load()) throw Cancelled();

    // Evolutionary phase.
    for (int g = 1; g <= o.generations; ++g) {
        const auto ranked = S.ranking();
        if (ranked.empty()) break;
        std::vector<std::vector<Gene>> parents;
        for (std::size_t k = 0; k < ranked.size() && k < std::size_t(o.keep); ++k)
            parents.push_back(ranked[k]->genes);
        const std::size_t from = S.all.size();
        for (int i = 0; i < o.candidates; ++i) {
            Rng r = chain_stream(o.seed, (std::uint64_t(g) << 32) | std::uint64_t(i));
            const auto& a = parents[uniform_below(r, std::uint32_t(parents.size()))];
            const auto& b = parents[uniform_below(r, std::uint32_t(parents.size()))];
            Candidate c;
            c.id = (std::uint64_t(g) << 32) | std::uint64_t(i);
            c.generation = g;
            for (std::size_t j = 0; j < S.dims.size(); ++j) {
                Gene x = uniform_double(r) < 0.5 ? a[j] : b[j];
                if (uniform_double(r) < 0.5) mutate(S.dims[j], x, r);
                c.genes.push_back(x);
            }
            S.make(std::move(c));
        }
        S.score(from);
        summary(("generation " + std::to_string(g)).c_str());
        if (o.cancel && o.cancel->load()) throw Cancelled();
    }

    const auto ranked = S.ranking();
    if (ranked.empty()) {
        std::string why;
        for (const auto& c : S.all)
            if (!c.why.empty()) {
                why = c.why;
                break;
            }
        throw InputError("explore: none of the " + std::to_string(S.all.size()) + " candidates is valid" +
                         (why.empty() ? "" : " (the first refusal: " + why + ")"));
    }
    const std::size_t keep = std::min<std::size_t>(ranked.size(), std::size_t(o.keep));

    // The full renders of the best, each checked like a render.
    std::vector<RenderPlan> plans;
    std::vector<CNode> roots;
    for (std::size_t k = 0; k < keep; ++k) {
        CNode root = S.base;
        for (const auto& s : ranked[k]->overrides) apply_override(root, s, "--param");
        RenderRequest full;
        full.keep_image = true;
        full.threads = S.threads;
        plans.push_back(plan_render(load_pipeline(reg, root), full));
        roots.push_back(std::move(root));
    }
    fs::create_directories(dir, ec);
    if (ec) throw InputError("-o " + quote(o.out_dir, 200) + ": cannot create the folder: " + ec.message());
    for (const auto& f : files)
        if (f.ends_with(".png")) check_output(f);
    std::vector<Image> images;
    std::vector<std::string> captions;
    for (std::size_t k = 0; k < keep; ++k) {
        RenderHooks hooks;
        hooks.cancel = o.cancel;
        images.push_back(run_render(plans[k], hooks).image);
        // Rank, score and the values (3 digits; named when there is one): a caption fits a cell.
        std::string cap = "#" + std::to_string(k + 1) + " " + fixed(ranked[k]->total, 3) + " ";
        for (std::size_t j = 0; j < S.dims.size(); ++j) {
            Dim d = S.dims[j];
            d.digits = 3;
            cap += std::string(j ? ", " : "") + (S.dims.size() == 1 ? short_name(d.path) + " = " : "") +
                   gene_text(d, ranked[k]->genes[j]);
        }
        // Cut to the cell (12-pixel DejaVu Sans: digits about 7.6 pixels wide).
        const std::size_t fits = std::size_t(std::max(8.0, (images.back().width - 4) / 7.6));
        if (cap.size() > fits) cap = cap.substr(0, fits - 2) + "..";
        captions.push_back(cap);
        say("best-" + std::to_string(k + 1) + ": score " + fixed(ranked[k]->total, 4) + ": " +
            measures_line(*ranked[k]));
    }

    std::string command = "fixpoint explore " + o.config + " --seed " + std::to_string(o.seed) +
                          " --candidates " + std::to_string(o.candidates) + " --generations " +
                          std::to_string(o.generations);
    command += " --keep " + std::to_string(o.keep) + " --draft-size " + std::to_string(o.draft_size) +
               " --draft-points " + std::to_string(o.draft_points);
    for (const auto& s : o.sets) command += " --set '" + s + "'";
    for (const auto& p : o.params) command += " --param '" + p + "'";
    for (const auto& r : o.random) command += " --random " + r;
    if (!o.weights.empty()) command += " --weights " + o.weights;
    // All the files or none: a Ctrl-C or a full disk half way removes those written.
    FileSet written(o.cancel);
    for (std::size_t k = 0; k < keep; ++k) {
        const Candidate& c = *ranked[k];
        std::string head = "# " + command + "\n# rank " + std::to_string(k + 1) + " of " +
                           std::to_string(ranked.size()) + " valid candidates (generation " +
                           std::to_string(c.generation) + "), score " + fixed(c.total, 4) + "\n# " +
                           measures_line(c) + "\n";
        for (const auto& s : c.overrides) head += "# " + s + "\n";
        const std::string base_name = (dir / ("best-" + std::to_string(k + 1))).string();
        written.bytes(head + emit_yaml(roots[k]), base_name + ".yaml");
        written.image(images[k], base_name + ".png", plans[k].pipeline.bit_depth, plans[k].pipeline.recipe);
    }
    const Image sheet = contact_sheet(images, captions, o.columns);
    written.image(sheet, (dir / "sheet.png").string(), 8,
                  "# contact sheet: " + command + "\n# the recipe of best-1:\n" + plans[0].pipeline.recipe);

    // Every candidate: ranked ones by rank, then the refused ones.
    std::string tsv = "rank\tid\tgeneration\tscore";
    for (const auto& m : measure_table()) tsv += std::string("\t") + m.name + "\t" + m.name + "_score";
    for (const auto& d : S.dims) tsv += "\t" + d.path;
    tsv += "\trefused\n";
    auto row = [&](const Candidate& c, const std::string& rank) {
        tsv += rank + "\t" + std::to_string(c.id) + "\t" + std::to_string(c.generation) + "\t" +
               (c.valid ? fixed(c.total, 6) : "");
        for (std::size_t k = 0; k < measure_table().size(); ++k) {
            const bool has = c.valid && k < c.raw.size() && c.raw[k];
            tsv += "\t" + (has ? fixed(*c.raw[k], 6) : "") + "\t" + (has ? fixed(c.scores[k], 6) : "");
        }
        for (std::size_t j = 0; j < S.dims.size(); ++j) tsv += "\t" + gene_text(S.dims[j], c.genes[j]);
        std::string why = c.why;
        std::replace(why.begin(), why.end(), '\t', ' ');
        std::replace(why.begin(), why.end(), '\n', ' ');
        tsv += "\t" + why + "\n";
    };
    for (std::size_t k = 0; k < ranked.size(); ++k) row(*ranked[k], std::to_string(k + 1));
    for (const auto& c : S.all)
        if (!c.valid) row(c, "-");
    written.bytes(tsv, (dir / "candidates.tsv").string());
    written.commit();
    say(o.out_dir + ": best-1 ... best-" + std::to_string(keep) +
        " (.yaml, .png), sheet.png, candidates.tsv");
    return 0;
}

} // namespace fp::host
