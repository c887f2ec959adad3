// The root of every plugin object.
#pragma once

namespace fp {

/// Every plugin instance derives from Object through one of the interfaces. The host owns
/// instances through shared_ptr handles that also keep the plugin's library loaded.
/// Objects are immutable once built: every hot-path method is const and may be called from
/// several threads at once.
class Object {
public:
    Object() = default;
    Object(const Object&) = delete;
    Object& operator=(const Object&) = delete;
    virtual ~Object();
};

} // namespace fp
