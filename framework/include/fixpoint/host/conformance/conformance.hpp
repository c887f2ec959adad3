// The plugin conformance suite: properties every plugin must have, run by
// `fixpoint conformance` and by CTest on every plugin of plugins/.
//
// For every plugin: metadata complete; builds from its example (defaults fill the rest);
// wrong type, out-of-range, NaN and unknown parameters refused with a parameter error;
// batch evaluation equals point-by-point evaluation; const evaluation from two threads at
// once gives the same result. Per kind: a Shape's inside test agrees with its boundary; a
// Metric obeys the metric axioms; a Transform gives finite output for finite input in its
// sample domain and an involution is one; a Renderer gives the same image on 1 and 2 threads;
// an IterationScheme, on both precisions, many step indices, with and without a mask, with
// parameters drawn from their ranges: finite, free of state between calls, float close to
// double, the same when several threads step at once, and is_picard() exact.
#pragma once

#include <fixpoint/host/core/registry.hpp>

#include <string>
#include <vector>

namespace fp::host {

/// One check and whether it passed (`fixpoint conformance --verbose` lists them).
struct CheckResult {
    std::string name;
    bool passed = true;
};

struct ConformanceReport {
    std::vector<std::string> findings; ///< the failures (empty: conformant)
    std::vector<CheckResult> checks;   ///< every check run, in order
};

/// Run every check on one plugin, with the list of checks run. `example` (a YAML mapping of
/// parameters) replaces the plugin's own example when given: a python-scheme is checked with
/// the user's file.
ConformanceReport conformance_report(const Registry& reg, const PluginEntry& plugin,
                                     const std::string* example = nullptr);

/// Run every check on one plugin; returns the failures (empty: conformant).
std::vector<std::string> run_conformance(const Registry& reg, const PluginEntry& plugin);

/// The kind-specific checks on an object already built (also usable on objects made in
/// tests without a plugin file).
std::vector<std::string> check_object(const Object& obj, Kind kind);

} // namespace fp::host
