// subdivision: a subdivision map f(A) = A P^-1 S P (paper 05, eq. (3.1); Schaefer, Levin and
// Goldman, "Subdivision schemes and attractors", 2005).
//
// P is n x n: row i is control point i lifted into the (n - 1)-dimensional hyperplane
// Q^{n-1} of points (x_1, ..., x_{n-1}, 1), so its last column is all ones and it must be
// invertible. S is the n x n subdivision matrix: the child of a set of control points V (rows)
// is S V, so every row of S must sum to 1 (an affine combination; otherwise the child leaves
// the hyperplane). Parameters:
//   points   the n control points [x, y] (P's first two columns), lifted automatically: n = 3
//            needs no lift (P = [x y 1]); n = 4 is lifted as the paper's Example 1 does, with
//            third coordinate z = x y (its P for (0,0), (1,0), (0,1), (1,1) has third column
//            (0, 0, 0, 1)). Other n: give P.
//   P        instead of points: the full matrix, row major (n x n, last column ones).
//   S        the subdivision matrix, row major, divided by `divisor` (the paper writes
//            S_1 = 1/9 (...): `divisor: 9` and the integers).
// Refused (fp::ParamError): S of the wrong size; a row of S whose sum differs from 1 by more
// than 1e-9 (refused, not normalised: a wrong entry would silently change the fractal); P
// singular (pivot below 1e-12 of P's largest entry); P's last column not ones; both or
// neither of points and P.
//
// As a map of the plane (apply, used by chaos-game and the conformance suite) a point (x, y)
// is lifted like the control points, multiplied by M = P^-1 S P and projected back to its
// first two coordinates. That is a map of the plane only when the lifted coordinates do not
// feed x and y (M's entries there are zero, within 1e-12): true for the carpet maps of
// Example 1 (affine maps of the square) and for every n = 3 map; not in general. Otherwise
// apply() throws once per batch, naming the mfs renderer, which subdivides vertex sets and
// never needs the point map. Per point: 4 multiplications, 4 additions (fp::TransformBase).
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/vertex_map.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using std::size_t;

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

/// The inverse of the n x n row-major matrix a (Gauss-Jordan, partial pivoting); false when
/// a pivot falls below tol.
bool invert(std::vector<double> a, size_t n, std::vector<double>& inv, double tol) {
    inv.assign(n * n, 0.0);
    for (size_t i = 0; i < n; ++i) inv[i * n + i] = 1;
    for (size_t c = 0; c < n; ++c) {
        size_t piv = c;
        for (size_t r = c + 1; r < n; ++r)
            if (std::fabs(a[r * n + c]) > std::fabs(a[piv * n + c])) piv = r;
        if (!(std::fabs(a[piv * n + c]) > tol)) return false;
        for (size_t k = 0; k < n; ++k)
            std::swap(a[c * n + k], a[piv * n + k]), std::swap(inv[c * n + k], inv[piv * n + k]);
        const double d = a[c * n + c];
        for (size_t k = 0; k < n; ++k) a[c * n + k] /= d, inv[c * n + k] /= d;
        for (size_t r = 0; r < n; ++r) {
            if (r == c) continue;
            const double f = a[r * n + c];
            if (f == 0) continue;
            for (size_t k = 0; k < n; ++k)
                a[r * n + k] -= f * a[c * n + k], inv[r * n + k] -= f * inv[c * n + k];
        }
    }
    return true;
}

std::vector<double> mul(const std::vector<double>& a, const std::vector<double>& b, size_t n) {
    std::vector<double> c(n * n, 0.0);
    for (size_t i = 0; i < n; ++i)
        for (size_t k = 0; k < n; ++k)
            for (size_t j = 0; j < n; ++j) c[i * n + j] += a[i * n + k] * b[k * n + j];
    return c;
}

class Subdivision final : public fp::VertexMap {
public:
    explicit Subdivision(const fp::ParamBag& p) {
        const bool has_points = p.has("points"), has_P = p.has("P");
        if (has_points && has_P) throw fp::ParamError("give either points or P, not both");
        if (!has_points && !has_P) throw fp::ParamError("give the control points (points) or the matrix P");
        const double divisor = p.real("divisor");
        std::vector<double> S = p.reals("S");
        std::vector<double> P;
        if (has_points) {
            const auto& pts = p.vec2s("points");
            n_ = pts.size();
            if (n_ > 4)
                throw fp::ParamError("points",
                                     "with " + std::to_string(n_) +
                                         " control points give P (n x n, last column ones): only 3 "
                                         "points (the plane) and 4 (lifted with z = x y) are lifted "
                                         "automatically");
            for (const auto& q : pts) {
                P.push_back(q.x), P.push_back(q.y);
                if (n_ == 4) P.push_back(q.x * q.y);
                P.push_back(1.0);
            }
        } else {
            P = p.reals("P");
            const size_t m = P.size();
            n_ = size_t(std::lround(std::sqrt(double(m))));
            if (n_ * n_ != m || n_ < 3)
                throw fp::ParamError("P", "P has " + std::to_string(m) +
                                              " entries: give a square n x n matrix (n >= 3), row major");
            for (size_t i = 0; i < n_; ++i)
                if (P[i * n_ + n_ - 1] != 1.0)
                    throw fp::ParamError("P", "the last column of P must be all ones (row " +
                                                  std::to_string(i + 1) + " ends in " +
                                                  num(P[i * n_ + n_ - 1]) + ")");
        }
        if (S.size() != n_ * n_)
            throw fp::ParamError("S", "S has " + std::to_string(S.size()) + " entries; " +
                                          std::to_string(n_) + " control points need a " +
                                          std::to_string(n_) + " x " + std::to_string(n_) + " matrix (" +
                                          std::to_string(n_ * n_) + " entries, row major)");
        for (double& v : S) v /= divisor;
        for (size_t i = 0; i < n_; ++i) {
            double sum = 0;
            for (size_t j = 0; j < n_; ++j) sum += S[i * n_ + j];
            if (!(std::fabs(sum - 1.0) <= 1e-9))
                throw fp::ParamError("S", "row " + std::to_string(i + 1) + " of S sums to " + num(sum) +
                                              " (after dividing by the divisor " + num(divisor) +
                                              "), not 1: a subdivision rule takes affine combinations");
        }
        double scale = 0;
        for (double v : P) scale = std::max(scale, std::fabs(v));
        std::vector<double> Pinv;
        if (!invert(P, n_, Pinv, 1e-12 * scale))
            throw fp::ParamError(has_P ? "P" : "points",
                                 std::string(has_P ? "P" : "the P of these control points") +
                                     " is singular: f(A) = A P^-1 S P needs affinely independent (lifted) "
                                     "points" +
                                     (n_ == 3 && !has_P ? " (these three lie on one line)" : ""));
        S_ = S;
        for (size_t i = 0; i < n_; ++i) pts_.push_back({P[i * n_], P[i * n_ + 1]});
        // M = P^-1 S P; x' = sum_i a_i M[i][0] for a = (x, y, lift..., 1).
        const std::vector<double> M = mul(mul(Pinv, S, n_), P, n_);
        double mmax = 0;
        for (double v : M) mmax = std::max(mmax, std::fabs(v));
        for (size_t i = 2; i + 1 < n_; ++i)
            if (std::fabs(M[i * n_]) > 1e-12 * mmax || std::fabs(M[i * n_ + 1]) > 1e-12 * mmax)
                plane_ = false;
        a_ = M[0], c_ = M[1];       // x' = a x + b y + e
        b_ = M[n_], d_ = M[n_ + 1]; // y' = c x + d y + f
        e_ = M[(n_ - 1) * n_], f_ = M[(n_ - 1) * n_ + 1];
    }

    void apply(fp::Points<float> p, fp::Mask mask) const override { run(p, mask); }
    void apply(fp::Points<double> p, fp::Mask mask) const override { run(p, mask); }

    std::string plane_map_problem() const override {
        return plane_
                   ? std::string()
                   : "this subdivision map is no map of the plane (its lifted coordinates feed x and y): use "
                     "it in the mfs renderer, which subdivides vertex sets";
    }
    size_t vertex_count() const override { return n_; }
    std::vector<fp::Vec2> control_points() const override { return pts_; }

    void subdivide(fp::Points<const double> parent, fp::Points<double> child) const override {
        const size_t n = n_;
        for (size_t s = 0; s + n <= parent.n; s += n)
            for (size_t i = 0; i < n; ++i) {
                double x = 0, y = 0;
                for (size_t j = 0; j < n; ++j) {
                    x += S_[i * n + j] * parent.x[s + j];
                    y += S_[i * n + j] * parent.y[s + j];
                }
                child.x[s + i] = x;
                child.y[s + i] = y;
            }
    }

    fp::Box sample_domain() const override { return {-2, 2, -2, 2}; }

private:
    template <class T>
    void run(fp::Points<T> p, fp::Mask mask) const {
        if (!plane_) throw fp::InputError(plane_map_problem());
        const T a = T(a_), b = T(b_), c = T(c_), d = T(d_), e = T(e_), f = T(f_);
        for (size_t i = 0; i < p.n; ++i) {
            const T x = p.x[i], y = p.y[i];
            const T nx = a * x + b * y + e, ny = c * x + d * y + f;
            p.x[i] = !mask || mask[i] ? nx : x;
            p.y[i] = !mask || mask[i] ? ny : y;
        }
    }

    size_t n_ = 3;
    std::vector<double> S_;
    std::vector<fp::Vec2> pts_;
    bool plane_ = true;
    double a_ = 1, b_ = 0, c_ = 0, d_ = 1, e_ = 0, f_ = 0;
};

constexpr fp::ParamSpec params[] = {
    fp::param::vec2s("points",
                     "the n control points [x, y], rows of P (lifted: n = 3 none, n = 4 with z = x y); "
                     "or give P")
        .min_len(3)
        .opt(),
    fp::param::reals("P", "instead of points: the n x n matrix P, row major, last column ones").opt(),
    fp::param::reals("S", "the n x n subdivision matrix, row major (divided by divisor); each row sums to 1")
        .min_len(9),
    fp::param::real("divisor", "S is the given matrix divided by this (the paper's 1/9 (...))")
        .def("1")
        .above(0),
};

} // namespace

FIXPOINT_PLUGIN(
    fp::describe<Subdivision>(fp::Kind::Transform, "subdivision",
                              "a subdivision map f(A) = A P^-1 S P on n control points (paper 05, "
                              "eq. (3.1))",
                              params)
        .with_example("{points: [[0, 0], [1, 0], [0.5, 0.6666666666666666]], S: [2, 0, 0, 1, 1, 0, 1, 0, "
                      "1], divisor: 2}"))
