// `fixpoint symmetry`: which symmetry operations of the plane groups an image keeps.
//
// An image shows a region of the plane (its recipe's `area` or `view`, or --area). Each
// operation g (a rotation, mirror, glide or translation about the origin of the plane, or one
// given with --op) is applied in the plane and the picture resampled (bilinear) at g(p) for the
// centre p of every pixel whose image g(p) lies in the picture; the score is the fraction of those
// pixels whose colour agrees with the colour at g(p) (symmetry.cpp says what "agrees" is and
// why). An operation is kept when its score reaches the threshold; a group is kept when all the
// operations that generate it (with its lattice's translations) are.
#pragma once

#include <fixpoint/render.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace fp::host {

/// How pixels map to the plane.
struct PixelFrame {
    int width = 0, height = 0;
    Box region;
    /// true: pixel 0 at xmin, pixel W - 1 at xmax (orbit-trap's `area`, paper 04's Algorithm 2);
    /// false: the region is cut into W x H cells and a pixel stands at its cell's centre (the
    /// `view` of chaos-game, superfractal, mfs). Row 0 is at ymax either way.
    bool endpoints = true;
    Vec2 to_plane(double i, double j) const;
    Vec2 to_pixel(Vec2 p) const; ///< fractional (column, row)
};

/// An affine map of the plane p -> A p + t, A = [a b; c d].
struct PlaneOp {
    std::string id;   ///< short name: r3, m(-x,y), t(2pi,0), op1, ...
    std::string what; ///< in words
    double a = 1, b = 0, c = 0, d = 1, tx = 0, ty = 0;
    Vec2 operator()(Vec2 p) const { return {a * p.x + b * p.y + tx, c * p.x + d * p.y + ty}; }
};

struct SymmetryOptions {
    double tolerance = 0.1;  ///< per channel, colours in [0, 1]
    double threshold = 0.85; ///< an operation is kept when its score is at least this
    int smooth = 1;          ///< binomial [1 2 1] / 4 passes over the picture before scoring
};

struct OpScore {
    PlaneOp op;
    std::size_t compared = 0; ///< pixels whose image lies in the picture
    double score = 0;         ///< fraction of them that agree; meaningless when !measured
    bool measured = false;    ///< enough pixels compared (the operation keeps part of the picture)
    bool kept = false;
};

/// A wallpaper group (one orientation on one lattice) or a rosette group (the point symmetry
/// about the origin, C1 ... D6) as the operations that generate it.
struct GroupDef {
    std::string name; ///< p1 ... p6m, or C1 ... D6
    std::string
        lattice; ///< "square" (2 pi Z^2), "hexagonal" (2 pi (1, 0), 2 pi (1/2, sqrt 3 / 2)), or "" (rosette)
    std::vector<std::string> ops; ///< ids of PlaneOps of symmetry_ops()
    double size = 0; ///< operations per unit area (wallpaper) or the order (rosette): larger is bigger
};

/// The operations measured: translations of both lattices, rotations by 180, 90, 120, 60
/// degrees, the mirrors in the axes and the diagonal, and the glides of pg, pmg, pgg, p4g.
const std::vector<PlaneOp>& symmetry_ops();
/// The wallpaper groups of paper 04's maps (wallpaper_groups.hpp's generators, with the mirror
/// groups in both orientations) on the square and hexagonal lattices, and the rosette groups.
const std::vector<GroupDef>& wallpaper_groups();
const std::vector<GroupDef>& rosette_groups();
/// Whether `name` names a group of either list (names are case-sensitive: p3m1, D3).
bool known_group(const std::string& name);

/// Parse --op: "[a, b, c, d]" or "[a, b, c, d, tx, ty]" (p -> [a b; c d] p + t, in the plane).
/// Throws fp::InputError "--op '...': ...".
PlaneOp parse_op(const std::string& text, const std::string& id);
/// Parse --area: "[xmin, xmax, ymin, ymax]". Throws fp::InputError.
Box parse_area(const std::string& text);

/// The frame of an image from its recipe: renderer.area (pixel ends) or renderer.view (cells).
/// Throws fp::InputError when the recipe gives neither or renders another size than the image's
/// (a contact sheet, sets beside the fractal). `source` names the image in messages.
PixelFrame frame_from_recipe(const std::string& recipe, int width, int height, const std::string& source);
/// The frame of an image with no recipe: [-2 pi, 2 pi] across its width about its centre, square
/// pixels (paper 04's area; Lu et al.'s default).
PixelFrame default_frame(int width, int height);

/// Score one operation: the colour of each pixel p of `img` against the picture at g(p), in
/// `img` itself or, given, in `other` (whose frame places it in the plane: e.g. a render of a
/// wider region, to compare a zoom with the pattern it should repeat).
OpScore score_op(const Image& img, const PixelFrame& f, const PlaneOp& op, const SymmetryOptions& o,
                 const Image* other = nullptr, const PixelFrame* other_frame = nullptr);

struct GroupResult {
    const GroupDef* group = nullptr;
    bool kept = false;
    bool measured = true; ///< every operation of the group was measured
    double worst = 0;     ///< the lowest score of its operations
};

struct SymmetryReport {
    std::vector<OpScore> ops;
    std::vector<GroupResult> groups;           ///< every wallpaper group, or those named by --group
    std::vector<GroupResult> rosettes;         ///< every rosette group, or those named by --group
    const GroupDef* largest = nullptr;         ///< the largest wallpaper group kept
    const GroupDef* largest_rosette = nullptr; ///< the largest rosette group kept
};

/// Measure. `only_group` non-empty: only the operations of the groups of that name (every
/// orientation and lattice). `extra`: further operations to score (not part of any group).
SymmetryReport measure_symmetry(const Image& img, const PixelFrame& f, const SymmetryOptions& o,
                                const std::string& only_group, const std::vector<PlaneOp>& extra,
                                const Image* other = nullptr, const PixelFrame* other_frame = nullptr);

/// The report as a table (text) or as JSON.
std::string symmetry_text(const SymmetryReport& r, const PixelFrame& f, const SymmetryOptions& o,
                          const std::string& only_group);
std::string symmetry_json(const SymmetryReport& r, const PixelFrame& f, const SymmetryOptions& o,
                          const std::string& only_group, const std::string& source);

/// With --group: whether a group of that name was kept.
bool group_kept(const SymmetryReport& r, const std::string& name);

} // namespace fp::host
