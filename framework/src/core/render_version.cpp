// The render versions' changelog, built in (render_version.hpp).
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/render_version.hpp>
#include <fixpoint/version.hpp>

#include <yaml-cpp/yaml.h>

#include <algorithm>

extern const char fixpoint_render_versions_yaml[]; // cmake/embed_text.cmake

namespace fp::host {

namespace {

/// The changelog read once. Its shape is checked here and by the unit tests: a build with a
/// malformed log fails its first test, never a user's render.
std::vector<RenderChange> read_changes() {
    const YAML::Node root = YAML::Load(fixpoint_render_versions_yaml);
    const YAML::Node versions = root["versions"];
    if (!versions.IsSequence() || versions.size() == 0)
        throw InternalError("render-versions.yaml: expected a list 'versions'");
    std::vector<RenderChange> out;
    int expect = 1;
    for (const auto& v : versions) {
        const int n = v["version"].as<int>();
        if (n != expect)
            throw InternalError("render-versions.yaml: version " + std::to_string(n) + " where " +
                                std::to_string(expect) + " comes next");
        const std::string date = v["date"].as<std::string>();
        if (n == 1) {
            out.push_back({1, date, {}, {}, v["what"].as<std::string>()});
        } else {
            const YAML::Node changes = v["changes"];
            if (!changes.IsSequence() || changes.size() == 0)
                throw InternalError("render-versions.yaml: version " + std::to_string(n) +
                                    " names no change");
            for (const auto& c : changes) {
                RenderChange rc{n, date, {}, {}, c["what"].as<std::string>()};
                if (c["plugins"]) rc.plugins = c["plugins"].as<std::vector<std::string>>();
                if (const YAML::Node ps = c["params"]) {
                    if (!ps.IsMap())
                        throw InternalError("render-versions.yaml: version " + std::to_string(n) +
                                            ": params must map a parameter's path to its values");
                    for (const auto& kv : ps) {
                        if (!kv.second.IsSequence() || kv.second.size() == 0)
                            throw InternalError("render-versions.yaml: version " + std::to_string(n) + ": " +
                                                kv.first.as<std::string>() + " names no value");
                        std::vector<std::optional<std::string>> values;
                        for (const auto& v : kv.second)
                            values.push_back(v.IsNull() ? std::nullopt
                                                        : std::optional<std::string>(v.as<std::string>()));
                        rc.params.emplace_back(kv.first.as<std::string>(), std::move(values));
                    }
                }
                out.push_back(std::move(rc));
            }
        }
        ++expect;
    }
    return out;
}

} // namespace

const std::vector<RenderChange>& render_changes() {
    static const std::vector<RenderChange> changes = read_changes();
    return changes;
}

int render_version() { return render_changes().back().version; }

std::string render_version_tag() {
    return std::string(FIXPOINT_VERSION) + " (render version " + std::to_string(render_version()) + ")";
}

RecipeParams params_of(const CNode& root) {
    return [&root](const std::string& path) -> std::optional<std::string> {
        const CNode* n = &root;
        for (std::size_t from = 0; n && from <= path.size();) {
            const std::size_t dot = std::min(path.find('.', from), path.size());
            n = n->is_map() ? n->find(path.substr(from, dot - from)) : nullptr;
            from = dot + 1;
        }
        if (!n || n->type == CNode::Type::Null) return std::nullopt;
        return n->is_scalar() ? n->scalar : std::string();
    };
}

std::vector<RenderChange> changes_since(int since, const std::vector<std::string>& plugins,
                                        const RecipeParams& params) {
    std::vector<RenderChange> out;
    for (const auto& c : render_changes()) {
        if (c.version <= since) continue;
        // (A render using all of the change's plugins: e.g. chaos-game and inversion for a change
        // of the draw under paper 01's rules, which only maps with sets turn on.)
        const bool touches = std::all_of(c.plugins.begin(), c.plugins.end(), [&](const auto& n) {
            return std::find(plugins.begin(), plugins.end(), n) != plugins.end();
        });
        // (And whose recipe has the change's parameters: a changed default touches only the
        // recipes that leave it out.)
        const bool has = !params || std::all_of(c.params.begin(), c.params.end(), [&](const auto& pv) {
            return std::find(pv.second.begin(), pv.second.end(), params(pv.first)) != pv.second.end();
        });
        if (touches && has) out.push_back(c);
    }
    return out;
}

std::string render_version_difference(int since, const std::vector<std::string>& plugins,
                                      const RecipeParams& params) {
    const int now = render_version();
    if (since > now)
        return "the recipe is of render version " + std::to_string(since) + ", newer than this fixpoint's " +
               std::to_string(now) + ": the image may differ";
    const auto changes = changes_since(since, plugins, params);
    if (changes.empty()) return "";
    std::string what;
    for (const auto& c : changes)
        what += (what.empty() ? "" : "; ") + c.what + " (" + std::to_string(c.version) + ")";
    return "the recipe is of render version " + std::to_string(since) + ", this fixpoint renders version " +
           std::to_string(now) + ": " + what + "; the image may differ (docs/render-versions.md)";
}

} // namespace fp::host
