// One plugin host for every unit test of a test program (loading the plugins once).
#pragma once

#include <fixpoint/host/host.hpp>

namespace fp::test {

inline const fp::host::Host& host() {
    static const fp::host::Host h;
    return h;
}

} // namespace fp::test
