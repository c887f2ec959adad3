// The render version: an image's bytes are a function of its recipe and of this number.
//
// Every change that changes the bytes of any render bumps it, with a line in the changelog
// framework/render-versions.yaml (built into the host; docs/render-versions.md says how to
// bump it). Recipes record it (`render_version: N`), and so do checkpoints (their header's
// version and their identity, which is the recipe). A recipe of an older version renders
// silently when no change since names a plugin it uses (its bytes are the old ones), else with
// a warning that names the changes; with --strict it is refused. The golden corpus
// (tests/golden-recipes/) fails the build when bytes change while the version stays.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fp::host {

/// One entry of the changelog: what changed the bytes of renders at `version`.
struct RenderChange {
    int version = 0;
    std::string date;
    /// The renders it changed are those using all of these plugins; empty: every render.
    std::vector<std::string> plugins;
    /// And, of those, the renders whose recipe has each of these parameters (a dotted path:
    /// "renderer.sets") at one of its values; nullopt among them: the parameter left out.
    /// Empty: every render of the plugins. (A change of a default touches only the recipes
    /// that leave the parameter out.)
    std::vector<std::pair<std::string, std::vector<std::optional<std::string>>>> params;
    std::string what;
};

/// A recipe's parameter by its dotted path ("renderer.sets"): its scalar's text, "" for a
/// list or map, nullopt where the recipe leaves it out.
using RecipeParams = std::function<std::optional<std::string>(const std::string& path)>;

struct CNode;
/// The parameters of the recipe `root` (kept alive by the caller) as RecipeParams read them.
RecipeParams params_of(const CNode& root);

/// The changelog, oldest first (framework/render-versions.yaml as built in). Version 1 has no
/// change: it is what every recipe without `render_version` was made by.
const std::vector<RenderChange>& render_changes();

/// The version this build renders: the changelog's last.
int render_version();

/// "0.1.0 (render version 2)": what a checkpoint records of the fixpoint that wrote it.
std::string render_version_tag();

/// The changes after version `since`, up to this build's, that touch a render using
/// `plugins` (by name): those whose plugins it all uses and whose parameters its recipe has
/// (`params`; without it, a change that names parameters touches every render of its plugins).
std::vector<RenderChange> changes_since(int since, const std::vector<std::string>& plugins,
                                        const RecipeParams& params = {});

/// What a recipe of version `since` using `plugins` is told: empty when it renders its old
/// bytes, else one line ("the recipe is of render version 1, this fixpoint renders version 2:
/// ...; the image may differ").
std::string render_version_difference(int since, const std::vector<std::string>& plugins,
                                      const RecipeParams& params = {});

} // namespace fp::host
