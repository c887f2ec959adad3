// The top level of a config file.
#include <fixpoint/host/core/flam3_import.hpp>
#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/ranks.hpp>
#include <fixpoint/host/core/render_version.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/version.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>

namespace fp::host {

namespace {

/// FNV-1a (64 bits) of a plugin's file, "fnv1a64:" and 16 hex digits: tells two builds of one
/// version apart in a recipe (an identity, not a security measure). Empty if it cannot be read.
std::string hash_file(const std::filesystem::path& f) {
    std::FILE* fp = std::fopen(f.c_str(), "rb");
    if (!fp) return "";
    std::uint64_t h = 14695981039346656037ull;
    unsigned char buf[1 << 16];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, fp)) > 0;)
        for (std::size_t i = 0; i < n; ++i) h = (h ^ buf[i]) * 1099511628211ull;
    const bool ok = !std::ferror(fp);
    std::fclose(fp);
    if (!ok) return "";
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return std::string("fnv1a64:") + hex;
}

/// hash_file once per file and process: a loaded plugin's file does not change under it, and
/// a process that loads many pipelines (a collection, the fuzzer) reads each file once.
std::string file_hash(const std::filesystem::path& f) {
    static std::mutex m;
    static std::map<std::filesystem::path, std::string> known;
    const std::lock_guard<std::mutex> lock(m);
    const auto it = known.find(f);
    if (it != known.end()) return it->second;
    return known.emplace(f, hash_file(f)).first->second;
}

/// The plugins a validated tree uses, by name; skip_finish: not those of the parameters whose
/// role is finish (a filter: a kept histogram does not depend on it).
void used_plugins(const TObject& t, std::map<std::string, const PluginEntry*>& out,
                  bool skip_finish = false) {
    out.emplace(t.plugin->desc->name, t.plugin);
    for (const auto& p : t.params) {
        if (skip_finish && p.spec->role == ParamRole::finish) continue;
        if (p.object) used_plugins(*p.object, out, skip_finish);
        for (const auto& it : p.items) used_plugins(*it.object, out, skip_finish);
    }
}

} // namespace

CNode load_config(const std::string& path, bool allow_code) {
    // A flam3 genome: the config its import makes (core/flam3_import.hpp), its output the
    // render's default.
    if (is_flam3_file(path)) {
        const Flam3Import im = import_flam3(path, {}, "");
        for (const auto& w : im.warnings) std::fprintf(stderr, "warning: %s: %s\n", path.c_str(), w.c_str());
        return parse_config(im.yaml, path);
    }
    // A histogram file (render --histogram) carries its recipe as an image does.
    const bool histogram = is_histogram_file(path), image = histogram || is_recipe_image(path);
    CNode root = parse_config(histogram ? read_histogram_header(path).recipe
                              : image   ? read_recipe(path)
                                        : read_yaml_text(path),
                              path);
    if (!image) return root;
    if (CNode* out = root.find("output"); out && out->is_map())
        for (std::size_t i = 0; i < out->keys.size(); ++i)
            if (out->keys[i].first == "path") {
                out->keys.erase(out->keys.begin() + std::ptrdiff_t(i));
                out->key_marks.erase(out->key_marks.begin() + std::ptrdiff_t(i));
                break;
            }
    if (!allow_code) refuse_code(root);
    return root;
}

Pipeline load_pipeline(const Registry& reg, const std::string& path, const std::vector<std::string>& sets,
                       const std::string& vary, bool allow_code) {
    CNode root = load_config(path, allow_code);
    for (const auto& s : sets) apply_override(root, s);
    if (!vary.empty()) apply_override(root, vary, "--vary");
    return load_pipeline(reg, std::move(root));
}

Pipeline load_pipeline(const Registry& reg, CNode root) {
    auto fail = [](const Mark& m, const std::string& msg) { throw InputError(m.str() + ": " + msg); };
    if (!root.is_map()) fail(root.mark, "expected a mapping with a 'renderer:' key, got " + root.describe());
    // animation: is read by `fixpoint animate` (animate.cpp); a render of the config as it
    // stands leaves it aside, and recipes do not carry it.
    const std::vector<std::string> top = {"renderer",       "output",  "fixpoint_version",
                                          "render_version", "plugins", "animation"};
    for (std::size_t i = 0; i < root.keys.size(); ++i) {
        const auto& k = root.keys[i].first;
        if (std::find(top.begin(), top.end(), k) != top.end()) continue;
        const auto near = suggest(k, top);
        fail(root.key_marks[i],
             "unknown top-level key " + quote(k) +
                 (near.empty() ? " (expected renderer, output)" : " (did you mean '" + near[0] + "'?)"));
    }
    const CNode* r = root.find("renderer");
    if (!r) fail(root.mark, "missing 'renderer:' (the pipeline to render)");

    Pipeline p;
    if (const CNode* o = root.find("output")) {
        if (!o->is_map()) fail(o->mark, "output: expected a mapping (path, bit_depth), got " + o->describe());
        for (std::size_t i = 0; i < o->keys.size(); ++i) {
            const auto& [k, v] = o->keys[i];
            if (k == "path") {
                if (!v.is_scalar()) fail(v.mark, "output.path: expected a file name, got " + v.describe());
                p.output_path = v.scalar;
                p.output_mark = v.mark;
            } else if (k == "bit_depth") {
                if (!v.is_scalar() || (v.scalar != "8" && v.scalar != "16"))
                    fail(v.mark, "output.bit_depth: must be 8 or 16, got " + v.describe());
                p.bit_depth = v.scalar == "8" ? 8 : 16;
            } else if (k == "tiled") {
                if (!v.is_scalar() || (v.scalar != "auto" && v.scalar != "true" && v.scalar != "false"))
                    fail(v.mark, "output.tiled: must be auto, true or false, got " + v.describe());
                p.tiled = v.scalar == "auto" ? Tiled::Auto : v.scalar == "true" ? Tiled::Yes : Tiled::No;
                p.tiled_mark = v.mark;
            } else {
                const auto near = suggest(k, {"path", "bit_depth", "tiled"});
                fail(o->key_marks[i], "output: unknown key " + quote(k) +
                                          (near.empty() ? " (expected path, bit_depth, tiled)"
                                                        : " (did you mean '" + near[0] + "'?)"));
            }
        }
    }
    // Stage 2: validate the whole tree against the schemas; stage 3: build.
    auto typed = validate(reg, Kind::Renderer, *r, "renderer");
    p.renderer = std::dynamic_pointer_cast<const Renderer>(build(reg, *typed));
    if (!p.renderer) throw InternalError("renderer plugin built an object that is not a Renderer");
    p.renderer_mark = r->mark;
    p.renderer_type = typed->plugin->desc->name;
    p.renderer_plugin = typed->plugin;

    // The plugins the render uses, each "VERSION HASH": recorded in the recipe, and compared
    // with those a recipe (or a config copied from one) was made with.
    std::map<std::string, const PluginEntry*> used;
    used_plugins(*typed, used);
    for (const auto& [name, e] : used)
        if (e->desc->abilities & ability::one_batch_at_a_time && p.one_thread.empty())
            p.one_thread = name + " runs one batch at a time";
    CNode record = map_node();
    for (const auto& [name, e] : used) {
        const std::string hash = file_hash(e->file);
        record.keys.emplace_back(
            name, scalar_node(std::string(e->desc->version) + (hash.empty() ? "" : " " + hash), true));
    }
    record.key_marks.resize(record.keys.size());
    std::vector<std::string> other_builds;
    if (const CNode* given = root.find("plugins")) {
        if (!given->is_map())
            fail(given->mark, "plugins: expected a mapping of plugin names to 'VERSION HASH' (as a recipe "
                              "records them), got " +
                                  given->describe());
        for (std::size_t i = 0; i < given->keys.size(); ++i) {
            const auto& [name, v] = given->keys[i];
            if (!v.is_scalar())
                fail(v.mark, "plugins." + name + ": expected 'VERSION HASH', got " + v.describe());
            const CNode* now = record.find(name);
            if (!now || now->scalar == v.scalar) continue;
            std::string line = "plugin " + quote(name) + " is " + now->scalar +
                               ", the recipe was made with " + v.scalar + ": the image may differ";
            // Another version of a plugin is refused by --strict; another build of the same version
            // is told only: the render version covers the builds of fixpoint's own plugins (the
            // golden corpus holds every build to it).
            const auto version_of = [](const std::string& s) { return s.substr(0, s.find(' ')); };
            (version_of(now->scalar) != version_of(v.scalar) ? p.may_differ : other_builds)
                .push_back(std::move(line));
        }
    }
    // The render version of a recipe (render_version.hpp): one without it (a recipe has
    // fixpoint_version or plugins) was made by version 1. A config written by hand has neither
    // and renders by this version.
    p.recipe_mark = root.mark;
    int made_by = render_version();
    if (const CNode* rv = root.find("render_version")) {
        p.recipe_mark = rv->mark;
        std::size_t used_chars = 0;
        int n = 0;
        try {
            n = rv->is_scalar() ? std::stoi(rv->scalar, &used_chars) : 0;
        } catch (const std::exception&) {
            n = 0;
        }
        if (n < 1 || used_chars != rv->scalar.size())
            fail(rv->mark, "render_version: expected a whole number from 1 (as a recipe records it), got " +
                               rv->describe());
        made_by = n;
    } else if (root.find("fixpoint_version") || root.find("plugins")) {
        made_by = 1;
    }
    std::vector<std::string> names;
    for (const auto& [name, e] : used) names.push_back(name);
    if (std::string d = render_version_difference(made_by, names, params_of(root)); !d.empty())
        p.may_differ.insert(p.may_differ.begin(), std::move(d));
    p.warnings = p.may_differ;
    p.warnings.insert(p.warnings.end(), other_builds.begin(), other_builds.end());

    CNode recipe = map_node();
    recipe.keys.emplace_back("fixpoint_version", scalar_node(FIXPOINT_VERSION, true));
    recipe.keys.emplace_back("render_version", scalar_node(std::to_string(render_version())));
    recipe.keys.emplace_back("plugins", std::move(record));
    recipe.keys.emplace_back("renderer", resolved(*typed));
    CNode out = map_node();
    out.keys.emplace_back("bit_depth", scalar_node(std::to_string(p.bit_depth)));
    // (Only when given: the bytes of a file, not its pixels; recipes before it stay as they were.)
    if (p.tiled != Tiled::Auto)
        out.keys.emplace_back("tiled", scalar_node(p.tiled == Tiled::Yes ? "true" : "false"));
    out.key_marks.resize(out.keys.size());
    recipe.keys.emplace_back("output", std::move(out));
    recipe.key_marks.resize(recipe.keys.size());
    p.recipe = emit_yaml(recipe);
    // What a checkpoint must match to be continued: the recipe but renderer.points, which a
    // resumed render may raise.
    CNode& rnode = recipe.keys[3].second; // renderer
    for (std::size_t i = 0; i < rnode.keys.size(); ++i) {
        if (rnode.keys[i].first != "points") continue;
        try {
            p.points = std::stoll(rnode.keys[i].second.scalar);
        } catch (const std::exception&) {
            p.points = -1;
        }
        rnode.keys.erase(rnode.keys.begin() + std::ptrdiff_t(i));
        if (i < rnode.key_marks.size()) rnode.key_marks.erase(rnode.key_marks.begin() + std::ptrdiff_t(i));
        break;
    }
    p.identity = emit_yaml(recipe);
    // What a kept histogram depends on: the recipe without its finishing parameters (but with
    // its points, which the histogram counts).
    CNode sums = map_node();
    for (std::size_t i = 0; i < 2; ++i) sums.keys.push_back(recipe.keys[i]);
    std::map<std::string, const PluginEntry*> summed;
    used_plugins(*typed, summed, true);
    CNode sums_record = map_node();
    for (const auto& [name, e] : summed)
        if (const CNode* had = recipe.keys[2].second.find(name)) sums_record.keys.emplace_back(name, *had);
    sums_record.key_marks.resize(sums_record.keys.size());
    sums.keys.emplace_back("plugins", std::move(sums_record));
    sums.keys.emplace_back("renderer", resolved(*typed, true));
    sums.key_marks.resize(sums.keys.size());
    p.histogram_identity = emit_yaml(sums);
    return p;
}

CheckpointHeader checkpoint_header(const Pipeline& p) {
    return CheckpointHeader{render_version_tag(), p.renderer_type, p.identity, p.points};
}

void check_memory(const Pipeline& p, unsigned threads) {
    // Under mpirun, the ranks on this machine each hold a render's buffers (host/ranks.hpp).
    const unsigned local = ranks::on_this_machine();
    const std::uint64_t need = p.renderer->memory_bytes(threads) * local, have = available_memory();
    if (need > have)
        throw InputError(p.renderer_mark.str() + ": renderer: a " + std::to_string(p.renderer->width()) +
                         "x" + std::to_string(p.renderer->height()) + " render needs " + format_bytes(need) +
                         " of memory with " + std::to_string(threads) + " thread(s)" +
                         (local > 1 ? " on each of " + std::to_string(local) + " ranks" : "") +
                         "; this machine has " + format_bytes(have) + " available");
}

void check_tiled(const Pipeline& p, const std::string& out) {
    try {
        (void)tiled_file(out, p.renderer->width(), p.renderer->height(), p.tiled);
    } catch (const InputError& e) {
        if (p.tiled_mark.line > 0) throw InputError(p.tiled_mark.str() + ": " + e.what());
        throw;
    }
}

MemoryPlan check_memory_within(const Pipeline& p, unsigned threads, std::uint64_t requested, bool can_stream,
                               std::uint64_t held) {
    const unsigned local = ranks::on_this_machine();
    const std::uint64_t have = requested ? requested : available_memory(), budget = have / local;
    const std::uint64_t whole = p.renderer->memory_bytes(threads);
    if (whole <= budget) return {budget, false};
    const bool stream = can_stream && p.renderer->streams_rows();
    // Streamed, the renderer has the budget less what the host holds beside it.
    const std::uint64_t need =
        stream ? p.renderer->memory_within(threads, budget > held ? budget - held : 0) + held : whole;
    if (need > budget) {
        // Over even in strips, or a renderer that cannot make them: say the least that works.
        const bool strips = need < whole;
        throw InputError(p.renderer_mark.str() + ": renderer: a " + std::to_string(p.renderer->width()) +
                         "x" + std::to_string(p.renderer->height()) + " render needs " +
                         (strips ? "at least " : "") + format_bytes(need) + " of memory with " +
                         std::to_string(threads) + " thread(s)" + (strips ? ", in strips of one row" : "") +
                         (local > 1 ? " on each of " + std::to_string(local) + " ranks" : "") + "; " +
                         (requested ? "--memory gives " + format_bytes(requested)
                                    : "this machine has " + format_bytes(have) + " available"));
    }
    return {budget - held, true};
}

std::string check_drawn(const Pipeline& p, const RenderStats& st) {
    if (st.drawn == RenderStats::unknown_count) return "";
    // Chains that restart or escape explain an empty image; say so only when there were any.
    std::string why;
    if (st.restarts || st.bad_values)
        why = "; " + std::to_string(st.restarts) + " restarted chain" + (st.restarts == 1 ? "" : "s") + ", " +
              std::to_string(st.bad_values) + " bad value" + (st.bad_values == 1 ? "" : "s") +
              " (points escaping to infinity or NaN)";
    if (st.drawn == 0)
        throw InputError(p.renderer_mark.str() + ": renderer: nothing was drawn (0 of " +
                         std::to_string(st.samples) + " " + st.unit + " " + st.drawn_means + why +
                         "); check the view and the parameters");
    if (double(st.drawn) < 0.001 * double(st.samples))
        return "only " + std::to_string(st.drawn) + " of " + std::to_string(st.samples) + " " + st.unit +
               " " + st.drawn_means + why;
    return "";
}

bool check_vector_output(const Pipeline& p, const std::string& out) {
    const bool vector = is_vector(format_for(out));
    if (vector && !p.renderer->has_vector_output())
        throw InputError(p.renderer_mark.str() + ": renderer: this renderer has no vector output: write '" +
                         out + "' as .png, .exr or .tif instead");
    return vector;
}

} // namespace fp::host
