// star-polygon — a regular star with `points` tips (paper 01, Fig. 6: star-shaped concave
// pentagons, stars with 24 vertices).
//
// The 2n vertices alternate between the outer and the inner circle around `centre`:
//
//     vertex 2k     = centre + outer_radius (cos a_k, sin a_k),          a_k = pi/2 + rotation + 2 pi k / n
//     vertex 2k + 1 = centre + inner_radius (cos(a_k + pi/n), sin(a_k + pi/n))
//
// so with rotation 0 the first tip points up. With inner < outer the polygon is simple, and
// the centre lies strictly on the inner side of every edge (cross(outer, inner) =
// R r sin(pi/n) > 0), so it is in the kernel and is the default centre of inversion. With
// n = 2 the star is a rhombus. The geometry is polygon_core.hpp's.
#include "polygon_core.hpp"

#include <numbers>
#include <string>

namespace {

constexpr fp::ParamSpec params[] = {
    fp::param::integer("points", "number of tips").def("5").min(2).max(100000),
    fp::param::real("outer_radius", "distance from the centre to the tips").def("1").above(0),
    fp::param::real("inner_radius", "distance from the centre to the inner vertices; below outer_radius")
        .def("0.5")
        .above(0),
    fp::param::real("rotation", "rotation in radians, counter-clockwise; 0 puts a tip straight up").def("0"),
    fp::param::vec2("centre", "centre of the star").def("[0, 0]"),
};

struct Star {
    std::vector<fp::Vec2> vertices;
    fp::Vec2 centre;
    std::string empty_kernel;
};

Star build(const fp::ParamBag& p) {
    const auto n = p.integer("points");
    const double outer = p.real("outer_radius"), inner = p.real("inner_radius");
    const double rotation = p.real("rotation");
    const fp::Vec2 c = p.vec2("centre");
    if (!(inner < outer))
        throw fp::ParamError("inner_radius", "inner_radius (" + fp::number_text(inner) +
                                                 ") must be less than outer_radius (" +
                                                 fp::number_text(outer) + ")");
    Star s;
    s.centre = c;
    s.empty_kernel = "inner_radius (" + fp::number_text(inner) + ") is too small for outer_radius (" +
                     fp::number_text(outer) + "): the star has no kernel";
    s.vertices.reserve(std::size_t(2 * n));
    const double step = std::numbers::pi / double(n);
    for (std::int64_t k = 0; k < 2 * n; ++k) {
        const double a = std::numbers::pi / 2 + rotation + step * double(k);
        const double r = k % 2 == 0 ? outer : inner;
        s.vertices.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
    }
    return s;
}

class StarPolygon final : public fp_shapes::PolygonShape {
public:
    explicit StarPolygon(const fp::ParamBag& p) : StarPolygon(build(p)) {}

private:
    // Simple by construction, so the O(n^2) validation of `polygon` is skipped; the centre is
    // still checked against the kernel (it fails only for an inner radius so small against
    // the outer one that the star has no interior to speak of).
    explicit StarPolygon(const Star& s)
        : PolygonShape(s.vertices, "inner_radius", &s.centre, s.empty_kernel) {}
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<StarPolygon>(fp::Kind::Shape, "star-polygon",
                                          "a regular star polygon with n tips between two radii", params))
