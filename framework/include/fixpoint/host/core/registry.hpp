// Plugin discovery and loading (Boost.DLL).
#pragma once

#include <fixpoint/plugin.hpp>
#include <fixpoint/text.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace boost::dll {
class shared_library;
}

namespace fp::host {

struct PluginEntry {
    const PluginDescriptor* desc = nullptr;
    std::filesystem::path file;
    std::shared_ptr<boost::dll::shared_library> lib;
};

/// A file in a plugin folder that did not load: skipped (one bad file must not block every
/// command), reported by the caller, and named by the error when a config asks for a plugin
/// that file would have provided.
struct RefusedPlugin {
    std::filesystem::path file;
    std::string reason; ///< the whole message, naming the file
    std::string name;   ///< the plugin's name when it could be read (a duplicate), else empty
};

class Registry {
public:
    Registry() = default;
    ~Registry();
    Registry(Registry&&) noexcept;
    Registry& operator=(Registry&&) noexcept;

    /// The default folders: the build's or install's plugin folder (found from the running
    /// executable), then every folder of FIXPOINT_PLUGIN_PATH.
    static std::vector<std::filesystem::path> default_dirs();

    /// Load every `*.so` in `dir` (a missing folder is skipped). A file that fails to load is
    /// skipped and listed in refused(); a folder that cannot be read throws fp::InputError.
    void load_dir(const std::filesystem::path& dir);
    /// Load one plugin file. Throws fp::InputError naming the file for a file that is not a
    /// plugin, a mismatched ABI, or a name taken by another file.
    const PluginEntry& load_file(const std::filesystem::path& file);

    /// Every plugin of the file `e` came from, in the file's order (a family library holds
    /// many: FIXPOINT_PLUGIN_FAMILY).
    std::vector<const PluginEntry*> of_file(const PluginEntry& e) const;

    const PluginEntry* find(std::string_view name) const;
    /// The plugin `name` for a command that names one (describe): throws fp::InputError
    /// "unknown plugin 'X' (did you mean 'Y'?)", or "plugin 'X' is not available: REASON" when
    /// a refused file would have provided it.
    const PluginEntry& get(const std::string& name) const;
    /// The files of the folders that did not load, in the order met.
    const std::vector<RefusedPlugin>& refused() const { return refused_; }
    /// The refused file that would have provided plugin `name`: one that declared that name
    /// (a second plugin of a name already loaded), or, when no plugin has the name, one whose
    /// file is named after it (`name.so`: the descriptor of a file that did not load is not
    /// read). Null when none.
    const RefusedPlugin* refused_for(std::string_view name) const;
    /// All plugins, sorted by kind then name; only those of `kind` when given.
    std::vector<const PluginEntry*> all(std::optional<Kind> kind = std::nullopt) const;
    /// Closest names to `name` (for "did you mean").
    std::vector<std::string> closest(std::string_view name, std::optional<Kind> kind) const;

    /// Construct an instance; the returned handle keeps the plugin's library loaded.
    std::shared_ptr<const Object> create(const PluginEntry& e, const ParamBag& bag) const;

private:
    std::vector<std::unique_ptr<PluginEntry>> entries_;
    std::vector<RefusedPlugin> refused_;
    /// load_file's work; `name` gets the plugin's name as soon as its descriptor is read, so
    /// that a refusal after that point (a duplicate, a name not in kebab-case) can record it.
    const PluginEntry& load(const std::filesystem::path& file, std::string& name);
};

/// (fixpoint/text.hpp's, shared with the plugins.)
using ::fp::edit_distance;
using ::fp::suggest;

} // namespace fp::host
