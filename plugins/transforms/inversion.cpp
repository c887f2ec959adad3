// inversion — star-shaped set inversion (paper 01, Sec. 3, eq. (4)).
//
// Given a star-shaped set S and a centre o in its kernel, the ray from o through p meets the
// boundary of S once, at b = o + t_b (p - o). The inverse p' lies on the same ray with
// d(o, p) d(o, p') = d(o, b)^2 (eq. (3)), that is
//
//     p' = o + t_b^2 (p - o).
//
// For a circle with o its centre, t_b = R / |p - o| and this is eq. (2). The map swaps the
// inside and the outside of S, fixes the boundary, and is an involution: the ray through p'
// is the same, its exit parameter is 1 / t_b, and o + (1 / t_b)^2 t_b^2 (p - o) = p.
// p = o gives t_b = inf and a non-finite p' (the point at infinity); renderers deal with it.
//
// The centre defaults to the shape's own centre(). A centre outside the kernel is refused:
// the ray from it could meet the boundary more than once, and the map would not be defined.
//
// apply() works in chunks of fp::chunk_size points on the stack: the directions d = p - o,
// one batched inversion_factor call on the shape per chunk (the only virtual call; it gives
// t_b^2, exactly R^2 / |d|^2 for a circle about its centre), then p' = o + t_b^2 d (the SDK's
// kernels, fixpoint/kernels.hpp).
// Inactive points get the zero direction and are left unchanged. A point within ~1e-19 of o
// in float gives an infinite factor: its image is at infinity anyway, and the renderer's
// bad-value policy restarts the chain.
//
// kernel(): with a shape that is a circle (Shape::as_circle) and o its centre, the map is
// classical circle inversion, and run() computes exactly KnownKernel's circle_inversion
// (d = p - o, s = R^2 / |d|^2 from the circle, p' = o + s d; contains() is the circle's
// |d|^2 < R^2): a renderer may then run it in its own fused loop with the same bits.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/kernels.hpp>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace {

constexpr fp::ParamSpec params[] = {
    fp::param::object("shape", fp::Kind::Shape, "the star-shaped set S to invert in"),
    fp::param::vec2("centre", "centre of inversion o, strictly inside the kernel of the shape; default: the "
                              "shape's own centre")
        .opt(),
};

class Inversion final : public fp::Transform {
public:
    explicit Inversion(const fp::ParamBag& p) : shape_(p.object<fp::Shape>("shape")) {
        o_ = p.has("centre") ? p.vec2("centre") : shape_->centre();
        if (!shape_->in_kernel(o_))
            throw fp::ParamError("centre", "inversion centre (" + fp::number_text(o_.x) + ", " +
                                               fp::number_text(o_.y) +
                                               ") is outside the kernel of the shape");
    }

    void apply(fp::Points<float> p, fp::Mask mask) const override { run(p, mask); }
    void apply(fp::Points<double> p, fp::Mask mask) const override { run(p, mask); }

    bool has_region() const override { return true; }
    void contains(fp::Points<const float> p, unsigned char* out) const override { shape_->inside(p, out); }
    void contains(fp::Points<const double> p, unsigned char* out) const override { shape_->inside(p, out); }
    std::vector<fp::Vec2> region_outline(std::size_t samples) const override {
        return shape_->outline(samples);
    }
    std::optional<fp::Vec2> region_centre() const override { return o_; }
    bool is_involution() const override { return true; }

    fp::KnownKernel kernel() const override {
        fp::Vec2 c;
        double r2 = 0;
        // Bit for bit (a centre of -0 against the circle's +0 would differ in zero signs).
        auto same = [](double a, double b) {
            return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
        };
        if (!shape_->as_circle(c, r2) || !same(c.x, o_.x) || !same(c.y, o_.y)) return {};
        return {fp::KnownKernel::Kind::circle_inversion, c.x, c.y, r2};
    }

    fp::Box sample_domain() const override {
        const fp::Box b = shape_->bounds();
        const double w = b.xmax - b.xmin, h = b.ymax - b.ymin;
        return {b.xmin - w, b.xmax + w, b.ymin - h, b.ymax + h};
    }

private:
    template <class T>
    void run(fp::Points<T> p, fp::Mask mask) const {
        const T ox = T(o_.x), oy = T(o_.y);
        T dx[fp::chunk_size], dy[fp::chunk_size], t[fp::chunk_size];
        for (std::size_t begin = 0; begin < p.n; begin += fp::chunk_size) {
            const std::size_t n = std::min(fp::chunk_size, p.n - begin);
            const fp::Points<T> c = p.sub(begin, n);
            const unsigned char* m = mask ? mask + begin : nullptr;
            if (!fp::kernels::directions(ox, oy, fp::Points<const T>{c.x, c.y, n}, m, dx, dy)) continue;
            shape_->inversion_factor(o_, fp::Points<const T>{dx, dy, n}, t);
            fp::kernels::scale_from(ox, oy, c, m, t);
        }
    }

    std::shared_ptr<const fp::Shape> shape_;
    fp::Vec2 o_;
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<Inversion>(fp::Kind::Transform, "inversion",
                            "star-shaped set inversion p' = o + t_b^2 (p - o) (paper 01, eq. (4))", params)
        .with_example("{shape: {type: circle, centre: [0, 0], radius: 1}}"))
