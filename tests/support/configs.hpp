// The chaos-game recipes the tests render again and again (three inverted circles, the
// Sierpinski triangle), built from the few numbers each test chooses, so that a test's config
// says only what it changes. The text is exactly what the tests wrote out before: one key a line,
// in the order given, so that the lines and columns their messages name stay where they were.
#pragma once

#include <string>
#include <vector>

namespace fp::test {

/// `renderer:` of type chaos-game with `keys` ("width: 64", ...; one a line, in order) and then
/// `maps`, a `  maps:` block.
inline std::string chaos_game(const std::vector<std::string>& keys, const std::string& maps) {
    std::string s = "renderer:\n  type: chaos-game\n";
    for (const auto& k : keys) s += "  " + k + "\n";
    return s + maps;
}

/// The `maps:` of three circles of radius `radius` (as written in YAML) centred on the cube roots
/// of 1, inverted; coloured red, green and blue where `coloured`.
inline std::string three_circles(const std::string& radius, bool coloured = false) {
    const char* centres[] = {"[1, 0]", "[-0.5, 0.866]", "[-0.5, -0.866]"};
    const char* colours[] = {"[1, 0.4, 0.2]", "[0.2, 1, 0.4]", "[0.3, 0.4, 1]"};
    std::string s = "  maps:\n";
    for (int i = 0; i < 3; ++i)
        s += std::string("    - {type: inversion, shape: {type: circle, centre: ") + centres[i] +
             ", radius: " + radius + "}" + (coloured ? std::string(", colour: ") + colours[i] : "") + "}\n";
    return s;
}

/// A small chaos game: three circles of radius 0.8, 24 x 16 pixels, a few thousand points
/// (a render in milliseconds, for the tests of what is done with an image rather than of it).
inline const std::string small_circles =
    chaos_game({"width: 24", "height: 16", "points: 4000", "chains: 8", "view: [-2, 2, -1.5, 1.5]"},
               three_circles("0.8"));

/// The `maps:` of the Sierpinski triangle: three affine maps of ratio 1/2.
inline const std::string sierpinski = "  maps:\n"
                                      "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}\n"
                                      "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}\n"
                                      "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, 0.5]}\n";

} // namespace fp::test
