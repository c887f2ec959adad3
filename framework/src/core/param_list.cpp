// The parameters of a config for the preview page's panel (host/param_list.hpp): the tree is
// walked with the plugins' schemas, as validate() walks it, but nothing is refused: what the
// page shows is what the file says, even while the file is wrong.
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/param_list.hpp>

#include <cmath>

namespace fp::host {

namespace {

// The plugin named in an object slot's node: its `type:`, else (not a mapping) the node as
// written, else nothing.
std::string type_of(const CNode& n) {
    if (!n.is_map()) return emit_flow_yaml(n);
    const CNode* t = n.find("type");
    return t && t->is_scalar() ? t->scalar : "";
}

std::string type_of_default(const char* yaml) {
    try {
        return type_of(parse_yaml(yaml, "<default>"));
    } catch (const InputError&) {
        return "";
    }
}

const char* kind_text(const ParamSpec& s) {
    switch (s.type) {
    case ParamType::Bool: return "bool";
    case ParamType::Int: return "int";
    case ParamType::Real: return "real";
    case ParamType::String: return s.choices ? "choice" : "string";
    case ParamType::Vec2: return "point";
    case ParamType::Colour: return "colour";
    case ParamType::Reals: return "reals";
    case ParamType::Vec2s: return "points";
    case ParamType::Object: return "plugin";
    case ParamType::Objects: return "list";
    case ParamType::Sequence: return "sequence";
    }
    return "?";
}

std::vector<std::string> split_choices(const char* choices) {
    std::vector<std::string> out;
    const std::string all = choices;
    for (std::size_t a = 0;;) {
        const auto b = all.find('|', a);
        out.push_back(all.substr(a, b == std::string::npos ? b : b - a));
        if (b == std::string::npos) return out;
        a = b + 1;
    }
}

class Lister {
public:
    explicit Lister(const Registry& reg) : reg_(reg) {}
    std::vector<ParamEntry> out;

    std::vector<std::string> plugins_of(Kind k) const {
        std::vector<std::string> names;
        for (const auto* e : reg_.all(k)) names.emplace_back(e->desc->name);
        return names;
    }

    // The parameters of the plugin in the object slot `node` of `kind` at `path`: none when
    // the slot names no plugin of that kind (an unknown one, a typo, not a mapping).
    void plugin_params(Kind kind, const CNode& node, const std::string& path, int depth) {
        const std::string type = node.is_map() ? type_of(node) : "";
        const PluginEntry* e = type.empty() ? nullptr : reg_.find(type);
        if (!e || e->desc->kind != kind) return;
        for (std::size_t i = 0; i < e->desc->n_params; ++i) {
            const ParamSpec& s = e->desc->params[i];
            param(s, node.find(s.name), path + "." + s.name, e->desc->name, depth);
        }
    }

    void param(const ParamSpec& s, const CNode* v, const std::string& path, const std::string& owner,
               int depth) {
        ParamEntry p;
        p.path = path;
        p.name = s.name;
        p.owner = owner;
        p.kind = kind_text(s);
        p.written = v != nullptr;
        p.required = !s.default_yaml && !s.optional;
        p.default_value = s.default_yaml ? s.default_yaml : "";
        p.value = v ? emit_flow_yaml(*v) : p.default_value;
        if (s.type != ParamType::Bool && s.type != ParamType::String && s.type != ParamType::Colour &&
            s.type != ParamType::Object && s.type != ParamType::Objects) {
            if (std::isfinite(s.lo)) {
                p.min = s.lo;
                p.min_open = s.lo_open;
            }
            if (std::isfinite(s.hi)) {
                p.max = s.hi;
                p.max_open = s.hi_open;
            }
        }
        if (s.choices) p.choices = split_choices(s.choices);
        if (s.type == ParamType::Object || s.type == ParamType::Objects) {
            p.plugin_kind = kind_name(s.kind);
            p.choices = plugins_of(s.kind);
        }
        p.description = s.doc ? s.doc : "";
        p.depth = depth;
        if (s.type == ParamType::Object) {
            // The slot shows the plugin's name; the parameters of a plugin the config does not
            // write (a default) are not listed: a path under it would add keys to a mapping
            // without its `type:`.
            p.value = v ? type_of(*v) : s.default_yaml ? type_of_default(s.default_yaml) : "";
            out.push_back(std::move(p));
            if (v) plugin_params(s.kind, *v, path, depth + 1);
            return;
        }
        if (s.type == ParamType::Objects) {
            p.count = v && v->is_seq() ? v->items.size() : 0;
            out.push_back(std::move(p));
            if (v && v->is_seq())
                for (std::size_t i = 0; i < v->items.size(); ++i)
                    item(s, v->items[i], path, i, owner, depth + 1);
            return;
        }
        out.push_back(std::move(p));
    }

    // Item `i` of the list `s` at `path`: its slot, its plugin's parameters and the keys that
    // stand beside them (a map's weight and colour, declared by the list's owner).
    void item(const ParamSpec& s, const CNode& v, const std::string& path, std::size_t i,
              const std::string& owner, int depth) {
        const std::string ip = path + "[" + std::to_string(i) + "]";
        ParamEntry p;
        p.path = ip;
        p.name = std::string(s.name) + "[" + std::to_string(i) + "]";
        p.owner = owner;
        p.kind = "plugin";
        p.value = type_of(v);
        p.written = true;
        p.plugin_kind = kind_name(s.kind);
        p.choices = plugins_of(s.kind);
        const PluginEntry* e = reg_.find(p.value);
        p.description = e && e->desc->summary ? e->desc->summary : "";
        p.depth = depth;
        out.push_back(std::move(p));
        if (!v.is_map()) return; // no path reaches into it
        plugin_params(s.kind, v, ip, depth + 1);
        for (std::uint32_t j = 0; j < s.n_item_params; ++j) {
            const ParamSpec& x = s.item_params[j];
            param(x, v.find(x.name), ip + "." + x.name, owner, depth + 1);
        }
    }

private:
    const Registry& reg_;
};

} // namespace

std::vector<ParamEntry> list_params(const Registry& reg, const CNode& root) {
    Lister l(reg);
    const CNode* r = root.is_map() ? root.find("renderer") : nullptr;
    ParamEntry p;
    p.path = p.name = p.plugin_kind = "renderer";
    p.kind = "plugin";
    p.value = r ? type_of(*r) : "";
    p.written = r != nullptr;
    p.required = true;
    p.choices = l.plugins_of(Kind::Renderer);
    p.description = "the pipeline to render";
    l.out.push_back(std::move(p));
    if (r) l.plugin_params(Kind::Renderer, *r, "renderer", 0);
    return std::move(l.out);
}

} // namespace fp::host
