// ParamBag: typed values of one plugin instance, with read tracking.
#include <fixpoint/params.hpp>

namespace fp {

std::string_view param_type_name(ParamType t) {
    switch (t) {
    case ParamType::Bool: return "bool";
    case ParamType::Int: return "int";
    case ParamType::Real: return "real";
    case ParamType::String: return "string";
    case ParamType::Vec2: return "point";
    case ParamType::Colour: return "colour";
    case ParamType::Reals: return "list of reals";
    case ParamType::Vec2s: return "list of points";
    case ParamType::Object: return "object";
    case ParamType::Objects: return "list of objects";
    case ParamType::Sequence: return "sequence";
    }
    return "?";
}

ParamBag::ParamBag(const ParamSpec* specs, std::size_t n, std::string owner)
    : specs_(specs), n_specs_(n), owner_(std::move(owner)) {}

const ParamSpec* ParamBag::spec(const std::string& name) const {
    for (std::size_t i = 0; i < n_specs_; ++i)
        if (name == specs_[i].name) return &specs_[i];
    return nullptr;
}

void ParamBag::set(const std::string& name, ParamValue v) { values_[name] = Entry{std::move(v), false}; }

std::vector<std::string> ParamBag::unread() const {
    std::vector<std::string> out;
    for (const auto& [k, e] : values_)
        if (!e.read) out.push_back(k);
    return out;
}

bool ParamBag::has(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) return false;
    it->second.read = true; // asking whether an optional value is there counts as reading it
    return true;
}

const ParamValue& ParamBag::get(const std::string& name, ParamType t) const {
    const ParamSpec* s = spec(name);
    if (!s) throw InternalError(owner_ + ": plugin reads undeclared parameter '" + name + "'");
    if (s->type != t)
        throw InternalError(owner_ + ": plugin reads parameter '" + name + "' as " +
                            std::string(param_type_name(t)) + ", declared " +
                            std::string(param_type_name(s->type)));
    auto it = values_.find(name);
    if (it == values_.end())
        throw InternalError(owner_ + ": optional parameter '" + name + "' read without has()");
    it->second.read = true;
    return it->second.value;
}

bool ParamBag::boolean(const std::string& n) const { return std::get<bool>(get(n, ParamType::Bool)); }
std::int64_t ParamBag::integer(const std::string& n) const {
    return std::get<std::int64_t>(get(n, ParamType::Int));
}
double ParamBag::real(const std::string& n) const { return std::get<double>(get(n, ParamType::Real)); }
const std::string& ParamBag::string(const std::string& n) const {
    return std::get<std::string>(get(n, ParamType::String));
}
Vec2 ParamBag::vec2(const std::string& n) const { return std::get<Vec2>(get(n, ParamType::Vec2)); }
Rgb ParamBag::colour(const std::string& n) const { return std::get<Rgb>(get(n, ParamType::Colour)); }
const std::vector<double>& ParamBag::reals(const std::string& n) const {
    return std::get<std::vector<double>>(get(n, ParamType::Reals));
}
const std::vector<Vec2>& ParamBag::vec2s(const std::string& n) const {
    return std::get<std::vector<Vec2>>(get(n, ParamType::Vec2s));
}
const std::shared_ptr<const Object>& ParamBag::object_ptr(const std::string& n) const {
    return std::get<std::shared_ptr<const Object>>(get(n, ParamType::Object));
}
const std::vector<ObjectItem>& ParamBag::objects(const std::string& n) const {
    return std::get<std::vector<ObjectItem>>(get(n, ParamType::Objects));
}

const Sequence& ParamBag::sequence(const std::string& n) const {
    return std::get<Sequence>(get(n, ParamType::Sequence));
}

void ParamBag::bad_cast(const std::string& name) const {
    throw InternalError(owner_ + ": parameter '" + name + "' holds an object of another interface");
}

} // namespace fp
