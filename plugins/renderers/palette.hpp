// The colours point-plotting renderers give maps that have no `colour` of their own.
#pragma once

#include <fixpoint/types.hpp>

#include <cstddef>

namespace fp_render {

/// Tableau 10, by map index.
constexpr fp::Rgb palette[] = {
    {0x4e / 255.f, 0x79 / 255.f, 0xa7 / 255.f}, {0xf2 / 255.f, 0x8e / 255.f, 0x2b / 255.f},
    {0xe1 / 255.f, 0x57 / 255.f, 0x59 / 255.f}, {0x76 / 255.f, 0xb7 / 255.f, 0xb2 / 255.f},
    {0x59 / 255.f, 0xa1 / 255.f, 0x4f / 255.f}, {0xed / 255.f, 0xc9 / 255.f, 0x48 / 255.f},
    {0xb0 / 255.f, 0x7a / 255.f, 0xa1 / 255.f}, {0xff / 255.f, 0x9d / 255.f, 0xa7 / 255.f},
    {0x9c / 255.f, 0x75 / 255.f, 0x5f / 255.f}, {0xba / 255.f, 0xb0 / 255.f, 0xac / 255.f},
};

constexpr fp::Rgb palette_colour(std::size_t map) {
    return palette[map % (sizeof(palette) / sizeof(palette[0]))];
}

} // namespace fp_render
