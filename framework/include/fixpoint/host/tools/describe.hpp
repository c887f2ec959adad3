// The plugin reference in Markdown, written from the plugins' own descriptors
// (`fixpoint describe --markdown`). docs/plugins.md is its output, checked in and compared
// with a fresh one by CTest (plugin_reference), so the reference cannot drift from the code.
#pragma once

#include <fixpoint/host/core/registry.hpp>

#include <string>

namespace fp::host {

/// One plugin as a Markdown section: a heading of `level` (1 to 6) with its name, then its
/// kind, version, summary, whether it runs code, its example and a table of its parameters
/// (type, default, range or choices, doc; the extra keys of a list's items in a table of their
/// own). Nothing in it depends on where the plugin's file lies.
std::string markdown_plugin(const PluginEntry& e, int level);

/// Every plugin of `reg`, grouped by kind in the SDK's order of kinds and by name within a
/// kind, under a title and an index: the whole reference.
std::string markdown_reference(const Registry& reg);

} // namespace fp::host
