// The render versions' changelog, built in (render_version.hpp).
#include <fixpoint/errors.hpp>
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
            out.push_back({1, date, {}, v["what"].as<std::string>()});
        } else {
            const YAML::Node changes = v["changes"];
            if (!changes.IsSequence() || changes.size() == 0)
                throw InternalError("render-versions.yaml: version " + std::to_string(n) +
                                    " names no change");
            for (const auto& c : changes) {
                RenderChange rc{n, date, {}, c["what"].as<std::string>()};
                if (c["plugins"]) rc.plugins = c["plugins"].as<std::vector<std::string>>();
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

std::vector<RenderChange> changes_since(int since, const std::vector<std::string>& plugins) {
    std::vector<RenderChange> out;
    for (const auto& c : render_changes()) {
        if (c.version <= since) continue;
        // (A render using all of the change's plugins: e.g. chaos-game and inversion for a change
        // of the draw under paper 01's rules, which only maps with sets turn on.)
        const bool touches = std::all_of(c.plugins.begin(), c.plugins.end(), [&](const auto& n) {
            return std::find(plugins.begin(), plugins.end(), n) != plugins.end();
        });
        if (touches) out.push_back(c);
    }
    return out;
}

std::string render_version_difference(int since, const std::vector<std::string>& plugins) {
    const int now = render_version();
    if (since > now)
        return "the recipe is of render version " + std::to_string(since) + ", newer than this fixpoint's " +
               std::to_string(now) + ": the image may differ";
    const auto changes = changes_since(since, plugins);
    if (changes.empty()) return "";
    std::string what;
    for (const auto& c : changes)
        what += (what.empty() ? "" : "; ") + c.what + " (" + std::to_string(c.version) + ")";
    return "the recipe is of render version " + std::to_string(since) + ", this fixpoint renders version " +
           std::to_string(now) + ": " + what + "; the image may differ (docs/render-versions.md)";
}

} // namespace fp::host
