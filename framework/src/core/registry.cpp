// Plugin registry: discovery, ABI check, duplicate names, lifetime.
#include <fixpoint/host/core/registry.hpp>
#include <fixpoint/text.hpp>

#include <boost/dll/shared_library.hpp>

#include <algorithm>
#include <cstdlib>
#include <unistd.h>

namespace fs = std::filesystem;

namespace fp::host {

Registry::~Registry() = default;
Registry::Registry(Registry&&) noexcept = default;
Registry& Registry::operator=(Registry&&) noexcept = default;

std::vector<fs::path> Registry::default_dirs() {
    std::vector<fs::path> dirs;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) dirs.push_back(exe.parent_path() / FIXPOINT_PLUGIN_REL_DIR);
    if (const char* env = std::getenv("FIXPOINT_PLUGIN_PATH")) {
        std::string s = env;
        std::size_t start = 0;
        while (start <= s.size()) {
            const auto colon = s.find(':', start);
            const std::string part =
                s.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
            if (!part.empty()) {
                // A folder the user named that is not there is a mistake to report, not to skip.
                std::error_code ec2;
                if (!fs::is_directory(part, ec2))
                    throw InputError("FIXPOINT_PLUGIN_PATH: " + quote(part, 200) + " is not a folder" +
                                     (ec2 ? " (" + ec2.message() + ")" : ""));
                dirs.emplace_back(part);
            }
            if (colon == std::string::npos) break;
            start = colon + 1;
        }
    }
    return dirs;
}

void Registry::load_dir(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return;
    const auto unreadable = [&dir](const std::error_code& e) {
        return InputError("cannot read plugin folder " + quote(dir.string(), 200) + ": " + e.message());
    };
    std::vector<fs::path> files;
    fs::directory_iterator it(dir, ec);
    if (ec) throw unreadable(ec);
    for (; it != fs::directory_iterator(); it.increment(ec)) {
        if (ec) throw unreadable(ec);
        if (it->path().extension() == ".so") files.push_back(it->path());
    }
    if (ec) throw unreadable(ec);
    std::sort(files.begin(), files.end()); // a fixed order: messages do not depend on the file system
    for (const auto& f : files) {
        // Follows links: a link loop or a dangling link named .so is refused like a bad file;
        // anything else that is not a regular file (a folder named x.so) is not a candidate.
        std::error_code ec2;
        const bool regular = fs::is_regular_file(f, ec2);
        if (ec2) {
            refused_.push_back(
                {f, "cannot load plugin " + quote(f.string(), 200) + ": " + ec2.message(), ""});
            continue;
        }
        if (!regular) continue;
        std::string name;
        try {
            load(f, name);
        } catch (const InputError& e) {
            refused_.push_back({f, e.what(), name});
        }
    }
}

const PluginEntry& Registry::get(const std::string& name) const {
    const PluginEntry* e = find(name);
    if (const auto* r = refused_for(name))
        throw InputError("plugin " + quote(name) + " is not available: " + r->reason);
    if (e) return *e;
    const auto near = closest(name, std::nullopt);
    throw InputError("unknown plugin " + quote(name) +
                     (near.empty() ? "" : " (did you mean '" + near[0] + "'?)"));
}

const RefusedPlugin* Registry::refused_for(std::string_view name) const {
    for (const auto& r : refused_)
        if (r.name == name) return &r;
    if (find(name)) return nullptr;
    for (const auto& r : refused_)
        if (r.name.empty() && r.file.stem() == name) return &r;
    return nullptr;
}

// Boost.DLL 1.74 wraps dlerror() as "boost::dll::shared_library::load() failed (dlerror system
// message: FILE: REASON): Bad file descriptor", the last part a stale errno: keep REASON.
static std::string dlopen_reason(const std::string& what, const std::string& file) {
    const std::string open = "(dlerror system message: ";
    const auto a = what.find(open), b = what.rfind(')');
    if (a == std::string::npos || b == std::string::npos || b < a) return excerpt(what, 200);
    std::string r = what.substr(a + open.size(), b - a - open.size());
    if (r.rfind(file + ": ", 0) == 0) r.erase(0, file.size() + 2);
    return excerpt(r, 200);
}

static bool kebab(const char* s) {
    if (!s || !*s || *s == '-') return false;
    for (const char* c = s; *c; ++c)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '-')) return false;
    return s[std::char_traits<char>::length(s) - 1] != '-';
}

const PluginEntry& Registry::load_file(const fs::path& file) {
    std::string name;
    return load(file, name);
}

const PluginEntry& Registry::load(const fs::path& file, std::string& name) {
    std::error_code ec;
    const fs::path canon = fs::weakly_canonical(file, ec);
    const fs::path path = ec ? file : canon;
    for (const auto& e : entries_)
        if (e->file == path) return *e; // the same file reached twice (overlapping folders)

    const std::string f = path.string();
    auto lib = std::make_shared<boost::dll::shared_library>();
    try {
        // Local binding: with global binding one plugin's helpers silently replace another's.
        lib->load(path, boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local);
    } catch (const std::exception& e) {
        throw InputError("cannot load plugin '" + f + "': " + dlopen_reason(e.what(), f));
    }
    const bool family = lib->has("fixpoint_family");
    if (!lib->has("fixpoint_abi") || !(family || lib->has("fixpoint_descriptor")))
        throw InputError("'" + f +
                         "' is not a fixpoint plugin (it exports no fixpoint_abi/fixpoint_descriptor)");
    const std::uint32_t abi = lib->get_alias<const std::uint32_t>("fixpoint_abi");
    if (abi != abi_version)
        throw InputError("plugin '" + f + "' was built for plugin ABI " + std::to_string(abi) +
                         ", this fixpoint needs ABI " + std::to_string(abi_version) +
                         ": rebuild it against this SDK");
    // One descriptor, or a family's (FIXPOINT_PLUGIN_FAMILY): every one checked before any is
    // added, so that a library loads whole or not at all.
    std::vector<const PluginDescriptor*> descs;
    if (family) {
        const auto& fam = lib->get_alias<const PluginFamily>("fixpoint_family");
        if (!fam.descriptors || fam.n == 0) throw InputError("plugin '" + f + "' has a malformed descriptor");
        for (std::uint32_t i = 0; i < fam.n; ++i) descs.push_back(&fam.descriptors[i]);
    } else {
        descs.push_back(&lib->get_alias<const PluginDescriptor>("fixpoint_descriptor"));
    }
    for (std::size_t i = 0; i < descs.size(); ++i) {
        const PluginDescriptor& d = *descs[i];
        if (d.abi != abi_version || !d.create || !d.summary || (!d.params && d.n_params) ||
            unsigned(d.kind) >= unsigned(kind_count))
            throw InputError("plugin '" + f + "' has a malformed descriptor");
        name = d.name ? d.name : "";
        if (!kebab(d.name))
            throw InputError("plugin '" + f + "' has name '" + std::string(d.name ? d.name : "") +
                             "', which is not kebab-case");
        if (const PluginEntry* other = find(d.name))
            throw InputError("two plugins named '" + std::string(d.name) + "': '" + other->file.string() +
                             "' and '" + f + "'");
        for (std::size_t j = 0; j < i; ++j)
            if (std::string_view(descs[j]->name) == d.name)
                throw InputError("two plugins named '" + std::string(d.name) + "' in '" + f + "'");
    }
    const std::size_t first = entries_.size();
    for (const PluginDescriptor* d : descs) {
        auto entry = std::make_unique<PluginEntry>();
        entry->desc = d;
        entry->file = path;
        entry->lib = lib;
        entries_.push_back(std::move(entry));
    }
    return *entries_[first];
}

std::vector<const PluginEntry*> Registry::of_file(const PluginEntry& e) const {
    std::vector<const PluginEntry*> out;
    for (const auto& x : entries_)
        if (x->file == e.file) out.push_back(x.get());
    return out;
}

const PluginEntry* Registry::find(std::string_view name) const {
    for (const auto& e : entries_)
        if (name == e->desc->name) return e.get();
    return nullptr;
}

std::vector<const PluginEntry*> Registry::all(std::optional<Kind> kind) const {
    std::vector<const PluginEntry*> out;
    for (const auto& e : entries_)
        if (!kind || e->desc->kind == *kind) out.push_back(e.get());
    std::sort(out.begin(), out.end(), [](const PluginEntry* a, const PluginEntry* b) {
        if (a->desc->kind != b->desc->kind) return a->desc->kind < b->desc->kind;
        return std::string_view(a->desc->name) < std::string_view(b->desc->name);
    });
    return out;
}

std::vector<std::string> Registry::closest(std::string_view name, std::optional<Kind> kind) const {
    std::vector<std::string> names;
    for (const auto* e : all(kind)) names.emplace_back(e->desc->name);
    return suggest(name, names);
}

std::shared_ptr<const Object> Registry::create(const PluginEntry& e, const ParamBag& bag) const {
    Object* raw = e.desc->create(bag);
    if (!raw) throw InternalError("plugin '" + std::string(e.desc->name) + "' returned no object");
    // The deleter holds the library: it is unloaded only after the last object from it is gone.
    auto lib = e.lib;
    return std::shared_ptr<const Object>(raw, [lib](const Object* o) { delete o; });
}

} // namespace fp::host
