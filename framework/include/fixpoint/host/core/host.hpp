// The host: plugin registry plus building objects from YAML.
#pragma once

#include <fixpoint/fixpoint.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace fp::host {

class Registry;

class Host {
public:
    /// Discovers plugins in the build's (or install's) plugin folder, in FIXPOINT_PLUGIN_PATH
    /// (colon-separated) and in `extra_dirs`.
    explicit Host(std::vector<std::filesystem::path> extra_dirs = {});
    ~Host();

    const Registry& registry() const { return *registry_; }

    /// Builds an object of interface I from YAML text (a flow mapping such as
    /// "{type: circle, radius: 1}"). Errors are fp::InputError with the message
    /// "<source>:line:col: path: message".
    template <class I>
    std::shared_ptr<const I> make(const std::string& yaml, const std::string& source = "<string>") const {
        return std::dynamic_pointer_cast<const I>(make_object(kind_of<I>(), yaml, source));
    }

    std::shared_ptr<const Object> make_object(Kind kind, const std::string& yaml,
                                              const std::string& source) const;

    template <class I>
    static constexpr Kind kind_of();

private:
    std::unique_ptr<Registry> registry_;
};

template <>
constexpr Kind Host::kind_of<Shape>() {
    return Kind::Shape;
}
template <>
constexpr Kind Host::kind_of<Transform>() {
    return Kind::Transform;
}
template <>
constexpr Kind Host::kind_of<IterationScheme>() {
    return Kind::IterationScheme;
}
template <>
constexpr Kind Host::kind_of<NumberSystem>() {
    return Kind::NumberSystem;
}
template <>
constexpr Kind Host::kind_of<Trap>() {
    return Kind::Trap;
}
template <>
constexpr Kind Host::kind_of<Metric>() {
    return Kind::Metric;
}
template <>
constexpr Kind Host::kind_of<Colourer>() {
    return Kind::Colourer;
}
template <>
constexpr Kind Host::kind_of<Renderer>() {
    return Kind::Renderer;
}
template <>
constexpr Kind Host::kind_of<Filter>() {
    return Kind::Filter;
}

} // namespace fp::host
