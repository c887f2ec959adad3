// `fixpoint symmetry` (host/symmetry.hpp): which plane-group operations an image keeps.
//
// Coordinates. The operations act on the plane about its origin, with paper 04's lattices: the
// square lattice 2 pi Z^2 of p1 ... p4g (eq. (1)) and the hexagonal lattice
// 2 pi Z (1, 0) + 2 pi Z (1/2, sqrt 3 / 2) of p3 ... p6m (eqs. (7), (8)), with the generators
// of plugins/transforms/wallpaper_groups.hpp (e.g. cm = the mirror (x, -y) and the centring
// (x + pi, y + pi)). Pixels map to the plane by the region of the image's recipe (`area`: pixel 0
// at xmin and W - 1 at xmax, as orbit-trap draws; `view`: cells, as chaos-game bins).
//
// Score. The picture is first smoothed (`smooth` passes of the binomial filter [1 2 1] / 4 in
// each direction, default 1: a Gaussian of about 0.7 pixels). Then for an operation g and every
// pixel p whose image g(p) falls inside the picture (the square of pixel centres), the colour I(p)
// is compared with the picture at g(p); the score is the fraction of these pixels that agree. A
// pixel agrees when every channel (RGB, the alpha left out) of I(p) is within `tolerance` of the
// bilinear value at g(p), or of one of the four pixels around g(p).
//   Why so: g(p) seldom falls on a pixel centre (a rotation by 120 degrees never does), and the
// orbit-trap patterns have sharp edges and detail finer than a pixel, where their orbits are
// long and chaotic. At an edge the bilinear value mixes two colours, neither of which is the
// pattern's: a pixel on either side of the edge is what a symmetric pattern gives. Detail finer
// than a pixel differs between p and g(p) point by point (two nearby sample points, or two
// floating-point roundings of the same orbit, part after tens of steps) but not on average: the
// smoothing compares what the picture resolves. Measured on Fig. 5(a) (161 x 161, 8 samples),
// the 3-fold rotation scores 0.81 without smoothing and 0.97 with one pass (two: 0.97; one
// sample per pixel and no smoothing: 0.67), while the same rotation of Fig. 5(e), broken, rises
// only from 0.24 to 0.37 (two: 0.41): a broken operation still scores low, since away from edges
// all four neighbours differ.
//   A fraction (rather than a correlation) because it reads directly ("97 % of the pixels map
// onto their own colour"), does not depend on the image's contrast, and tells one stray region
// from a broken symmetry. An operation that keeps fewer than 100 pixels in the picture (a
// translation by a period in a zoomed image) is not measured ("n/a"), and a group that needs it
// is not decided.
//   With `other` (--against) the pixels of the image are compared with the picture at g(p) in
// another image with its own frame: a zoom against a wider render tests self-similarity at full
// resolution in both (within one image, the magnified copy would be a few pixels wide).
//
// Thresholds. Kept: score >= 0.85 (default, --threshold); tolerance 0.1 of full scale per channel
// (default, --tolerance). Measured on every config of configs/orbit-trap/ at 161 x 161 pixels,
// 8 samples: exact symmetries score 0.99-1.0 (grid-aligned ones 1.0), the 3-fold rotations of the
// p3m1 maps 0.97; broken operations score 0.1-0.5, with two intermediate cases, both genuinely
// broken in part: the mirror of Fig. 7(c) (0.69; overlapping traps) and the rotation by 120
// degrees of Fig. 5(f) (0.66; its round trap at the origin colours much of the picture alike).
// The hexagonal groups' maps are reduced mod 2 pi on the SQUARE lattice, which their rotations by
// 120 and 60 degrees do not preserve (wallpaper_groups.hpp): the reduced point of a rotated orbit
// differs from the rotated reduced point by a square-lattice vector, which is not a period of the
// hexagonal map, so a few % (up to about 4 %) of the pixels of a p3m1 pattern do not keep the
// 3-fold rotation. The threshold 0.85 leaves room for that; the mirrors and translations of those
// maps are exact.
//
// Largest group: among the groups whose operations are all kept, the one with the most
// operations per unit area of the plane (a proper supergroup always has more), ties to the
// earlier in the list; likewise the rosette (point) group about the origin by its order.
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/tools/symmetry.hpp>
#include <fixpoint/text.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

namespace fp::host {

namespace {

constexpr double pi = std::numbers::pi;
/// Fewer pixels than this (a 10 x 10 patch) compared: the operation is not measured.
constexpr std::size_t min_compared = 100;

/// The numbers of a YAML flow list of finite numbers; false when `text` is not one.
bool parse_numbers(const std::string& text, const std::string& source, std::vector<double>& out) {
    CNode n;
    try {
        n = parse_yaml(text, source);
    } catch (const InputError&) {
        return false;
    }
    if (!n.is_seq()) return false;
    out.clear();
    for (const CNode& c : n.items) {
        char* end = nullptr;
        const double v = c.is_scalar() && !c.scalar.empty() ? std::strtod(c.scalar.c_str(), &end) : NAN;
        if (!end || *end || !std::isfinite(v)) return false;
        out.push_back(v);
    }
    return true;
}

std::string fmt(double v, int digits = 4) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

std::string json_string(const std::string& s) {
    std::string r = "\"";
    for (char ch : s) {
        const unsigned char u = static_cast<unsigned char>(ch);
        if (ch == '"' || ch == '\\')
            r += '\\', r += ch;
        else if (u < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", u);
            r += buf;
        } else
            r += ch;
    }
    return r + "\"";
}

const PlaneOp* find_op(const std::vector<OpScore>& ops, const std::string& id, const OpScore** score) {
    for (const auto& s : ops)
        if (s.op.id == id) {
            *score = &s;
            return &s.op;
        }
    *score = nullptr;
    return nullptr;
}

std::vector<GroupResult> judge(const std::vector<GroupDef>& defs, const std::vector<OpScore>& ops,
                               const std::string& only) {
    std::vector<GroupResult> out;
    for (const auto& g : defs) {
        if (!only.empty() && g.name != only) continue;
        GroupResult r;
        r.group = &g;
        r.kept = true;
        r.worst = 1;
        for (const auto& id : g.ops) {
            const OpScore* s = nullptr;
            find_op(ops, id, &s);
            if (!s) throw InternalError("symmetry: group " + g.name + " names an unknown operation " + id);
            r.measured = r.measured && s->measured;
            r.kept = r.kept && s->kept;
            if (s->measured) r.worst = std::min(r.worst, s->score);
        }
        out.push_back(r);
    }
    return out;
}

const GroupDef* largest(const std::vector<GroupResult>& rs) {
    const GroupDef* best = nullptr;
    for (const auto& r : rs)
        if (r.kept && (!best || r.group->size > best->size)) best = r.group;
    return best;
}

} // namespace

Vec2 PixelFrame::to_plane(double i, double j) const {
    const Box& b = region;
    if (endpoints) {
        const double u = width > 1 ? i / (width - 1) : 0.5, v = height > 1 ? j / (height - 1) : 0.5;
        return {b.xmin + (b.xmax - b.xmin) * u, b.ymax - (b.ymax - b.ymin) * v};
    }
    return {b.xmin + (b.xmax - b.xmin) * (i + 0.5) / width, b.ymax - (b.ymax - b.ymin) * (j + 0.5) / height};
}

Vec2 PixelFrame::to_pixel(Vec2 p) const {
    const Box& b = region;
    if (endpoints)
        return {width > 1 ? (p.x - b.xmin) / (b.xmax - b.xmin) * (width - 1) : 0.0,
                height > 1 ? (b.ymax - p.y) / (b.ymax - b.ymin) * (height - 1) : 0.0};
    return {(p.x - b.xmin) / (b.xmax - b.xmin) * width - 0.5,
            (b.ymax - p.y) / (b.ymax - b.ymin) * height - 0.5};
}

const std::vector<PlaneOp>& symmetry_ops() {
    static const std::vector<PlaneOp> ops = [] {
        const double a = 2 * pi, h = std::sqrt(3.0) / 2;
        return std::vector<PlaneOp>{
            {"t(2pi,0)", "translation by (2 pi, 0): both lattices", 1, 0, 0, 1, a, 0},
            {"t(0,2pi)", "translation by (0, 2 pi): the square lattice", 1, 0, 0, 1, 0, a},
            {"t(pi,pi)", "translation by (pi, pi): the centring of cm, cmm", 1, 0, 0, 1, pi, pi},
            {"t(pi,pi*sqrt3)", "translation by 2 pi (1/2, sqrt 3 / 2): the hexagonal lattice", 1, 0, 0, 1, pi,
             a * h},
            {"r2", "rotation by 180 degrees", -1, 0, 0, -1, 0, 0},
            {"r4", "rotation by 90 degrees", 0, -1, 1, 0, 0, 0},
            {"r3", "rotation by 120 degrees", -0.5, -h, h, -0.5, 0, 0},
            {"r6", "rotation by 60 degrees", 0.5, -h, h, 0.5, 0, 0},
            {"m(x,-y)", "mirror in the x axis", 1, 0, 0, -1, 0, 0},
            {"m(-x,y)", "mirror in the y axis", -1, 0, 0, 1, 0, 0},
            {"m(y,x)", "mirror in the diagonal y = x", 0, 1, 1, 0, 0, 0},
            {"g(x+pi,-y)", "glide along the x axis", 1, 0, 0, -1, pi, 0},
            {"g(-x,y+pi)", "glide along the y axis", -1, 0, 0, 1, 0, pi},
            {"g(x+pi,pi-y)", "glide along y = pi/2 (p4g)", 1, 0, 0, -1, pi, pi},
        };
    }();
    return ops;
}

const std::vector<GroupDef>& wallpaper_groups() {
    static const std::vector<GroupDef> gs = [] {
        const std::string T1 = "t(2pi,0)", T2 = "t(0,2pi)", H2 = "t(pi,pi*sqrt3)", C = "t(pi,pi)";
        const std::string mx = "m(x,-y)", my = "m(-x,y)", gx = "g(x+pi,-y)", gy = "g(-x,y+pi)";
        const double hx = 2 / std::sqrt(3.0); // unit cells per area of the hexagonal lattice / square
        std::vector<GroupDef> v = {
            {"p1", "square", {T1, T2}, 1},
            {"p2", "square", {T1, T2, "r2"}, 2},
            {"pm", "square", {T1, T2, mx}, 2},
            {"pm", "square", {T1, T2, my}, 2},
            {"pg", "square", {T1, T2, gx}, 2},
            {"pg", "square", {T1, T2, gy}, 2},
            {"cm", "square", {T1, T2, mx, C}, 4},
            {"cm", "square", {T1, T2, my, C}, 4},
            {"pmm", "square", {T1, T2, mx, my}, 4},
            {"cmm", "square", {T1, T2, mx, my, C}, 8},
            {"pmg", "square", {T1, T2, mx, gy}, 4},
            {"pmg", "square", {T1, T2, my, gx}, 4},
            {"pgg", "square", {T1, T2, gx, gy}, 4},
            {"p4", "square", {T1, T2, "r4"}, 4},
            {"p4m", "square", {T1, T2, "r4", mx}, 8},
            {"p4g", "square", {T1, T2, "r4", "g(x+pi,pi-y)"}, 8},
            {"p1", "hexagonal", {T1, H2}, hx},
            {"p2", "hexagonal", {T1, H2, "r2"}, 2 * hx},
            {"cm", "hexagonal", {T1, H2, my}, 2 * hx},
            {"cm", "hexagonal", {T1, H2, mx}, 2 * hx},
            {"cmm", "hexagonal", {T1, H2, mx, my}, 4 * hx},
            {"p3", "hexagonal", {T1, H2, "r3"}, 3 * hx},
            {"p3m1", "hexagonal", {T1, H2, "r3", my}, 6 * hx},
            {"p31m", "hexagonal", {T1, H2, "r3", mx}, 6 * hx},
            {"p6", "hexagonal", {T1, H2, "r6"}, 6 * hx},
            {"p6m", "hexagonal", {T1, H2, "r6", mx}, 12 * hx},
        };
        return v;
    }();
    return gs;
}

const std::vector<GroupDef>& rosette_groups() {
    static const std::vector<GroupDef> gs = {
        {"C1", "", {}, 1},
        {"C2", "", {"r2"}, 2},
        {"D1", "", {"m(x,-y)"}, 2},
        {"D1", "", {"m(-x,y)"}, 2},
        {"C3", "", {"r3"}, 3},
        {"C4", "", {"r4"}, 4},
        {"D2", "", {"r2", "m(x,-y)"}, 4},
        {"C6", "", {"r6"}, 6},
        {"D3", "", {"r3", "m(x,-y)"}, 6},
        {"D3", "", {"r3", "m(-x,y)"}, 6},
        {"D4", "", {"r4", "m(x,-y)"}, 8},
        {"D6", "", {"r6", "m(x,-y)"}, 12},
    };
    return gs;
}

bool known_group(const std::string& name) {
    for (const auto* list : {&wallpaper_groups(), &rosette_groups()})
        for (const auto& g : *list)
            if (g.name == name) return true;
    return false;
}

PlaneOp parse_op(const std::string& text, const std::string& id) {
    std::vector<double> v;
    if (!parse_numbers(text, "--op", v) || (v.size() != 4 && v.size() != 6))
        throw InputError(
            "--op " + quote(text) +
            ": expected [a, b, c, d] or [a, b, c, d, tx, ty] (finite numbers: p -> [a b; c d] p + t "
            "in the plane)");
    PlaneOp op{id, "the map p -> [a b; c d] p + t given by --op " + text, v[0], v[1], v[2], v[3], 0, 0};
    if (v.size() == 6) op.tx = v[4], op.ty = v[5];
    return op;
}

Box parse_area(const std::string& text) {
    std::vector<double> v;
    if (!parse_numbers(text, "--area", v) || v.size() != 4 || !(v[0] < v[1]) || !(v[2] < v[3]))
        throw InputError(
            "--area " + quote(text) +
            ": expected [xmin, xmax, ymin, ymax], four finite numbers with xmin < xmax and ymin < ymax");
    return {v[0], v[1], v[2], v[3]};
}

PixelFrame frame_from_recipe(const std::string& recipe, int width, int height, const std::string& source) {
    CNode root;
    try {
        root = parse_yaml(recipe, source);
    } catch (const InputError&) {
        throw InputError(source + ": its recipe is not readable YAML; give the region with --area");
    }
    const CNode* r = root.is_map() ? root.find("renderer") : nullptr;
    if (!r || !r->is_map())
        throw InputError(source + ": its recipe has no renderer; give the region with --area");
    // A tile (render --tile) shows one period about the area's centre, not the area: its frame
    // is not in the recipe's numbers.
    if (const CNode* t = r->find("tile"); t && t->is_scalar() && t->scalar == "true")
        throw InputError(source + ": a tile (render --tile) shows one period, not its recipe's area; render "
                                  "the pattern without --tile to measure it");
    PixelFrame f;
    f.width = width, f.height = height;
    const CNode* reg = r->find("area");
    f.endpoints = reg != nullptr;
    if (!reg) reg = r->find("view");
    std::vector<double> v;
    bool ok = reg && reg->is_seq() && reg->items.size() == 4;
    for (std::size_t k = 0; ok && k < 4; ++k) {
        const CNode& c = reg->items[k];
        char* end = nullptr;
        const double x = c.is_scalar() && !c.scalar.empty() ? std::strtod(c.scalar.c_str(), &end) : NAN;
        ok = end && !*end && std::isfinite(x);
        v.push_back(x);
    }
    if (!ok || !(v[0] < v[1]) || !(v[2] < v[3]))
        throw InputError(
            source + ": its recipe gives no region (renderer.area or renderer.view); give it with --area");
    f.region = {v[0], v[1], v[2], v[3]};
    // The recipe's size: an image of another size is not one render of it (a contact sheet, the
    // sets beside the fractal), and its region would be wrong.
    const auto size = [&](const char* key) {
        const CNode* n = r->find(key);
        return n && n->is_scalar() ? std::atoll(n->scalar.c_str()) : -1LL;
    };
    const long long rw = size("width"), rh = size("height");
    if (rw > 0 && rh > 0 && (rw != width || rh != height))
        throw InputError(source + ": the image is " + std::to_string(width) + "x" + std::to_string(height) +
                         " but its recipe renders " + std::to_string(rw) + "x" + std::to_string(rh) +
                         " (a contact sheet, or sets beside the fractal?): give the region with --area");
    return f;
}

PixelFrame default_frame(int width, int height) {
    PixelFrame f;
    f.width = width, f.height = height;
    const double half_w = 2 * pi, half_h = width > 1 ? half_w * (height - 1) / (width - 1) : half_w;
    f.region = {-half_w, half_w, -half_h, half_h};
    f.endpoints = true;
    return f;
}

OpScore score_op(const Image& img, const PixelFrame& f, const PlaneOp& op, const SymmetryOptions& o,
                 const Image* other, const PixelFrame* other_frame) {
    OpScore s;
    s.op = op;
    const Image& to = other ? *other : img;
    const PixelFrame& tf = other ? *other_frame : f;
    const int W = to.width, H = to.height, nc = std::min({img.channels, to.channels, 3});
    const auto px = [&](int i, int j) { return to.pixels.data() + (std::size_t(j) * W + i) * to.channels; };
    const auto own = [&](int i, int j) {
        return img.pixels.data() + (std::size_t(j) * img.width + i) * img.channels;
    };
    const auto close = [&](const float* a, const float* b) {
        for (int k = 0; k < nc; ++k)
            if (std::fabs(double(a[k]) - double(b[k])) > o.tolerance) return false;
        return true;
    };
    std::size_t agree = 0;
    for (int j = 0; j < img.height; ++j)
        for (int i = 0; i < img.width; ++i) {
            const Vec2 q = tf.to_pixel(op(f.to_plane(i, j)));
            // Inside the square of pixel centres (a hair of slack for rounding).
            constexpr double eps = 1e-9;
            if (!(q.x >= -eps && q.x <= W - 1 + eps && q.y >= -eps && q.y <= H - 1 + eps)) continue;
            const double qx = std::clamp(q.x, 0.0, double(W - 1)), qy = std::clamp(q.y, 0.0, double(H - 1));
            const int i0 = std::min(int(qx), std::max(W - 2, 0)), j0 = std::min(int(qy), std::max(H - 2, 0));
            const int i1 = std::min(i0 + 1, W - 1), j1 = std::min(j0 + 1, H - 1);
            const double fx = qx - i0, fy = qy - j0;
            const float* c00 = px(i0, j0);
            const float* c10 = px(i1, j0);
            const float* c01 = px(i0, j1);
            const float* c11 = px(i1, j1);
            float bil[3];
            for (int k = 0; k < nc; ++k)
                bil[k] = float((1 - fy) * ((1 - fx) * c00[k] + fx * c10[k]) +
                               fy * ((1 - fx) * c01[k] + fx * c11[k]));
            const float* a = own(i, j);
            ++s.compared;
            if (close(a, bil) || close(a, c00) || close(a, c10) || close(a, c01) || close(a, c11)) ++agree;
        }
    s.measured = s.compared >= min_compared;
    s.score = s.compared ? double(agree) / double(s.compared) : 0;
    s.kept = s.measured && s.score >= o.threshold;
    return s;
}

namespace {
/// The picture smoothed by `passes` binomial [1 2 1] / 4 filters in each direction (edges
/// clamped), RGB only.
Image smoothed(const Image& in, int passes) {
    Image out;
    out.width = in.width, out.height = in.height, out.channels = std::min(in.channels, 3);
    const int W = in.width, H = in.height, nc = out.channels;
    out.pixels.resize(std::size_t(W) * H * nc);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i)
            for (int k = 0; k < nc; ++k)
                out.pixels[(std::size_t(j) * W + i) * nc + k] =
                    in.pixels[(std::size_t(j) * W + i) * in.channels + k];
    std::vector<float> tmp(out.pixels.size());
    for (int pass = 0; pass < passes; ++pass) {
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i)
                for (int k = 0; k < nc; ++k) {
                    const auto at = [&](int ii) {
                        return out.pixels[(std::size_t(j) * W + std::clamp(ii, 0, W - 1)) * nc + k];
                    };
                    tmp[(std::size_t(j) * W + i) * nc + k] =
                        0.25f * at(i - 1) + 0.5f * at(i) + 0.25f * at(i + 1);
                }
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i)
                for (int k = 0; k < nc; ++k) {
                    const auto at = [&](int jj) {
                        return tmp[(std::size_t(std::clamp(jj, 0, H - 1)) * W + i) * nc + k];
                    };
                    out.pixels[(std::size_t(j) * W + i) * nc + k] =
                        0.25f * at(j - 1) + 0.5f * at(j) + 0.25f * at(j + 1);
                }
    }
    return out;
}
} // namespace

SymmetryReport measure_symmetry(const Image& img0, const PixelFrame& f, const SymmetryOptions& o,
                                const std::string& only_group, const std::vector<PlaneOp>& extra,
                                const Image* other0, const PixelFrame* other_frame) {
    const Image img = smoothed(img0, o.smooth);
    Image other_img;
    if (other0) other_img = smoothed(*other0, o.smooth);
    const Image* other = other0 ? &other_img : nullptr;
    SymmetryReport r;
    // The operations to score: every one, or those of the named group's variants.
    std::vector<std::string> wanted;
    if (!only_group.empty())
        for (const auto* list : {&wallpaper_groups(), &rosette_groups()})
            for (const auto& g : *list)
                if (g.name == only_group)
                    for (const auto& id : g.ops)
                        if (std::find(wanted.begin(), wanted.end(), id) == wanted.end()) wanted.push_back(id);
    for (const auto& op : symmetry_ops())
        if (only_group.empty() || std::find(wanted.begin(), wanted.end(), op.id) != wanted.end())
            r.ops.push_back(score_op(img, f, op, o, other, other_frame));
    for (const auto& op : extra) r.ops.push_back(score_op(img, f, op, o, other, other_frame));
    r.groups = judge(wallpaper_groups(), r.ops, only_group);
    r.rosettes = judge(rosette_groups(), r.ops, only_group);
    r.largest = largest(r.groups);
    r.largest_rosette = largest(r.rosettes);
    return r;
}

bool group_kept(const SymmetryReport& r, const std::string& name) {
    for (const auto* list : {&r.groups, &r.rosettes})
        for (const auto& g : *list)
            if (g.group->name == name && g.kept) return true;
    return false;
}

std::string symmetry_text(const SymmetryReport& r, const PixelFrame& f, const SymmetryOptions& o,
                          const std::string& only_group) {
    std::string t;
    t += "region [" + fmt(f.region.xmin) + ", " + fmt(f.region.xmax) + ", " + fmt(f.region.ymin) + ", " +
         fmt(f.region.ymax) + "], " + std::to_string(f.width) + "x" + std::to_string(f.height) +
         " pixels; kept: score >= " + fmt(o.threshold, 3) + " (colours within " + fmt(o.tolerance, 3) + ")\n";
    char line[512];
    std::snprintf(line, sizeof line, "%-16s %-7s %-9s %-4s %s\n", "operation", "score", "pixels", "kept", "");
    t += line;
    for (const auto& s : r.ops) {
        std::snprintf(line, sizeof line, "%-16s %-7s %-9zu %-4s %s\n", s.op.id.c_str(),
                      s.measured ? fmt(s.score, 4).c_str() : "n/a", s.compared,
                      !s.measured ? "n/a"
                      : s.kept    ? "yes"
                                  : "no",
                      s.op.what.c_str());
        t += line;
    }
    const auto list = [&](const std::vector<GroupResult>& gs) {
        std::string kept, undecided;
        for (const auto& g : gs) {
            const std::string n =
                g.group->name + (g.group->lattice.empty() ? "" : " (" + g.group->lattice + ")");
            if (g.kept && kept.find(n) == std::string::npos) kept += (kept.empty() ? "" : ", ") + n;
            if (!g.measured && undecided.find(n) == std::string::npos)
                undecided += (undecided.empty() ? "" : ", ") + n;
        }
        return std::make_pair(kept, undecided);
    };
    const auto [wk, wu] = list(r.groups);
    const auto [rk, ru] = list(r.rosettes);
    if (!only_group.empty()) {
        const bool kept = group_kept(r, only_group);
        t += only_group + ": " + (kept ? "kept" : "not kept") +
             (!kept && !wu.empty() ? " (not measurable here: " + wu + ")" : "") + "\n";
        return t;
    }
    t += "wallpaper groups kept: " + (wk.empty() ? std::string("none") : wk) + "\n";
    if (!wu.empty())
        t += "undecided (they need an operation marked n/a, too large for the picture): " + wu + "\n";
    t += "largest wallpaper group: " +
         (r.largest    ? r.largest->name + " (" + r.largest->lattice + " lattice)"
          : wu.empty() ? std::string("none")
                       : std::string("none decided")) +
         "\n";
    t +=
        "point group about the origin: " + (r.largest_rosette ? r.largest_rosette->name : std::string("C1")) +
        "\n";
    return t;
}

std::string symmetry_json(const SymmetryReport& r, const PixelFrame& f, const SymmetryOptions& o,
                          const std::string& only_group, const std::string& source) {
    std::string j = "{\"image\": " + json_string(source) + ", \"width\": " + std::to_string(f.width) +
                    ", \"height\": " + std::to_string(f.height) + ", \"region\": [" + fmt(f.region.xmin, 10) +
                    ", " + fmt(f.region.xmax, 10) + ", " + fmt(f.region.ymin, 10) + ", " +
                    fmt(f.region.ymax, 10) + "], \"threshold\": " + fmt(o.threshold, 6) +
                    ", \"tolerance\": " + fmt(o.tolerance, 6) + ",\n \"operations\": [";
    for (std::size_t k = 0; k < r.ops.size(); ++k) {
        const auto& s = r.ops[k];
        j += std::string(k ? ",\n  " : "\n  ") + "{\"id\": " + json_string(s.op.id) + ", \"map\": [" +
             fmt(s.op.a, 10) + ", " + fmt(s.op.b, 10) + ", " + fmt(s.op.c, 10) + ", " + fmt(s.op.d, 10) +
             ", " + fmt(s.op.tx, 10) + ", " + fmt(s.op.ty, 10) +
             "], \"score\": " + (s.measured ? fmt(s.score, 6) : std::string("null")) +
             ", \"pixels\": " + std::to_string(s.compared) + ", \"kept\": " + (s.kept ? "true" : "false") +
             "}";
    }
    j += "],\n \"groups\": [";
    bool first = true;
    for (const auto* list : {&r.groups, &r.rosettes})
        for (const auto& g : *list) {
            j += std::string(first ? "\n  " : ",\n  ") + "{\"name\": " + json_string(g.group->name) +
                 ", \"lattice\": " + (g.group->lattice.empty() ? "null" : json_string(g.group->lattice)) +
                 ", \"kept\": " + (g.kept ? "true" : "false") +
                 ", \"measured\": " + (g.measured ? "true" : "false") + "}";
            first = false;
        }
    j += "],\n \"largest\": " + (r.largest ? json_string(r.largest->name) : std::string("null")) +
         ", \"largest_lattice\": " + (r.largest ? json_string(r.largest->lattice) : std::string("null")) +
         ", \"point_group\": " + json_string(r.largest_rosette ? r.largest_rosette->name : "C1");
    if (!only_group.empty())
        j += ", \"group\": " + json_string(only_group) +
             ", \"group_kept\": " + (group_kept(r, only_group) ? "true" : "false");
    return j + "}\n";
}

} // namespace fp::host
