// orbit-trap's batch of samples (the passes over it after each step are in kernels-inl.hpp).
// See orbit-trap.cpp for the algorithm around them.
#pragma once

#include "reduce.hpp"

#include <fixpoint/fixpoint.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace fp_orbit_trap {

using std::size_t;
using std::uint32_t;
using std::uint64_t;

/// The arrays x, y and id are padded to whole blocks of this many: kernels-inl.hpp reads whole
/// vectors, up to the widest a target has (64 floats: SVE-2048).
constexpr size_t block = 64;

template <class T>
struct Scratch {
    std::vector<T> x, y, ratio;
    std::vector<uint32_t> id;
    std::vector<std::int32_t> caught;
    // Results per sample of the tile.
    std::vector<std::int32_t> trap;
    std::vector<float> ratio_out;
    std::vector<uint32_t> iteration;
    std::vector<float> rgb;
    std::vector<uint32_t> quant; ///< rgb rounded to 24 fractional bits
    std::vector<uint64_t> sum;   ///< per pixel and channel: the sum of its samples' quant
    std::vector<double> u, v;    ///< per pixel: 2 i - (W - 1), 2 j - (H - 1)

    void resize(size_t n, size_t pixels) {
        sum.resize(3 * pixels), u.resize(pixels), v.resize(pixels);
        // x, y, id padded to whole blocks of the fused pass (which reads whole vectors).
        const size_t padded = (n + block - 1) / block * block;
        x.resize(padded), y.resize(padded), id.resize(padded), ratio.resize(n), caught.resize(n);
        trap.resize(n), ratio_out.resize(n), iteration.resize(n), rgb.resize(3 * n), quant.resize(3 * n);
    }
};

/// A sample's offset within its pixel, in pixels.
struct Offset {
    double x, y;
};

/// Fixed-point scale of the per-pixel colour sums (24 fractional bits).
constexpr double sum_scale = 16777216.0;

/// What a tile's start points are made from: the area's centre and half sizes, 1 / (W - 1) and
/// 1 / (H - 1), the image size, the sample pattern and the step limit.
struct TileFrame {
    double cx, hx, cy, hy, iw, ih;
    size_t width, height;
    const Offset* offsets;
    size_t ns;
    uint32_t max_iterations;
};

struct TileStats {
    uint64_t drawn = 0, bad = 0;
};

/// A trap the renderer tests inline (fp::TrapKernel::euclidean_circles), in T.
template <class T>
struct KnownCircles {
    std::vector<T> cx, cy, key, r;
};

// ---------------------------------------------------------------- the dispatched passes
// Each calls the pass compiled for the best instruction set this CPU has (orbit-trap/kernels.cpp).
/// The tile's start points and reset records (kernels-inl.hpp's tile_starts_t).
void tile_starts(const TileFrame& f, Scratch<float>& s, size_t p0, size_t np);
void tile_starts(const TileFrame& f, Scratch<double>& s, size_t p0, size_t np);
/// The mean of each pixel's samples (kernels-inl.hpp's tile_mean_all).
void tile_mean(const float* rgb, uint32_t* q, uint64_t* sum, size_t np, size_t ns, float* out);
/// The caught samples recorded and the others moved to the front; how many are left.
size_t retire(Scratch<float>& s, size_t live, uint32_t it);
size_t retire(Scratch<double>& s, size_t live, uint32_t it);
/// The same fused with the test of known circles (and, with `check`, the reduction's range).
size_t test_retire(const KnownCircles<float>& c, Scratch<float>& s, size_t live, uint32_t it, Reduction red,
                   bool check, bool& outside);
size_t test_retire(const KnownCircles<double>& c, Scratch<double>& s, size_t live, uint32_t it, Reduction red,
                   bool check, bool& outside);

} // namespace fp_orbit_trap
