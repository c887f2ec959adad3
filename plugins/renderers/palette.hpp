// The colours point-plotting renderers give maps that have no `colour` of their own, and the
// reading of a map item's colour parameters.
#pragma once

#include <fixpoint/errors.hpp>
#include <fixpoint/params.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <string>

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

/// A map item's flam3 colour parameters (chaos-game's maps, superfractal's), read by
/// read_item_colour.
constexpr fp::ParamSpec map_color_param =
    fp::param::real("color", "flam3's color: the map's index into the colourer's palette (default: the maps "
                             "spread evenly from 0 to 1)")
        .min(0)
        .max(1)
        .opt();
constexpr fp::ParamSpec map_color_speed_param =
    fp::param::real("color_speed",
                    "flam3's color_speed: how far the palette index a point carries moves toward "
                    "the map's color at each step")
        .def("0.5")
        .min(0)
        .max(1);

/// Item j of the list `list` (maps, final): its `colour` into c, flam3's palette index `color`
/// into index (refused, with one line, when the colourer takes no palette) and `color_speed`
/// into speed; each left as given where the item has none.
inline void read_item_colour(const fp::ParamBag& extras, const std::string& list, std::size_t j, bool palette,
                             fp::Rgb& c, float& index, float& speed) {
    if (extras.has("colour")) c = extras.colour("colour");
    if (extras.has("color")) {
        if (!palette)
            throw fp::ParamError(list, list + "[" + std::to_string(j) +
                                           "].color: a palette index (flam3's), but the colourer takes no "
                                           "palette (flame with palette: ...)");
        index = float(extras.real("color"));
    }
    if (extras.has("color_speed")) speed = float(extras.real("color_speed"));
}

} // namespace fp_render
