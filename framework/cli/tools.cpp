// The tool family: eval (a transform and scheme on points), to-subdivision (paper 05's converse
// construction), recipe (an image's recipe), addresses (paper 05's Algorithm 1), symmetry (the
// plane-group operations an image keeps).
#include "cli.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/flam3_import.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/tools/converse.hpp>
#include <fixpoint/host/tools/symmetry.hpp>
#include <fixpoint/host/tools/where.hpp>
#include <fixpoint/text.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace fs = std::filesystem;
using namespace fp::host;

namespace fp::cli {

namespace {

// A config rendered in memory for a measure, as `render` would check and render it (never written).
RenderRequest memory_request(const Options& o) {
    RenderRequest r;
    r.keep_image = true;
    r.threads = o.threads;
    return r;
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

constexpr long long max_eval_steps = 1'000'000'000'000;

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

// Paper 05's converse construction: affine maps to subdivision maps on a triangle or a lifted
// quad (host/converse.hpp), printed as the YAML items an mfs config's IFS takes.
int cmd_to_subdivision(const Options& o) {
    const CNode pts = parse_yaml(o.points, "--points");
    std::vector<Vec2> p;
    bool ok = pts.is_seq() && (pts.items.size() == 3 || pts.items.size() == 4);
    for (std::size_t j = 0; ok && j < pts.items.size(); ++j) {
        const CNode& q = pts.items[j];
        ok = q.is_seq() && q.items.size() == 2 && q.items[0].is_scalar() && q.items[1].is_scalar();
        char* e0 = nullptr;
        char* e1 = nullptr;
        if (ok) {
            p.push_back(
                {std::strtod(q.items[0].scalar.c_str(), &e0), std::strtod(q.items[1].scalar.c_str(), &e1)});
            ok = !*e0 && !*e1 && !q.items[0].scalar.empty() && !q.items[1].scalar.empty() &&
                 std::isfinite(p[j].x) && std::isfinite(p[j].y);
        }
    }
    if (!ok)
        throw InputError(
            "--points: expected three points [[x1, y1], [x2, y2], [x3, y3]] (a triangle) or four "
            "(a quad, lifted with z = x y)");
    const Registry reg = make_registry(o);
    const auto mats = subdivision_matrices(reg, p, o.maps);
    std::string pts_text = "[";
    for (std::size_t j = 0; j < p.size(); ++j)
        pts_text += std::string(j ? ", " : "") + "[" + number_text(p[j].x) + ", " + number_text(p[j].y) + "]";
    pts_text += "]";
    for (const auto& s : mats) {
        std::string m;
        for (std::size_t k = 0; k < s.size(); ++k) m += std::string(k ? ", " : "") + number_text(s[k]);
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
            RenderPlan plan = plan_render(p, memory_request(o));
            if (!region) frame = frame_from_recipe(p.recipe, p.renderer->width(), p.renderer->height(), path);
            RenderResult r = run_render(plan, render_hooks(o.quiet));
            tell(r.warnings);
            img = std::move(r.image);
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
        (void)plan_render(load_pipeline(*reg, f, is_against ? std::vector<std::string>{} : o.sets),
                          memory_request(o));
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

/// import's and export's -o, before any work: not replaced without --force, in a folder that exists.
void check_output(const Options& o) {
    if (o.out.empty()) return;
    if (!o.force && std::filesystem::exists(o.out))
        throw InputError(quote(o.out, 200) + " exists (--force replaces it)");
    const auto dir = std::filesystem::path(o.out).parent_path();
    if (!dir.empty() && !std::filesystem::is_directory(dir))
        throw InputError("cannot write " + quote(o.out, 200) + ": folder " + quote(dir.string(), 200) +
                         " does not exist");
}

// import: a flam3 genome as a config (host/core/flam3_import.hpp), to -o or stdout; its output
// image is named after the config.
int cmd_import(const Options& o) {
    if (!is_flam3_file(o.config))
        throw InputError(quote(o.config, 200) + ": not a flam3 genome file (.flam3, .flame or .flam)");
    if (!o.out.empty() && std::filesystem::path(o.out).extension() != ".yaml")
        throw InputError("-o " + quote(o.out, 200) + ": the config is YAML (name it .yaml)");
    check_output(o);
    Flam3Select which;
    which.index = o.level >= 0 ? int(o.level) : -1;
    which.name = o.name;
    const std::string image =
        o.out.empty() ? "" : std::filesystem::path(o.out).replace_extension(".png").filename().string();
    const Flam3Import im = import_flam3(o.config, which, image);
    for (const auto& w : im.warnings) std::fprintf(stderr, "warning: %s: %s\n", o.config.c_str(), w.c_str());
    if (o.out.empty()) {
        std::fputs(im.yaml.c_str(), stdout);
    } else {
        write_bytes(im.yaml, o.out);
        if (!o.quiet)
            std::fprintf(stderr, "%s: flame %d of %d of %s\n", o.out.c_str(), im.index, im.count,
                         o.config.c_str());
    }
    return 0;
}

// export: a chaos-game config as a flam3 genome (host/core/flam3_import.hpp), to -o or stdout.
int cmd_export(const Options& o) {
    if (!o.out.empty() && !is_flam3_file(o.out))
        throw InputError("-o " + quote(o.out, 200) + ": a genome file is .flam3, .flame or .flam");
    check_output(o);
    const Registry reg = make_registry(o);
    const Flam3Export ex = export_flam3(reg, o.config, o.sets);
    for (const auto& w : ex.warnings) std::fprintf(stderr, "warning: %s: %s\n", o.config.c_str(), w.c_str());
    if (o.out.empty()) {
        std::fputs(ex.xml.c_str(), stdout);
    } else {
        write_bytes(ex.xml, o.out);
        if (!o.quiet) std::fprintf(stderr, "%s: the genome of %s\n", o.out.c_str(), o.config.c_str());
    }
    return 0;
}

int cmd_recipe(const Options& o) {
    std::fputs(read_recipe(o.image).c_str(), stdout);
    return 0;
}

} // namespace

void add_tool_commands(CLI::App& app, Options& o, std::vector<Command>& table) {
    auto* eval = app.add_subcommand("eval", "Apply a transform to points read from stdin ('x y' per line)");
    eval->add_option("transform", o.transform,
                     "Transform as a YAML flow mapping, e.g. '{type: inversion, shape: {type: circle}}'")
        ->required();
    eval->add_option("--scheme", o.scheme,
                     "Iteration scheme as a YAML flow mapping (default {type: picard})");
    eval->add_option("--steps", o.steps,
                     "Steps per point (default 1, at most 10^12); step index n counts from 0");

    auto* to_sub = app.add_subcommand(
        "to-subdivision",
        "Paper 05's converse construction: affine maps as subdivision maps on a triangle or a quad");
    to_sub
        ->add_option("maps", o.maps,
                     "Affine maps as YAML flow mappings, e.g. '{type: affine, coefficients: [...]}'")
        ->required();
    to_sub
        ->add_option("--points", o.points,
                     "The control points: [[x1, y1], [x2, y2], [x3, y3]], or four (lifted with z = x y)")
        ->required();

    auto* imp = app.add_subcommand("import", "Make a config of a flam3 genome (.flam3): docs/flam3.md");
    imp->add_option("genome", o.config, "flam3 genome file (.flam3, .flame)")->required();
    imp->add_option("-o,--output", o.out, "The config to write (.yaml); default: standard output");
    auto* idx =
        imp->add_option("--index", o.level, "Which flame of a file of several, from 0 (default: the first)")
            ->check(CLI::Range(0LL, 1000000LL));
    imp->add_option("--name", o.name, "The flame of this name attribute")->excludes(idx);
    imp->add_flag("--force", o.force, "Replace an existing config");
    imp->add_flag("-q,--quiet", o.quiet, "No summary");
    table.push_back({imp, [&o] { return cmd_import(o); }});

    auto* exp =
        app.add_subcommand("export", "Write a chaos-game config as a flam3 genome (.flam3): docs/flam3.md");
    exp->add_option("config", o.config, "Config (YAML, or an image with a recipe)")->required();
    exp->add_option("-o,--output", o.out, "The genome to write (.flam3); default: standard output");
    add_sets(exp, o.sets, "Override a parameter before exporting: path.to.param=value (YAML)");
    exp->add_flag("--force", o.force, "Replace an existing genome");
    exp->add_flag("-q,--quiet", o.quiet, "No summary");
    table.push_back({exp, [&o] { return cmd_export(o); }});

    auto* recipe = app.add_subcommand("recipe", "Print the recipe embedded in an image");
    recipe->add_option("image", o.image, "Image written by fixpoint")->required();

    auto* addresses = app.add_subcommand(
        "addresses", "List the addresses of a renderer's polygons at a level (paper 05, Algorithm 1)");
    addresses->add_option("config", o.config, "Pipeline file (YAML)")->required();
    addresses->add_option("--level", o.level, "Level to list (default: the last)")
        ->check(CLI::Range(0LL, 1000LL));
    add_sets(addresses, o.sets);
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
    add_sets(symmetry, o.sets, "With a config: override a value, path.to.param=value (repeatable)");
    add_threads(symmetry, o.threads, "Worker threads to render a config with");
    symmetry->add_flag("--json", o.json, "Print the scores and groups as JSON");
    symmetry->add_flag("-q,--quiet", o.quiet, "No progress bar while a config renders");

    table.push_back({eval, [&o] { return cmd_eval(o); }});
    table.push_back({to_sub, [&o] { return cmd_to_subdivision(o); }});
    table.push_back({recipe, [&o] { return cmd_recipe(o); }});
    table.push_back({addresses, [&o] { return cmd_addresses(o); }});
    table.push_back({symmetry, [&o] { return cmd_symmetry(o); }});
}

} // namespace fp::cli
