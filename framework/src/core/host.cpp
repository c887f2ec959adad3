#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/registry.hpp>

namespace fp::host {

Host::Host(std::vector<std::filesystem::path> extra_dirs) : registry_(std::make_unique<Registry>()) {
    for (const auto& d : Registry::default_dirs()) registry_->load_dir(d);
    for (const auto& d : extra_dirs) registry_->load_dir(d);
}

Host::~Host() = default;

std::shared_ptr<const Object> Host::make_object(Kind kind, const std::string& yaml,
                                                const std::string& source) const {
    const CNode node = parse_yaml(yaml, source);
    const auto t = validate(*registry_, kind, node, std::string(kind_name(kind)));
    return build(*registry_, *t);
}

} // namespace fp::host
