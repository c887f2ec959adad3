// One plugin host for every unit test of a test program (loading the plugins once).
#pragma once

#include <fixpoint/host/core/host.hpp>

#include <functional>
#include <string>

namespace fp::test {

inline const fp::host::Host& host() {
    static const fp::host::Host h;
    return h;
}

/// Whether the transform `yaml` builds (its plugin may be left out of a build).
inline bool has_plugin(const std::string& yaml) {
    try {
        host().make_object(fp::Kind::Transform, yaml, "<string>");
        return true;
    } catch (const fp::InputError&) {
        return false;
    }
}

/// The message of the fp::InputError that `f` throws, or "(no error)".
inline std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const fp::InputError& e) {
        return e.what();
    }
    return "(no error)";
}

/// Paper 04's p4m example (Fig. 8), with the misprint P32 = [0.422963, 0] fixed to 0.429163 (the
/// p4m condition P32.x = P23.y; as in configs/orbit-trap/fig8a.yaml).
inline const std::string p4m_fig8 =
    "{type: wallpaper, group: p4m, P03: [0, -0.234602], P04: [0, -0.231376], P13: [0, -0.931333], "
    "P14: [0, -0.982975], P23: [0, 0.429163], P24: [0, 0.363704], P30: [-0.234602, 0], P31: [-0.931333, 0], "
    "P32: [0.429163, 0], P40: [-0.231376, 0], P41: [-0.982975, 0], P42: [0.363704, 0]}";

} // namespace fp::test
