// polygon — a star-shaped simple polygon given by its vertices (paper 01, Sec. 3,
// Definitions 2 and 3; the triangles, squares and crosses of Figs. 5 and 6).
//
// The star-shaped set inversion needs a centre o in the kernel, the points from which the
// whole polygon is visible, so that every ray from o meets the boundary once. The polygon is
// refused unless it is simple (no repeated consecutive vertices, no self-intersections), has
// non-zero area and a kernel with an interior; its default centre is the centroid of the
// kernel. Either orientation is accepted. The geometry (validation, kernel by half-plane
// clipping, crossing-number inside test, ray exit) is in polygon_core.hpp, shared with
// star-polygon; see the comment there for the tolerances and the vertex cases.
#include "polygon_core.hpp"

namespace {

constexpr fp::ParamSpec params[] = {
    fp::param::vec2s("vertices",
                     "the vertices in order, either orientation; edge i joins vertex i to vertex i + 1 "
                     "(the last joins the first). The polygon must be simple and star-shaped")
        .min_len(3),
};

std::vector<fp::Vec2> checked(const fp::ParamBag& p) {
    std::vector<fp::Vec2> v = p.vec2s("vertices");
    fp_shapes::validate_polygon(v, "vertices");
    return v;
}

class Polygon final : public fp_shapes::PolygonShape {
public:
    explicit Polygon(const fp::ParamBag& p) : PolygonShape(checked(p), "vertices") {}
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Polygon>(fp::Kind::Shape, "polygon",
                                      "a simple star-shaped polygon given by its vertices", params)
                    .with_example("{vertices: [[-1, -1], [1, -1], [0, 1]]}"))
