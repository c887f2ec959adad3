// `fixpoint addresses --where`: paper 05's Algorithm 1 by a predicate. The paper finds its
// "specific places" (the polygons that get a desired structure) by looking at the renders;
// a predicate on the polygons of a level names them instead, and the addresses it keeps are
// what `placements`, `only` and `highlight` take.
#pragma once

#include <fixpoint/types.hpp>

#include <string>
#include <vector>

namespace fp::host {

/// One condition on a polygon, parsed from --where text:
///   centre in [x0, x1, y0, y1]   the mean of its vertices lies in the box (edges included)
///   inside [x0, x1, y0, y1]      every vertex lies in the box
///   meets [x0, x1, y0, y1]       some vertex lies in the box
struct PolygonTest {
    enum class Kind { centre_in, inside, meets } kind = Kind::centre_in;
    Box box;
    bool operator()(const std::vector<Vec2>& vertices) const;
};

/// Parse one --where condition. Throws fp::InputError "--where 'TEXT': ..." saying what is
/// expected.
PolygonTest parse_where(const std::string& text);

/// The vertices of a line of Renderer::polygon_addresses ("ADDRESS (x, y) (x, y) ...").
std::vector<Vec2> address_line_vertices(const std::string& line);

} // namespace fp::host
