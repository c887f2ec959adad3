// The known kernels of the SDK (fixpoint/kernels.hpp, their formulas in fixpoint/kernels-inl.hpp):
// on every target this machine has, in float and double, the batch functions give the bits of the
// formulas written out here per point (the contract of fp::KnownKernel that lets a renderer run a
// map fused), masked points stay as they are, and the hexagon's lane test agrees with the scalar
// one of fixpoint/lattice.hpp that the reductions use, on random points, on its boundary and on
// NaN and infinities.
#include <fixpoint/kernels.hpp>
#include <fixpoint/lattice.hpp>
#include <fixpoint/rng.hpp>
#include <fixpoint/simd.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

template <class T>
bool same_bits(T a, T b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

const double circle[3] = {0.3, -0.2, 0.4225};
const double affine[6] = {0.5, 0.375, -0.5, 0.375, -0.0625, 0.4375};
const double gm[3] = {0.008, -0.7501, 2 * (1 + 0.7501)};

// The formulas of fp::KnownKernel (sdk/include/fixpoint/transform.hpp), per point: 0 inversion in
// the circle, 1 affine, 2 Gumowski-Mira.
template <class T>
void by_hand(int which, T& x, T& y) {
    if (which == 0) {
        const T cx = T(circle[0]), cy = T(circle[1]), r2 = T(circle[2]);
        const T dx = x - cx, dy = y - cy, s = r2 / (dx * dx + dy * dy);
        x = cx + s * dx, y = cy + s * dy;
    } else if (which == 1) {
        const double* k = affine;
        const T nx = (T(k[0]) * x + T(k[1]) * y) + T(k[4]), ny = (T(k[2]) * x + T(k[3]) * y) + T(k[5]);
        x = nx, y = ny;
    } else {
        const T alpha = T(gm[0]), mu = T(gm[1]), m2 = T(gm[2]);
        const auto f = [&](T u) {
            const T u2 = u * u;
            return mu * u + (m2 * u2) / (T(1) + u2);
        };
        const T nx = (y + (alpha * (T(1) - (T(0.05) * y) * y)) * y) + f(x);
        y = -x + f(nx);
        x = nx;
    }
}

template <class T>
void by_kernel(int which, fp::Points<T> p, fp::Mask mask) {
    if (which == 0) {
        // Eq. (4) with the circle's factor, as the inversion plugin composes it.
        std::vector<T> dx(p.n), dy(p.n), s(p.n);
        const T cx = T(circle[0]), cy = T(circle[1]);
        if (!fp::kernels::directions(cx, cy, fp::Points<const T>{p.x, p.y, p.n}, mask, dx.data(), dy.data()))
            return;
        fp::kernels::inversion_factor(T(circle[2]), fp::Points<const T>{dx.data(), dy.data(), p.n}, s.data());
        fp::kernels::scale_from(cx, cy, p, mask, s.data());
    } else if (which == 1) {
        fp::kernels::affine(affine, p, mask);
    } else {
        fp::kernels::gumowski_mira(gm, p, mask);
    }
}

// Random points of [-8, 8]^2 and the hexagon's boundary points (the midpoints of its sides and its
// vertices, and their neighbours), NaN, infinities, and an odd count (a partial last vector).
template <class T>
void points(std::vector<T>& x, std::vector<T>& y) {
    fp::Rng g = fp::chain_stream(41, sizeof(T));
    for (int i = 0; i < 901; ++i) {
        x.push_back(T(-8 + 16 * fp::uniform_double(g)));
        y.push_back(T(-8 + 16 * fp::uniform_double(g)));
    }
    const double pi = 3.14159265358979324;
    for (int a = 0; a < 12; ++a) {
        // (The sides' midpoints at 0, 60, ... degrees, at pi; the vertices between, at 2 pi / sqrt 3.)
        const double t = a * pi / 6, rad = a % 2 ? 2 * pi / std::sqrt(3.0) : pi;
        const T px = T(rad * std::cos(t)), py = T(rad * std::sin(t));
        for (const T s : {T(1), std::nextafter(T(1), T(0)), std::nextafter(T(1), T(2))})
            x.push_back(px * s), y.push_back(py * s);
    }
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    for (const T v : {nan, inf, -inf, T(0), T(pi), -T(pi)}) x.push_back(v), y.push_back(T(0.5));
}

template <class T>
void check_every_target() {
    std::vector<T> x0, y0;
    points(x0, y0);
    const std::size_t n = x0.size();
    std::vector<unsigned char> mask(n);
    for (std::size_t i = 0; i < n; ++i) mask[i] = i % 7 == 3 ? 0 : 1;
    for (const std::string& target : fp::simd::supported_targets()) {
        SCOPED_TRACE(target);
        ASSERT_TRUE(fp::simd::force_target(target));
        for (int which = 0; which < 3; ++which) {
            std::vector<T> x = x0, y = y0;
            by_kernel(which, fp::Points<T>{x.data(), y.data(), n}, mask.data());
            std::size_t finite = 0;
            for (std::size_t i = 0; i < n; ++i) {
                T ex = x0[i], ey = y0[i];
                if (mask[i]) by_hand(which, ex, ey);
                EXPECT_TRUE(same_bits(x[i], ex) && same_bits(y[i], ey))
                    << which << " " << i << ": " << x[i] << " " << ex << ", " << y[i] << " " << ey;
                finite += std::isfinite(ex) && std::isfinite(ey);
            }
            EXPECT_GT(finite, n / 2) << which; // (the points are not all thrown to infinity)
        }
        // The circle's inside test against its formula.
        std::vector<unsigned char> in(n);
        fp::kernels::in_circle(T(circle[0]), T(circle[1]), T(circle[2]),
                               fp::Points<const T>{x0.data(), y0.data(), n}, in.data());
        for (std::size_t i = 0; i < n; ++i) {
            const T dx = x0[i] - T(circle[0]), dy = y0[i] - T(circle[1]);
            EXPECT_EQ(in[i] != 0, dx * dx + dy * dy < T(circle[2])) << i;
        }
        // The hexagon's lanes against the scalar test.
        fp::kernels::in_cell(fp::Points<const T>{x0.data(), y0.data(), n}, in.data());
        std::size_t inside = 0;
        for (std::size_t i = 0; i < n; ++i) {
            EXPECT_EQ(in[i] != 0, fp::kernels::in_cell(x0[i], y0[i])) << i << ": " << x0[i] << ", " << y0[i];
            inside += in[i];
        }
        // About the hexagon's share of [-8, 8]^2 (2 sqrt 3 pi^2 / 256: 13%), and not all of it.
        EXPECT_GT(inside, n / 20);
        EXPECT_LT(inside, n / 4);
    }
    fp::simd::force_target("");
}

TEST(Kernels, BatchesAreTheFormulasOnEveryTargetInFloat) { check_every_target<float>(); }
TEST(Kernels, BatchesAreTheFormulasOnEveryTargetInDouble) { check_every_target<double>(); }

// The reductions by the names the recipes give them.
TEST(Kernels, ReductionsByName) {
    using fp::kernels::Reduction;
    EXPECT_EQ(fp::kernels::reduction_named("fmod"), Reduction::fmod);
    EXPECT_EQ(fp::kernels::reduction_named("centred"), Reduction::centred);
    EXPECT_EQ(fp::kernels::reduction_named("floor"), Reduction::floor);
    EXPECT_EQ(fp::kernels::reduction_named("none"), Reduction::none);
    EXPECT_EQ(fp::kernels::reduction_named("hexagonal"), Reduction::hexagonal);
}

} // namespace
