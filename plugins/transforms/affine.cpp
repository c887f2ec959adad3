// affine: an affine map of the plane, the maps of an iterated function system (paper 02
// Sec. 6, Fig. 5: the twig of four affine maps under Picard and Ishikawa).
//
//     x' = a x + b y + e,
//     y' = c x + d y + f,
//
// written either as `matrix: [a, b, c, d]` (row major) with `offset: [e, f]` (default
// [0, 0]), or as the six `coefficients: [a, b, c, d, e, f]` (the order of the IFS tables of
// Barnsley's Fractals Everywhere). Exactly one of the two forms: both, neither, or an offset
// beside coefficients are refused (ParamError), since a silently ignored offset would hide a
// mistake. A singular matrix is allowed (a projection is a valid IFS map).
//
// The map has no set (has_region() is false), so the chaos game applies no inversion rules
// to it (`inversion_rules: auto`). is_involution() is true exactly when the double-precision
// coefficients satisfy A^2 = I and A o + o = 0 exactly (point reflections, mirror lines);
// schu then takes its cheap form. Per point: 4 multiplications and 4 additions, evaluated in
// the order written (no FMA contraction), by the SDK's kernel (fixpoint/kernels.hpp).
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/kernels.hpp>

#include <vector>

namespace {

class Affine final : public fp::Transform {
public:
    explicit Affine(const fp::ParamBag& p) {
        const bool has_matrix = p.has("matrix"), has_coefficients = p.has("coefficients");
        const bool has_offset = p.has("offset");
        if (has_matrix && has_coefficients)
            throw fp::ParamError("give either matrix (with offset) or coefficients, not both");
        if (!has_matrix && !has_coefficients)
            throw fp::ParamError("give either matrix (with offset) or coefficients: [a, b, c, d, e, f]");
        if (has_coefficients) {
            if (has_offset)
                throw fp::ParamError("offset",
                                     "offset goes with matrix; with coefficients [a, b, c, d, e, f] the "
                                     "offset is (e, f)");
            const std::vector<double>& k = p.reals("coefficients");
            a_ = k[0], b_ = k[1], c_ = k[2], d_ = k[3], e_ = k[4], f_ = k[5];
        } else {
            const std::vector<double>& m = p.reals("matrix");
            a_ = m[0], b_ = m[1], c_ = m[2], d_ = m[3];
            if (has_offset) {
                const fp::Vec2 o = p.vec2("offset");
                e_ = o.x, f_ = o.y;
            }
        }
        k_[0] = a_, k_[1] = b_, k_[2] = c_, k_[3] = d_, k_[4] = e_, k_[5] = f_;
    }

    // The SDK's affine kernel (fixpoint/kernels.hpp): the formula a renderer's fused loop runs.
    void apply(fp::Points<float> p, fp::Mask mask) const override { fp::kernels::affine(k_, p, mask); }
    void apply(fp::Points<double> p, fp::Mask mask) const override { fp::kernels::affine(k_, p, mask); }

    fp::KnownKernel kernel() const override {
        fp::KnownKernel k;
        k.kind = fp::KnownKernel::Kind::affine;
        for (int i = 0; i < 6; ++i) k.c[i] = k_[i];
        return k;
    }

    bool is_involution() const override {
        return a_ * a_ + b_ * c_ == 1 && a_ * b_ + b_ * d_ == 0 && c_ * a_ + d_ * c_ == 0 &&
               c_ * b_ + d_ * d_ == 1 && a_ * e_ + b_ * f_ + e_ == 0 && c_ * e_ + d_ * f_ + f_ == 0;
    }

private:
    double a_ = 1, b_ = 0, c_ = 0, d_ = 1, e_ = 0, f_ = 0;
    double k_[6] = {1, 0, 0, 1, 0, 0}; ///< {a, b, c, d, e, f} for the kernels
};

constexpr fp::ParamSpec params[] = {
    fp::param::reals("matrix",
                     "[a, b, c, d]: the linear part, row major (x' = a x + b y + e, y' = c x + d y + "
                     "f); give this with offset, or coefficients")
        .len(4)
        .opt(),
    fp::param::vec2("offset",
                    "[e, f]: the translation added after the matrix (with matrix only; default: [0, 0])")
        .opt(),
    fp::param::reals("coefficients", "[a, b, c, d, e, f]: x' = a x + b y + e, y' = c x + d y + f (instead of "
                                     "matrix and offset)")
        .len(6)
        .opt(),
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<Affine>(fp::Kind::Transform, "affine",
                         "an affine map x' = a x + b y + e, y' = c x + d y + f (IFS maps, paper 02 "
                         "Fig. 5)",
                         params)
        .with_example("{coefficients: [0.5, 0, 0, 0.5, 0.25, 0]}"))
