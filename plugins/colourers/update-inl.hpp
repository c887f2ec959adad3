// Colourer::update for the two colour rules (fp::ColourRule): tone_map.hpp's update_colours
// loop inlined into one function per instruction set of the build, where the compiler
// vectorises it with that target's instructions (the map colours' gathers included); included
// through Highway's foreach_target by map-colour.cpp and flame.cpp, dispatched at run time.

#if defined(FP_COLOURERS_UPDATE_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef FP_COLOURERS_UPDATE_INL_HPP_
#undef FP_COLOURERS_UPDATE_INL_HPP_
#else
#define FP_COLOURERS_UPDATE_INL_HPP_
#endif

#include "tone_map.hpp"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace fp_colourers::HWY_NAMESPACE {

/// c' = c_j (map-colour).
void update_map(const std::uint32_t* map, fp::ColourState s, const fp::Rgb* map_colours,
                const unsigned char* mask) {
    update_colours(map, s.r, s.g, s.b, s.n, map_colours, mask, TakeMapColour{});
}

/// c' = (c + c_j) * 0.5 (flame's running colour, paper 02 Sec. 5).
void update_average(const std::uint32_t* map, fp::ColourState s, const fp::Rgb* map_colours,
                    const unsigned char* mask) {
    update_colours(map, s.r, s.g, s.b, s.n, map_colours, mask, AverageColour{});
}

} // namespace fp_colourers::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif // per-target include guard
