// Every parameter of a config, with its place in the config and its declaration: the data
// `fixpoint serve`'s page builds its parameter panel from (sliders for ranged numbers, colour
// pickers, a choice of plugin for each slot, a list editor for `maps`), in the order of the
// config's tree.
#pragma once

#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/registry.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace fp::host {

struct ParamEntry {
    std::string path;  ///< as --set takes it: "renderer.maps[0].shape.radius"
    std::string name;  ///< "radius"; for a list's item, "maps[0]"
    std::string owner; ///< the plugin that declares it ("circle"; "chaos-game" for the renderer's)
    /// bool, int, real, string, choice (a string of `choices`), colour, point, reals, points,
    /// sequence, plugin (an object slot: `choices` are the plugins of `plugin_kind`), list (a
    /// list of plugins: `count` items, each item's parameters follow as their own entries).
    std::string kind;
    std::string value;              ///< the value in the config, flow YAML on one line; else the default
    bool written = false;           ///< the config writes it (else `value` is the default, or empty)
    bool required = false;          ///< declared without a default
    std::string default_value;      ///< flow YAML; empty when none
    std::optional<double> min, max; ///< the declared range of a number (or of each element)
    bool min_open = false, max_open = false;
    std::vector<std::string> choices;
    std::string plugin_kind; ///< plugin, list: "shape", "iteration-scheme", "transform", ...
    std::string description; ///< the declaration's text
    int depth = 0;           ///< nesting: 0 for the renderer's own parameters
    std::size_t count = 0;   ///< list: items
};

/// The parameters of `root` (a config, not yet validated: an unknown plugin's slot is listed
/// without its parameters; a value of the wrong type is listed as written). The first entry is
/// the renderer's slot (path "renderer", kind plugin, plugin_kind "renderer", value its type);
/// an object slot's entry (path "renderer.iteration", value "mann") comes before the
/// parameters of the plugin in it, and changing the slot is edit_set(path, "{type: NAME}").
std::vector<ParamEntry> list_params(const Registry& reg, const CNode& root);

} // namespace fp::host
