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

#include <string>
#include <vector>

namespace fp::host {

/// One entry of the changelog: what changed the bytes of renders at `version`.
struct RenderChange {
    int version = 0;
    std::string date;
    /// The renders it changed are those using all of these plugins; empty: every render.
    std::vector<std::string> plugins;
    std::string what;
};

/// The changelog, oldest first (framework/render-versions.yaml as built in). Version 1 has no
/// change: it is what every recipe without `render_version` was made by.
const std::vector<RenderChange>& render_changes();

/// The version this build renders: the changelog's last.
int render_version();

/// "0.1.0 (render version 2)": what a checkpoint records of the fixpoint that wrote it.
std::string render_version_tag();

/// The changes after version `since`, up to this build's, that touch a render using
/// `plugins` (by name): those whose plugins it all uses.
std::vector<RenderChange> changes_since(int since, const std::vector<std::string>& plugins);

/// What a recipe of version `since` using `plugins` is told: empty when it renders its old
/// bytes, else one line ("the recipe is of render version 1, this fixpoint renders version 2:
/// ...; the image may differ").
std::string render_version_difference(int since, const std::vector<std::string>& plugins);

} // namespace fp::host
