// Palettes: flam3's 256 colours indexed by a number in [0, 1], for a colourer whose chains carry
// a palette index (flam3's `color` and `color_speed`: Colourer::palette_index).
//
// A palette is named (one of fixpoint's built-in gradients, or "flam3:N" / "flam3:NAME", read
// from flam3's palette file where Debian's flam3-palette package installs it), or given as a
// gradient of stops. Looked up as flam3 does (rect.c): `step`, the entry floor(256 t) clamped to
// [0, 255]; `linear`, between that entry and the next.
#pragma once

#include <fixpoint/params.hpp>
#include <fixpoint/types.hpp>

#include <array>
#include <string>
#include <vector>

namespace fp {

struct Palette {
    static constexpr int size = 256; ///< flam3's CMAP_SIZE
    std::array<Rgb, size> colours{};
    bool linear = false; ///< flam3's palette_mode: step (false) or linear

    /// The colour of index t (flam3's lookup; NaN takes entry 0).
    Rgb at(float t) const {
        const float x = t * float(size);
        int i = x >= 0.0f ? int(x) : 0; // (NaN fails the test: entry 0)
        if (!linear) return colours[std::size_t(i < size - 1 ? i : size - 1)];
        float f = x - float(i);
        if (!(x >= 0.0f)) i = 0, f = 0.0f;
        if (i >= size - 1) i = size - 2, f = 1.0f;
        const Rgb a = colours[std::size_t(i)], b = colours[std::size_t(i + 1)];
        return Rgb{a.r * (1.0f - f) + b.r * f, a.g * (1.0f - f) + b.g * f, a.b * (1.0f - f) + b.b * f};
    }
};

/// The built-in gradients' names, "a|b|..." (fixpoint's own; flam3's are "flam3:...").
const char* palette_builtins();

/// The palette `name` names: a built-in, or "flam3:N" (its number) or "flam3:NAME" from flam3's
/// palette file (flam3_palette_file()). fp::ParamError at `param` for a name that is none of
/// them ("did you mean"), and for flam3's file where it is not installed.
Palette palette_named(const std::string& name, const std::string& param);

/// A gradient through `stops`, four numbers each: position t (from 0 to 1, increasing) and the
/// colour r, g, b in [0, 1]; sampled at the entries' centres (i + 1/2) / 256, flat beyond the
/// first and last stop. fp::ParamError at `param` otherwise.
Palette palette_of_stops(const std::vector<double>& stops, const std::string& param);

/// Where flam3's palettes are read: $FIXPOINT_FLAM3_PALETTES when set (the tests' fixtures),
/// else /usr/share/flam3/flam3-palettes.xml (Debian's flam3-palette).
std::string flam3_palette_file();

/// Palette `which` (its number, or its name) of the flam3 palette file at `path`: 256 entries
/// "00RRGGBB" in its `data` attribute. fp::ParamError at `param` for a file that is missing or
/// not one, and for a palette it does not hold ("did you mean").
Palette read_flam3_palette(const std::string& path, const std::string& which, const std::string& param);

/// The colourer parameters of a palette, shared by the colourers that take one: `palette` (a
/// name), `palette_stops` (a gradient), `palette_mode` (flam3's). They decide the colour each
/// point deposits, so they are not finishing parameters.
constexpr ParamSpec palette_param =
    param::string("palette",
                  "a palette the maps' `color` indexes (flam3's): a built-in gradient, or flam3:N or "
                  "flam3:NAME from flam3's palette file (Debian's flam3-palette); unset: none")
        .opt();
constexpr ParamSpec palette_stops_param =
    param::reals("palette_stops",
                 "a palette as a gradient: position t (0 to 1, increasing) and colour r, g, b "
                 "(0 to 1) of each stop, one flat list")
        .min(0)
        .max(1)
        .min_len(4)
        .opt();
constexpr ParamSpec palette_mode_param =
    param::string("palette_mode",
                  "flam3's palette_mode: step (the entry the index falls in) or linear (between "
                  "entries)")
        .def("step")
        .one_of("step|linear");

/// The palette of a colourer's parameters (palette_param or palette_stops_param, at most one),
/// or none (false) when neither is given.
bool palette_of(const ParamBag& p, Palette& out);

} // namespace fp
