// `fixpoint explore`'s scores (explore.hpp): the measures of a draft, their weights, and the
// Lyapunov exponent of a chaos game's maps.
#pragma once

#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/registry.hpp>
#include <fixpoint/host/tools/symmetry.hpp>
#include <fixpoint/render.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace fp::host::explore_detail {

/// A draft rendered, with what its measures need.
struct Draft {
    const Image* image = nullptr;
    Rgb background;
    std::optional<double> lyapunov;
    const PixelFrame* frame = nullptr; ///< where the pixels stand in the plane; null: unknown
    bool symmetry = false;             ///< the symmetry measure is weighted (it costs a little)
    std::string group;                 ///< the wallpaper group the recipe declares, if any
    bool group_symmetry = false;       ///< the group measure is weighted (the same cost)
};

struct MeasureDef {
    const char* name;
    double default_weight;
    /// The default weight for patterns that fill the image (orbit-trap's wallpapers), where
    /// coverage and dimension tell the candidates nothing.
    double wallpaper_weight;
    std::optional<double> (*raw)(const Draft&);
    double (*score)(double);
};

/// The measures, in the order of --weights and of candidates.tsv.
const std::vector<MeasureDef>& measure_table();
/// The symmetry measure's place in the table.
std::size_t symmetry_index();
/// The index of a measure in the table (the table's size when there is none of that name).
std::size_t measure_index(const std::string& name);
/// --weights name=w,...: a weight per measure (the defaults for those not named: the
/// wallpaper ones when `wallpaper`).
std::vector<double> parse_weights(const std::string& text, bool wallpaper = false);
/// The largest Lyapunov exponent of a chaos game's maps (see scores.cpp); none for other
/// renderers or when every orbit escapes.
std::optional<double> chaos_game_lyapunov(const Registry& reg, const TObject& r, std::uint64_t seed,
                                          std::uint64_t id);

} // namespace fp::host::explore_detail
