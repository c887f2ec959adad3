// mfs: (nonuniform) multiple function systems of subdivision maps (paper 05: Zhang, Zhang and
// Xie, "Generating irregular fractals based on iterated function systems", AIMS Math. 2024).
//
// What it computes
// ----------------
// `maps` are subdivision maps f_1 .. f_N (fp::VertexMap: the `subdivision` transform), each
// listing the IFSs it belongs to (`systems`, default [0]); IFS e is the maps whose `systems`
// hold e, in map order. The multiple function system acts along `path` (ε_1, ε_2, ...): at
// level l every vertex set V of the previous level yields one child S_j V for each map f_j of
// IFS ε_l. Children subdivide their parent (the paper's Sec. 3.2: the matrix P of each map is
// replaced by the parent's points P' = V, so f'(V) = V P'^-1 S P' = S V). The polygon at
// address (a_1, ..., a_k) (1-based map numbers, written "a_1.a_2...a_k" as the paper's labels)
// has vertices S_{a_k} ... S_{a_1} P_0, P_0 the initial set `points`; it is the image of the
// initial polygon under f_{a_1} o ... o f_{a_k} with the original P. For a path over one IFS
// this is the usual level-k approximation of its attractor.
//
// Nonuniform MFS and Algorithm 2 (placements)
// -------------------------------------------
// `placements` are nested mfs structures, each with `at` (addresses "5" or "1.5; 2.5") and
// `split`. At every address the polygon of the target (this structure) is computed, cut into
// pieces by `split` (vertex indices of the polygon, one group per piece, e.g. "0 1 2; 3 2 1":
// the default when a 4-point polygon takes a 3-point structure: the paper's quads are listed
// in Z order (0,0), (1,0), (0,1), (1,1), so these are the triangles on either side of the
// diagonal from vertex 1 to vertex 2; identity when the counts agree), and each piece becomes
// the initial set P' of the nested structure (Proposition 1: the same S with P replaced by
// P' gives the image of the nested fractal under the affine map taking P to P'). The
// target's own polygons at a placed address, and their descendants, are dropped (replaced);
// an address the target's path does not produce (a hole, as in Example 3) just adds the
// structure. A nested structure uses its own maps, systems, path, placements, colour and
// colour_by; the drawing (size, view, draw mode, line width, labels) is the top renderer's.
// Per-set paths (Fig. 2, left) are placements whose structure has the same maps and another
// path. `hide: "2; 4; 6; 8"` drops the target's polygons at those addresses without placing
// anything (Example 2); `draw_target: false` draws only the placed structures.
//
// Algorithm 1 (analysis)
// ----------------------
// `fixpoint addresses CONFIG --level K` lists the target's polygons at level K with their
// vertices (polygon_addresses); `only: "2"` draws only the polygons (and placements) under an
// address,
// `highlight: "2.5; 5"` outlines polygons (any address of map numbers) on top, and
// `labels: true` writes each drawn target polygon's address at its centroid (Fig. 4, middle),
// or, with `highlight`, each highlighted polygon's address (Fig. 6, left).
//
// Drawing
// -------
// Polygons join their vertices in `order` (default: by angle about the centroid of the
// initial points, so Z-ordered quads draw as quads); `draw` fill, outline or points (the
// vertices); `colour_by` fixed (`colour`), level (depth, counting placements), ifs (the IFS of
// the last level), map (the last map) or address (the first map of the full address: the
// nine parts of Fig. 4 middle). Cairo fills with antialiasing (mfs_draw.hpp); the output path
// .svg or .pdf gives a vector document with the recipe embedded. The view defaults to the
// initial points' bounding box, 5% margin, widened to square pixels; y points up.
//
// Limits and errors (fp::ParamError, by parameter): more than 50 000 000 polygons in all is
// refused before anything is allocated, with the count and the memory it would take; a path
// naming an IFS that does not exist; a map that is no subdivision map or has another number of
// control points; `only` naming an address the path does not produce; placement addresses
// naming maps that do not exist; a split whose pieces do not fit. Renders are sequential and
// a pure function of the recipe (threads change nothing).
#include "mfs/renderer.hpp"
#include "palette.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/vertex_map.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace fp_mfs {
namespace {

constexpr double max_polygons = 5e7;

std::string bytes_text(double b) {
    const char* units[] = {"bytes", "KB", "MB", "GB", "TB", "PB", "EB"};
    int u = 0;
    while (b >= 1000 && u < 6) b /= 1000, ++u;
    char buf[48];
    std::snprintf(buf, sizeof buf, u ? "%.1f %s" : "%.0f %s", b, units[u]);
    return buf;
}

std::string count_text(double c) {
    char buf[48];
    std::snprintf(buf, sizeof buf, c < 1e15 ? "%.0f" : "%.3g", c);
    return buf;
}

} // namespace

Mfs::Mfs(const fp::ParamBag& p) {
    frame_ = fp::Frame::read(p);
    // Maps: subdivision maps with one vertex count; the IFSs from their `systems`.
    const auto& items = p.objects("maps");
    std::vector<std::vector<uint32_t>> member(items.size());
    // The IFS indices used, to check that they make 0, 1, ..., n - 1 before anything is sized by
    // them: an index is user input (`systems: [4294967295]` once indexed past a vector's end).
    std::vector<uint32_t> used;
    for (size_t i = 0; i < items.size(); ++i) {
        auto m = fp::as<fp::VertexMap>(items[i]);
        if (!m)
            throw fp::ParamError("maps",
                                 "maps[" + std::to_string(i) +
                                     "] is no subdivision map: the mfs renderer subdivides vertex sets "
                                     "(use type: subdivision)");
        if (i == 0) n_ = m->vertex_count();
        if (m->vertex_count() != n_)
            throw fp::ParamError("maps", "maps[" + std::to_string(i) + "] has " +
                                             std::to_string(m->vertex_count()) +
                                             " control points, maps[0] has " + std::to_string(n_) +
                                             ": the maps of one structure subdivide sets of one size");
        maps_.push_back(m);
        for (double e : items[i].extras->reals("systems")) {
            if (e != std::floor(e) || e < 0)
                throw fp::ParamError("maps", "maps[" + std::to_string(i) +
                                                 "].systems: IFS indices are whole " +
                                                 "numbers from 0, got " + fp::number_text(e));
            // A bound far above any real structure, which keeps the cast below exact; indices
            // below it that leave an IFS without maps are refused after the sort.
            if (e > 1e9)
                throw fp::ParamError("maps", "maps[" + std::to_string(i) + "].systems: IFS " + count_text(e) +
                                                 " is out of range: the maps' systems must number the IFSs "
                                                 "0, 1, 2, ...");
            member[i].push_back(uint32_t(e));
            used.push_back(uint32_t(e));
        }
    }
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    if (used.empty()) throw fp::ParamError("maps", "no map belongs to an IFS: give the maps' systems");
    const uint32_t n_ifs = used.back() + 1;
    for (uint32_t e = 0; e < used.size(); ++e)
        if (used[e] != e)
            throw fp::ParamError("maps", "IFS " + std::to_string(e) +
                                             " has no maps: the maps' systems must cover 0 to " +
                                             std::to_string(n_ifs - 1));
    systems_.resize(n_ifs);
    for (size_t i = 0; i < items.size(); ++i)
        for (uint32_t e : member[i])
            if (std::find(systems_[e].begin(), systems_[e].end(), uint32_t(i)) == systems_[e].end())
                systems_[e].push_back(uint32_t(i));
    // The path, each entry an IFS.
    const auto& path = p.reals("path");
    for (size_t l = 0; l < path.size(); ++l) {
        const double e = path[l];
        if (e != std::floor(e) || e < 0 || e >= double(n_ifs))
            throw fp::ParamError("path", "path[" + std::to_string(l) + "]: IFS " + count_text(e) +
                                             " does not exist: the maps' systems make " +
                                             (n_ifs == 1 ? std::string("IFS 0 only")
                                                         : "IFSs 0 to " + std::to_string(n_ifs - 1)));
        path_.push_back(uint32_t(e));
    }
    // The initial set and the drawing order.
    points_ = p.has("points") ? p.vec2s("points") : maps_[0]->control_points();
    if (points_.size() != n_)
        throw fp::ParamError("points", std::to_string(points_.size()) +
                                           " points given; the maps subdivide sets of " + std::to_string(n_));
    if (p.has("order")) {
        const auto& o = p.reals("order");
        std::vector<char> seen(n_, 0);
        for (double v : o) {
            if (v != std::floor(v) || v < 0 || v >= double(n_) || seen[size_t(v)])
                throw fp::ParamError("order", "order must list the vertex indices 0 to " +
                                                  std::to_string(n_ - 1) + " once each");
            seen[size_t(v)] = 1;
            order_.push_back(size_t(v));
        }
        if (order_.size() != n_)
            throw fp::ParamError("order", "order must list the vertex indices 0 to " +
                                              std::to_string(n_ - 1) + " once each");
    } else {
        double cx = 0, cy = 0;
        for (const auto& q : points_) cx += q.x / double(n_), cy += q.y / double(n_);
        std::vector<double> ang(n_);
        for (size_t i = 0; i < n_; ++i)
            ang[i] = std::atan2(points_[i].y - cy, points_[i].x - cx), order_.push_back(i);
        std::stable_sort(order_.begin(), order_.end(), [&](size_t a, size_t b) { return ang[a] < ang[b]; });
    }
    // Drawing.
    draw_target_ = p.boolean("draw_target");
    const std::string& draw = p.string("draw");
    mode_ = draw == "outline" ? DrawMode::Outline : draw == "points" ? DrawMode::Points : DrawMode::Fill;
    colour_by_ = p.string("colour_by");
    colour_ = p.colour("colour");
    mark_colour_ = p.colour("mark_colour");
    line_width_ = p.real("line_width");
    labels_ = p.boolean("labels");
    label_size_ = p.real("label_size");
    if (p.has("only")) {
        const auto a = parse_addresses(p.string("only"), maps_.size(), "only");
        if (a.size() != 1) throw fp::ParamError("only", "give one address");
        only_ = a[0];
        if (only_.size() > path_.size())
            throw fp::ParamError("only", "address " + address_text(only_) + " does not exist: the path has " +
                                             std::to_string(path_.size()) + " levels");
        for (size_t l = 0; l < only_.size(); ++l) {
            const auto& ifs = systems_[path_[l]];
            if (std::find(ifs.begin(), ifs.end(), only_[l]) == ifs.end())
                throw fp::ParamError("only", "address " + address_text(only_) + " does not exist at level " +
                                                 std::to_string(l + 1) + ": IFS " + std::to_string(path_[l]) +
                                                 " (path[" + std::to_string(l) + "]) has no f" +
                                                 std::to_string(only_[l] + 1));
        }
    }
    if (p.has("highlight")) highlight_ = parse_addresses(p.string("highlight"), maps_.size(), "highlight");
    if (p.has("hide")) placed_ = parse_addresses(p.string("hide"), maps_.size(), "hide");
    // Placements.
    double count = 1, level_count = 1;
    for (size_t l = 0; l < path_.size(); ++l) count *= double(systems_[path_[l]].size());
    level_count = count;
    if (level_count > max_polygons)
        throw fp::ParamError("path", "the path makes " + count_text(level_count) +
                                         " polygons at its last level (" +
                                         bytes_text(level_count * bytes_per_polygon()) + "): more than the " +
                                         count_text(max_polygons) + " a render may hold; shorten the path");
    total_ = count;
    if (p.has("placements")) {
        const auto& pl = p.objects("placements");
        for (size_t i = 0; i < pl.size(); ++i) {
            const std::string where = "placements[" + std::to_string(i) + "]";
            Placement P;
            P.mfs = std::dynamic_pointer_cast<const Mfs>(pl[i].object);
            if (!P.mfs)
                throw fp::ParamError("placements",
                                     where + " is no mfs structure: only mfs structures are placed");
            P.at = parse_addresses(pl[i].extras->string("at"), maps_.size(), "placements");
            const size_t m = P.mfs->vertex_count();
            if (pl[i].extras->has("split")) {
                P.pieces = parse_groups(pl[i].extras->string("split"), ' ', "placements",
                                        "a split such as \"0 1 2; 3 2 1\"");
            } else if (m == n_) {
                P.pieces.emplace_back();
                for (uint32_t k = 0; k < n_; ++k) P.pieces[0].push_back(k);
            } else if (n_ == 4 && m == 3) {
                P.pieces = {{0, 1, 2}, {3, 2, 1}};
            } else {
                throw fp::ParamError("placements", where + ": a " + std::to_string(n_) +
                                                       "-point polygon takes a " + std::to_string(m) +
                                                       "-point structure only with a split");
            }
            for (const auto& piece : P.pieces) {
                if (piece.size() != m)
                    throw fp::ParamError("placements",
                                         where + ".split: each piece needs " + std::to_string(m) +
                                             " vertex indices (the structure's control points)");
                for (uint32_t v : piece)
                    if (v >= n_)
                        throw fp::ParamError("placements",
                                             where + ".split: vertex " + std::to_string(v) +
                                                 " does not exist: the polygon has vertices 0 to " +
                                                 std::to_string(n_ - 1));
            }
            total_ += double(P.at.size()) * double(P.pieces.size()) * P.mfs->total();
            for (const auto& a : P.at) placed_.push_back(a);
            placements_.push_back(std::move(P));
        }
    }
    std::sort(placed_.begin(), placed_.end());
    if (total_ > max_polygons)
        throw fp::ParamError("placements",
                             "the structures make " + count_text(total_) + " polygons in all (" +
                                 bytes_text(total_ * bytes_per_polygon()) + "): more than the " +
                                 count_text(max_polygons) + " a render may hold");
    // The view.
    if (!frame_.has_region) {
        fp::Box b{points_[0].x, points_[0].x, points_[0].y, points_[0].y};
        for (const auto& q : points_)
            b.xmin = std::min(b.xmin, q.x), b.xmax = std::max(b.xmax, q.x), b.ymin = std::min(b.ymin, q.y),
            b.ymax = std::max(b.ymax, q.y);
        double w = b.xmax - b.xmin, h = b.ymax - b.ymin;
        const double size = std::max({w, h, 1e-9});
        w = std::max(w, 1e-3 * size) * 1.1, h = std::max(h, 1e-3 * size) * 1.1;
        const double aspect = double(frame_.width) / double(frame_.height);
        if (w / h < aspect)
            w = h * aspect;
        else
            h = w / aspect;
        const double cx = 0.5 * (b.xmin + b.xmax), cy = 0.5 * (b.ymin + b.ymax);
        frame_.region = {cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2};
    }
}

} // namespace fp_mfs

namespace {

constexpr fp::ParamSpec map_item_params[] = {
    fp::param::reals("systems", "the IFSs this map belongs to (0, 1, ...: the paper's F_0, F_1)")
        .def("[0]")
        .min(0),
};

constexpr fp::ParamSpec placement_item_params[] = {
    fp::param::string(
        "at", "the polygons it is placed in: addresses of 1-based map numbers, \"5\" or \"2.5; 3.5\""),
    fp::param::string("split",
                      "vertex indices of each piece the polygon is cut into, \"0 1 2; 3 2 1\" (default: "
                      "the whole polygon, or that split of a quad for a 3-point structure)")
        .opt(),
};

constexpr fp::ParamSpec params[] = {
    fp::param::integer("width", "image width in pixels (points in SVG/PDF)").def("512").min(1).max(32768),
    fp::param::integer("height", "image height in pixels (points in SVG/PDF)").def("512").min(1).max(32768),
    fp::param::reals("view", "the drawn region [xmin, xmax, ymin, ymax] (default: the initial points' box)")
        .len(4)
        .opt(),
    fp::param::objects("maps", fp::Kind::Transform,
                       "the subdivision maps f_1 .. f_N, each with its IFSs (`systems`)")
        .min_len(1)
        .items(map_item_params),
    fp::param::reals("path", "the IFS acting at each level (ε_1, ε_2, ...); its length is the depth").min(0),
    fp::param::vec2s("points", "the initial set P_0 (default: the first map's control points)")
        .min_len(3)
        .opt(),
    fp::param::reals("order", "the order in which a polygon's vertices are joined (default: by angle)").opt(),
    fp::param::objects("placements", fp::Kind::Renderer,
                       "mfs structures placed into polygons of this one (Proposition 1, Algorithm 2)")
        .items(placement_item_params)
        .opt(),
    fp::param::boolean("draw_target", "draw this structure's own polygons (false: only the placements)")
        .def("true"),
    fp::param::string("draw", "fill, outline or points (the vertices)")
        .def("fill")
        .one_of("fill|outline|points"),
    fp::param::string("colour_by", "fixed (colour), level, ifs, map (the last) or address (the first map)")
        .def("fixed")
        .one_of("fixed|level|ifs|map|address"),
    fp::param::colour("colour", "the polygons' colour (colour_by: fixed)").def("[0, 0, 0]"),
    fp::param::colour("background", "the background").def("[1, 1, 1]"),
    fp::param::real("line_width", "outline width, point size (pixels)").def("1").above(0),
    fp::param::string("only", "draw only the polygons under this address (Algorithm 1)").opt(),
    fp::param::string("highlight", "outline the polygons at these addresses, \"2.5; 5\"").opt(),
    fp::param::string("hide", "leave out this structure's polygons at these addresses, \"2; 4\" (Example 2)")
        .opt(),
    fp::param::boolean("labels", "write each polygon's address at its centroid (Fig. 4, middle)")
        .def("false"),
    fp::param::real("label_size", "label font size (pixels)").def("14").above(0),
    fp::param::colour("mark_colour", "colour of highlights and labels").def("[0.85, 0.1, 0.1]"),
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<fp_mfs::Mfs>(fp::Kind::Renderer, "mfs",
                              "nonuniform multiple function systems of subdivision maps (paper 05)", params)
        .with_example("{width: 64, height: 64, path: [0, 0], maps: ["
                      "{type: subdivision, points: [[0, 0], [1, 0], [0.5, 0.75]], S: [2, 0, 0, 1, 1, 0, 1, "
                      "0, 1], divisor: 2}, "
                      "{type: subdivision, points: [[0, 0], [1, 0], [0.5, 0.75]], S: [1, 1, 0, 0, 2, 0, 0, "
                      "1, 1], divisor: 2}, "
                      "{type: subdivision, points: [[0, 0], [1, 0], [0.5, 0.75]], S: [1, 0, 1, 0, 1, 1, 0, "
                      "0, 2], divisor: 2}]}"))
