#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/tools/describe.hpp>

#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fp::host {
namespace {

// Headings for the kinds, in the SDK's order of Kind (types.hpp); the command line's names
// (kind_name) go beside them.
constexpr std::string_view kind_titles[kind_count] = {
    "Shapes",  "Transforms", "Iteration schemes", "Number systems", "Traps",
    "Metrics", "Colourers",  "Renderers",         "Filters",
};

// Text in a table cell: a '|' would end the cell (GitHub reads "\|" as a pipe, in code spans
// too) and a line break the row. Descriptors are plain one-line text; nothing else is escaped
// so that the file reads as well raw as rendered.
std::string cell(std::string_view s) {
    std::string r;
    for (char c : s) {
        if (c == '|')
            r += "\\|";
        else if (c == '\n' || c == '\r')
            r += ' ';
        else
            r += c;
    }
    return r;
}

std::string code(std::string_view s) { return "`" + cell(s) + "`"; }

std::string type_of(const ParamSpec& s) {
    std::string t(param_type_name(s.type));
    if (s.type == ParamType::Object || s.type == ParamType::Objects)
        t += " (" + std::string(kind_name(s.kind)) + ")";
    if (s.count)
        t += ", exactly " + std::to_string(s.count);
    else if (s.min_count)
        t += ", at least " + std::to_string(s.min_count);
    return t;
}

std::string default_of(const ParamSpec& s) {
    if (s.default_yaml) return code(s.default_yaml);
    return s.optional ? "optional" : "**required**";
}

// The range (of each element, for a list) or the choices of a string.
std::string range_of(const ParamSpec& s) {
    if (s.choices) {
        std::string r;
        std::string_view c(s.choices);
        for (std::size_t at = 0;;) {
            const auto bar = c.find('|', at);
            if (!r.empty()) r += ", ";
            r += code(c.substr(at, bar == std::string_view::npos ? bar : bar - at));
            if (bar == std::string_view::npos) break;
            at = bar + 1;
        }
        return "one of " + r;
    }
    if (std::isfinite(s.lo) || std::isfinite(s.hi)) return declared_range(s);
    return "";
}

void table(std::string& out, const ParamSpec* ps, std::size_t n) {
    out += "| parameter | type | default | range | what it is |\n|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < n; ++i) {
        const ParamSpec& s = ps[i];
        out += "| " + code(s.name) + " | " + type_of(s) + " | " + default_of(s) + " | " + range_of(s) +
               " | " + cell(s.doc ? s.doc : "") +
               (s.role == ParamRole::finish ? " *(finishing: `fixpoint tone` may change it)*" : "") + " |\n";
    }
}

// The parameters' table, then one for the extra keys of each list's items (a chaos game's
// `maps` take `weight` and `colour` beside their own), depth first, named by their path.
void tables(std::string& out, const ParamSpec* ps, std::size_t n, const std::string& path) {
    table(out, ps, n);
    for (std::size_t i = 0; i < n; ++i) {
        const ParamSpec& s = ps[i];
        if (s.type != ParamType::Objects || !s.n_item_params) continue;
        const std::string item = path + s.name + "[]";
        out += "\nEach item of " + code(path + s.name) + " also takes:\n\n";
        tables(out, s.item_params, s.n_item_params, item + ".");
    }
}

} // namespace

std::string markdown_plugin(const PluginEntry& e, int level) {
    const PluginDescriptor& d = *e.desc;
    std::string out(std::size_t(level < 1 ? 1 : level > 6 ? 6 : level), '#');
    out += " `" + std::string(d.name) + "`\n\n";
    out += std::string(kind_name(d.kind)) + ", version " + d.version + ": " + (d.summary ? d.summary : "") +
           "\n";
    if (d.runs_code)
        out += "\n**Runs the code its parameters carry**: refused in a recipe read from an image unless "
               "`--allow-python`, and by `serve` unless started with it.\n";
    if (d.example && std::string_view(d.example) != "{}")
        out += "\nExample: `" + std::string(d.example) + "`\n";
    out += "\n";
    if (d.n_params)
        tables(out, d.params, d.n_params, "");
    else
        out += "No parameters.\n";
    return out;
}

std::string markdown_reference(const Registry& reg) {
    std::string out =
        "# Plugin reference\n\n"
        "<!-- Generated from the plugins' descriptors by `fixpoint describe --markdown`; do not "
        "edit.\n"
        "     Refresh: build/bin/fixpoint describe --markdown > docs/plugins.md -->\n\n"
        "Every plugin of this build with the parameters it declares: type, default, range "
        "(of each element, for a list) or choices, and what it is. A parameter without a "
        "default is required unless it says optional. `fixpoint describe NAME` prints one "
        "plugin in the terminal.\n\n";
    std::vector<std::pair<Kind, std::vector<const PluginEntry*>>> kinds;
    for (int k = 0; k < kind_count; ++k) {
        auto all = reg.all(Kind(k));
        if (!all.empty()) kinds.emplace_back(Kind(k), std::move(all));
    }
    for (const auto& [kind, entries] : kinds) {
        out += "- **" + std::string(kind_titles[int(kind)]) + "** (`" + std::string(kind_name(kind)) + "`):";
        const char* sep = " ";
        for (const auto* e : entries) {
            out += sep + std::string("[`") + e->desc->name + "`](#" + e->desc->name + ")";
            sep = ", ";
        }
        out += "\n";
    }
    for (const auto& [kind, entries] : kinds) {
        out += "\n## " + std::string(kind_titles[int(kind)]) + "\n";
        // The schemes go by their authors' names in the literature (khan is the Picard-Mann
        // hybrid): a table of which is which, from each description's words before its colon.
        if (kind == Kind::IterationScheme) {
            out += "\n| scheme | what it is |\n|---|---|\n";
            for (const auto* e : entries) {
                const std::string d = e->desc->summary ? e->desc->summary : "";
                out += "| [`" + std::string(e->desc->name) + "`](#" + e->desc->name + ") | " +
                       d.substr(0, d.find(": ")) + " |\n";
            }
        }
        for (const auto* e : entries) out += "\n" + markdown_plugin(*e, 3);
    }
    return out;
}

} // namespace fp::host
