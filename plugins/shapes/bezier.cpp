// bezier — a star-shaped set bounded by a closed piecewise Bézier curve (paper 01, Sec. 3:
// "when we model the boundary of the star-shaped set with polynomial curves, appropriate
// algorithms exist in the literature for finding the intersection with a ray and an
// inclusion test").
//
// The curve: with degree n (2, quadratic, or 3, cubic), `points` P_0 .. P_{N-1} (N a
// multiple of n) make N / n segments; segment k has the Bernstein control points P_{nk} ..
// P_{nk+n}, the last segment ending at P_0, so the curve is closed and passes through every
// n-th point. It is normalised to counter-clockwise (signed area by Green's theorem, exact
// for polynomials), so that the set lies to the left.
//
// Kernel (exact test, for the default centre and for every centre of inversion): o sees the
// whole boundary, each ray from o meeting it once, exactly when the polar angle of b(t) - o
// strictly increases along the curve and turns once in all. The angle increases where
//     g(t) = cross(b(t) - o, b'(t)) > 0,
// a polynomial of degree 2n - 1 per segment, affine in o. It is written in the Bernstein
// basis (the product of b - o and b'), whose coefficients bound it: all of them above a
// tolerance prove g above it on the interval, an end coefficient is g's value there, and
// otherwise the interval is halved by de Casteljau's rule (bezier/geometry.hpp). The
// tolerance asks o to stay 1e-12 of the set's size away from every tangent line (as the
// polygons ask of their edge lines). The turn is then counted on the ray pieces below: it must
// be one full turn (a curve that winds twice round o crosses itself). A centre that fails
// either is refused, naming the segment and t where the tangent passes on its wrong side.
// The default centre is the centroid of the kernel of the tangent lines sampled 33 times per
// segment (fewer past 128 segments), a polygon holding the true kernel, whose centroid is
// checked exactly like any centre, and refused, asking for `centre`, in the rare set where it
// falls outside.
//
// Ray exit from o, by exact root isolation: the curve is cut, as seen from o, into pieces
// whose control points lie in the sector between the rays to their two ends, of less than a
// quarter turn (halving a part until it does). A piece lies in its control hull, so its angle
// stays in the sector: with the angle increasing, a ray meets the piece whose sector holds its
// direction once, and no other piece. Along the piece h(t) = cross(d, b(t) - o), a cubic (the
// control points' crosses with d are its Bernstein coefficients), goes from <= 0 to >= 0
// exactly once: its root, refined by safeguarded Illinois (shapes/lanes-inl.hpp) to 4 ulps
// of the batch's type, gives the exit t = (b(t*) - o) . d / |d|^2. The pieces are found once
// per origin: those of the centre at construction, those of another centre of inversion on its
// first batch (kept, shared between threads, for the next).
//
// Inside test, by winding number: the signed crossings of the ray from the point to +x, with
// the curve cut where y'(t) = 0 so that y is monotonic on every piece and the row y = py
// crosses a piece at most once (half-open in y, as the polygons count, so a row through a
// piece's end counts once). A point left of a piece's control hull crosses it if its row
// does, one right of it never; otherwise the crossing's x comes from the root of y(t) = py on
// the piece. Points outside the control points' box are outside without a piece, and bounds
// answer first for most others: each ray piece about the centre lies in its control hull, so
// the distance from the centre to the curve over the piece's sector lies between the hull's
// nearest edge and farthest corner. Each of 256 equal sectors of the pseudo-angle about the
// centre takes the widest bounds of the pieces it overlaps (its ends widened by 1e-9, so that a
// point's rounded pseudo-angle never escapes them); a point nearer than them is inside, one
// farther is outside, and only the points between count crossings (the same answers).
//
// Batches run per SIMD target, one point or direction per lane (bezier/kernels.cpp), in
// double for either type; a lane takes the scalar method's steps, so the bits do not depend
// on the lane count.
#include "bezier/geometry.hpp"
#include "kernel_clip.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace {

using fp_bezier::Seg;

constexpr fp::ParamSpec params[] = {
    fp::param::vec2s(
        "points", "control points of the closed curve: with degree n, segment k runs from point n k through "
                  "the next n - 1 to point n k + n (the last segment ends at the first point), so their "
                  "number is a multiple of n")
        .min_len(2),
    fp::param::integer("degree", "2: quadratic segments, 3: cubic").def("3").min(2).max(3),
    fp::param::vec2("centre",
                    "a point of the kernel, the default centre of inversion (by default the centroid of the "
                    "kernel of the sampled tangents)")
        .opt(),
};

std::string point_text(fp::Vec2 p) { return "(" + fp::number_text(p.x) + ", " + fp::number_text(p.y) + ")"; }

std::string short_num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

class Bezier final : public fp::Shape {
public:
    explicit Bezier(const fp::ParamBag& p) {
        const int n = int(p.integer("degree"));
        std::vector<fp::Vec2> pts = p.vec2s("points");
        const std::size_t count = pts.size();
        if (count % std::size_t(n) != 0)
            throw fp::ParamError("points", "a closed curve of degree " + std::to_string(n) +
                                               " takes a multiple of " + std::to_string(n) +
                                               " control points (" + std::to_string(n) +
                                               " per segment), got " + std::to_string(count));
        fp::Box b{pts[0].x, pts[0].x, pts[0].y, pts[0].y};
        for (const auto& q : pts)
            b.xmin = std::min(b.xmin, q.x), b.xmax = std::max(b.xmax, q.x), b.ymin = std::min(b.ymin, q.y),
            b.ymax = std::max(b.ymax, q.y);
        box_ = b;
        size_ = std::max(b.xmax - b.xmin, b.ymax - b.ymin);
        for (std::size_t i = 0; i < count; ++i) {
            const fp::Vec2 a = pts[i], c = pts[(i + 1) % count];
            if (std::hypot(c.x - a.x, c.y - a.y) <= 1e-12 * size_)
                throw fp::ParamError("points", "control points " + std::to_string(i) + " and " +
                                                   std::to_string((i + 1) % count) + " coincide at " +
                                                   point_text(a) +
                                                   ": a segment's tangent would vanish there");
        }
        // Everything is kept relative to the middle of the box, for precision far from 0.
        ref_ = {(b.xmin + b.xmax) / 2, (b.ymin + b.ymax) / 2};
        for (std::size_t k = 0; k < count / std::size_t(n); ++k) {
            Seg s;
            s.n = n;
            for (int i = 0; i <= n; ++i)
                s.p[i] = fp_bezier::sub(pts[(std::size_t(n) * k + std::size_t(i)) % count], ref_);
            segs_.push_back(s);
        }
        const double area = fp_bezier::twice_area(segs_) / 2;
        if (!(std::abs(area) > 1e-12 * size_ * size_))
            throw fp::ParamError("points", "bezier curve encloses no area");
        if (area < 0) { // reversed: the segments in the other order, each read backwards
            std::reverse(segs_.begin(), segs_.end());
            for (Seg& s : segs_) std::reverse(s.p.begin(), s.p.begin() + s.n + 1);
        }
        for (const Seg& s : segs_) polys_.push_back(fp_bezier::power(s));
        fp::Box rel{b.xmin - ref_.x, b.xmax - ref_.x, b.ymin - ref_.y, b.ymax - ref_.y};
        ypieces_ = fp_bezier::y_pieces(segs_, polys_, ref_, rel, 1e-12 * size_);

        const bool given = p.has("centre");
        centre_ = given ? p.vec2("centre") : sampled_kernel_centroid();
        const std::string why = kernel_failure(centre_);
        if (!why.empty()) {
            if (given)
                throw fp::ParamError("centre", "bezier set's centre " + point_text(centre_) +
                                                   " is not in its kernel: " + why);
            throw fp::ParamError("points",
                                 "bezier set's default centre " + point_text(centre_) +
                                     " (the centroid of its sampled kernel) is not in its kernel: " + why +
                                     "; give a centre in the kernel");
        }
        double turn = 0;
        centre_pieces_ = *fp_bezier::ray_pieces(segs_, polys_, fp_bezier::sub(centre_, ref_), turn);
        set_sectors();
    }

    fp::Vec2 centre() const override { return centre_; }
    bool in_kernel(fp::Vec2 o) const override { return kernel_failure(o).empty(); }
    fp::Box bounds() const override { return box_; }

    std::vector<fp::Vec2> outline(std::size_t samples) const override {
        const std::size_t per =
            std::max<std::size_t>(4, (std::max<std::size_t>(samples, 16) + segs_.size() - 1) / segs_.size());
        std::vector<fp::Vec2> out;
        for (const auto& q : polys_)
            for (std::size_t j = 0; j < per; ++j) {
                const fp::Vec2 v = fp_bezier::at(q, double(j) / double(per));
                out.push_back({v.x + ref_.x, v.y + ref_.y});
            }
        return out;
    }

    void inside(fp::Points<const float> p, unsigned char* out) const override {
        fp_bezier::inside(ypieces_, p, out);
    }
    void inside(fp::Points<const double> p, unsigned char* out) const override {
        fp_bezier::inside(ypieces_, p, out);
    }
    void ray_exit(fp::Vec2 o, fp::Points<const float> d, float* t) const override { ray_t(o, d, t); }
    void ray_exit(fp::Vec2 o, fp::Points<const double> d, double* t) const override { ray_t(o, d, t); }

private:
    template <class T>
    void ray_t(fp::Vec2 o, fp::Points<const T> d, T* t) const {
        if (o.x == centre_.x && o.y == centre_.y) return fp_bezier::ray(centre_pieces_, d, t);
        const fp::Vec2 w = fp_bezier::sub(o, ref_);
        std::shared_ptr<const fp_bezier::RayPieces> r = other_.load();
        if (!r || r->o.x != w.x || r->o.y != w.y) {
            // Once per new origin (a centre of inversion off the set's centre), not per batch.
            double turn = 0;
            auto built = fp_bezier::ray_pieces(segs_, polys_, w, turn);
            if (!built) { // (o outside the kernel, against the contract: no exit)
                std::fill(t, t + d.n, std::numeric_limits<T>::infinity());
                return;
            }
            r = std::make_shared<const fp_bezier::RayPieces>(std::move(*built));
            other_.store(r);
        }
        fp_bezier::ray(*r, d, t);
    }

    /// Why o is not in the kernel (the comment at the top), or "" when it is.
    std::string kernel_failure(fp::Vec2 o) const {
        const fp::Vec2 w = fp_bezier::sub(o, ref_);
        for (std::size_t k = 0; k < segs_.size(); ++k) {
            const Seg& s = segs_[k];
            double vmax = 0;
            for (int j = 0; j < s.n; ++j)
                vmax = std::max(vmax, s.n * std::hypot(s.p[j + 1].x - s.p[j].x, s.p[j + 1].y - s.p[j].y));
            if (const auto t = fp_bezier::tangent_failure(s, w, 1e-12 * size_ * vmax))
                return "the tangent of segment " + std::to_string(k) + " at t = " + short_num(*t) +
                       " passes on its wrong side (or through it), so a ray from it would meet the curve "
                       "more than once";
        }
        double turn = 0;
        if (!fp_bezier::ray_pieces(segs_, polys_, w, turn)) return "it lies too close to the curve";
        const double turns = turn / (2 * std::numbers::pi);
        if (!(std::abs(turns - 1) < 0.5))
            return "the curve turns " + short_num(std::round(turns)) +
                   " times round it, so it crosses itself";
        return "";
    }

    /// The inside test's sector bounds (YPieces): from ray pieces about the centre whose
    /// distance bounds are within 2% of each other (up to 1024 of them), a sector taking the
    /// widest bounds of the pieces its pseudo-angles overlap (its ends widened by 1e-9).
    void set_sectors() {
        double turn = 0;
        const auto r = fp_bezier::ray_pieces(segs_, polys_, fp_bezier::sub(centre_, ref_), turn, 0.02);
        if (!r) return;
        const std::size_t S = fp_bezier::sector_count;
        ypieces_.c = r->o;
        ypieces_.sectors.assign(2 * S, 0);
        for (std::size_t j = 0; j < S; ++j) {
            const double lo = -2 + 4 * double(j) / double(S) - 1e-9,
                         hi = -2 + 4 * double(j + 1) / double(S) + 1e-9;
            double in2 = std::numeric_limits<double>::infinity(), out2 = 0;
            for (std::size_t i = 0; i < r->n; ++i) {
                const double a = r->key[i], b = i + 1 < r->n ? r->key[i + 1] : r->key[0] + 4;
                if ((a <= hi && b >= lo) || (a <= hi + 4 && b >= lo + 4))
                    in2 = std::min(in2, r->in2[i]), out2 = std::max(out2, r->out2[i]);
            }
            ypieces_.sectors[2 * j] = in2 == std::numeric_limits<double>::infinity() ? 0 : in2;
            ypieces_.sectors[2 * j + 1] = out2 == 0 ? std::numeric_limits<double>::infinity() : out2;
        }
    }

    /// The centroid of the kernel of the tangent lines at 33 points of each segment (fewer, down
    /// to 3, past 128 segments: the clipping costs the lines times the kernel's vertices).
    fp::Vec2 sampled_kernel_centroid() const {
        std::vector<fp_shapes::Line> lines;
        const int steps = int(std::clamp<std::size_t>(4096 / polys_.size(), 2, 32));
        for (const auto& q : polys_)
            for (int j = 0; j <= steps; ++j) {
                const double t = double(j) / steps;
                const fp::Vec2 a = fp_bezier::at(q, t), e = fp_bezier::tangent(q, t);
                if (e.x != 0 || e.y != 0) lines.push_back({{a.x + ref_.x, a.y + ref_.y}, e});
            }
        const double g = size_;
        std::vector<fp::Vec2> k{{box_.xmin - g, box_.ymin - g},
                                {box_.xmax + g, box_.ymin - g},
                                {box_.xmax + g, box_.ymax + g},
                                {box_.xmin - g, box_.ymax + g}};
        k = fp_shapes::clip_by_lines(k, lines);
        double a2 = 0;
        for (std::size_t i = 0; i < k.size(); ++i) a2 += fp_bezier::cross(k[i], k[(i + 1) % k.size()]);
        if (k.size() < 3 || !(a2 > 1e-12 * size_ * size_))
            throw fp::ParamError(
                "points",
                "bezier set is not star-shaped: no point sees the whole curve (its kernel is empty)");
        return fp_shapes::centroid(k);
    }

    std::vector<Seg> segs_;              ///< counter-clockwise, relative to ref_
    std::vector<fp_bezier::Poly> polys_; ///< their power bases
    fp_bezier::YPieces ypieces_;
    fp_bezier::RayPieces centre_pieces_;
    mutable std::atomic<std::shared_ptr<const fp_bezier::RayPieces>> other_;
    fp::Box box_{};
    fp::Vec2 ref_{}, centre_{};
    double size_ = 0;
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<Bezier>(fp::Kind::Shape, "bezier",
                         "a star-shaped set bounded by a closed piecewise Bézier curve (quadratic or cubic)",
                         params)
        .with_example("{points: [[1, 0], [1, 0.6], [0.6, 1], [0, 1], [-0.6, 1], [-1, 0.6], [-1, 0], "
                      "[-1, -0.6], [-0.6, -1], [0, -1], [0.6, -1], [1, -0.6]]}"))
