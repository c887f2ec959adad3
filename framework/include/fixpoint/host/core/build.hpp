// Stages 2 and 3 of loading a pipeline: validate a CNode tree against the plugins' schemas
// (types, ranges, finiteness, unknown and missing keys, kinds of slots), giving a typed tree
// with every default filled in; then build the objects bottom-up.
#pragma once

#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/registry.hpp>

#include <memory>
#include <string>
#include <vector>

namespace fp::host {

struct TObject;

/// A validated parameter.
struct TParam {
    const ParamSpec* spec = nullptr;
    Mark mark;                       ///< where its value stands (or the owning mapping, for defaults)
    std::string path;                ///< e.g. renderer.maps[2].shape.radius
    ParamValue value;                ///< plain values
    std::unique_ptr<TObject> object; ///< Object
    struct Item {
        std::unique_ptr<TObject> object;
        std::vector<TParam> extras;
    };
    std::vector<Item> items; ///< Objects
};

/// A validated plugin instance.
struct TObject {
    const PluginEntry* plugin = nullptr;
    Mark mark;
    std::string path;
    std::vector<TParam> params;
};

/// Validate `node` as an instance of `kind` at `path`. Throws fp::InputError
/// "file:line:col: path: message".
/// `extra_keys` are keys beside the object's own that the slot reads (an item's `weight`).
std::unique_ptr<TObject> validate(const Registry& reg, Kind kind, const CNode& node, const std::string& path,
                                  const std::vector<std::string>& extra_keys = {});

/// Build the objects of a validated tree. Plugin errors are given the position of the
/// parameter they name.
std::shared_ptr<const Object> build(const Registry& reg, const TObject& t);

/// An instance of `kind` from YAML text given outside a config (a command-line argument, a
/// Python string): parsed as `source` (its name in error positions, "<transform>"), validated
/// at `path` and built. Throws fp::InputError.
std::shared_ptr<const Object> build_from_text(const Registry& reg, Kind kind, const std::string& text,
                                              const std::string& source, const std::string& path);

/// One of the values a file parameter (ParamRole::file) declares as built in rather than a
/// file (superfractal's picture: "hues").
bool is_builtin_file(const ParamSpec& s, const std::string& value);

/// The file a file parameter's `value` names, written at `at`: a relative path written in a
/// config file is taken from that file's folder (a config and the script or picture beside it
/// move together, and render the same from any working folder); one given on the command line
/// (--set, --vary), in a text that is no file (a Python string, a page's unsaved text), in the
/// recipe of an image or a histogram file (as recipes were always read), or absolute stands as
/// it is, from the working folder. The result is from the working folder
/// where the file lies inside it, and the plugin gets it so (its messages name the file so); the recipe
/// records it absolute (resolved): a recipe rendered again from its image, anywhere, reads the
/// same file.
std::string file_from_config(const std::string& value, const Mark& at);

/// The tree with every default filled in, as YAML nodes (canonical numbers: shortest text
/// that reads back to the same double).
/// without_finish: leaves out the parameters whose role is finish (ParamRole::finish), at every
/// depth: what a kept histogram depends on (Pipeline::histogram_identity).
CNode resolved(const TObject& t, bool without_finish = false);

/// Shortest decimal text that reads back as exactly `v`.
std::string format_real(double v);
std::string format_float(float v);

/// A parameter's declared range as interval text, "[0, 1)" or "(0, inf)"; "(-inf, inf)" when
/// it has none.
std::string declared_range(const ParamSpec& s);

} // namespace fp::host
