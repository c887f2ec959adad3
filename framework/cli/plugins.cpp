// The plugin family: plugins (the list, or every file with --check), describe (one plugin's
// parameters), conformance (the suite run on plugins).
#include "cli.hpp"

#include <fixpoint/host/conformance/conformance.hpp>
#include <fixpoint/host/tools/describe.hpp>
#include <fixpoint/text.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

using namespace fp::host;

namespace fp::cli {

namespace {

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
        // (finishing: `fixpoint tone` may change it on a kept histogram, docs/histograms.md.)
        std::printf("%s%-16s %s; %s%s%s%s\n", indent.c_str(), s.name, type.c_str(), def.c_str(),
                    range.empty() ? "" : "; range ", range.c_str(),
                    s.role == ParamRole::finish ? "; finishing" : "");
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
    if (o.markdown) { // the reference of docs/plugins.md (host/tools/describe.hpp)
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

int cmd_conformance(const Options& o) {
    Registry reg = make_registry(o);
    std::vector<const PluginEntry*> targets;
    // A plugin file (a path, or a name ending in .so), or the name of a plugin found in the
    // plugin folders (an unknown one gets the "did you mean" of describe).
    for (const auto& f : o.files) {
        if (f.find('/') == std::string::npos && !f.ends_with(".so")) {
            targets.push_back(&reg.get(f));
        } else {
            const auto all = reg.of_file(reg.load_file(f)); // a family file: each of its plugins
            targets.insert(targets.end(), all.begin(), all.end());
        }
    }
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

void add_plugin_commands(CLI::App& app, Options& o, std::vector<Command>& table) {
    auto* plugins = app.add_subcommand("plugins", "List the plugins found");
    plugins->add_option("--kind", o.kind, "Only this kind (shape, transform, iteration-scheme, ...)");
    plugins->add_flag("--check", o.check,
                      "List every plugin file with its plugin or why it was refused (exit 1 if any was)");
    table.push_back({plugins, [&o] { return cmd_plugins(o); }});

    auto* describe = app.add_subcommand("describe", "Show a plugin's parameters");
    describe->add_option("name", o.name, "Plugin name (with --markdown: every plugin when none)");
    describe->add_flag("--markdown", o.markdown, "Markdown, as docs/plugins.md is");
    table.push_back({describe, [&o] { return cmd_describe(o); }});

    auto* conformance = app.add_subcommand("conformance", "Run the plugin conformance suite");
    conformance->add_option("files", o.files, "Plugin files or names (default: every plugin found)");
    conformance->add_flag("-v,--verbose", o.verbose, "List every check run and its result");
    conformance->add_option("--example", o.example,
                            "Parameters to check the plugin with instead of its own example (a YAML mapping, "
                            "as '{file: my_scheme.py}' for a python-scheme)");
    table.push_back({conformance, [&o] { return cmd_conformance(o); }});
}

} // namespace fp::cli
