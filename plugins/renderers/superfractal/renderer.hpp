// The superfractal renderer's class (superfractal.cpp: what it computes, its construction and
// schema; superfractal/steps.cpp: the steps of the V-variable algorithm and the child's plot).
#pragma once

#include "picture.hpp"
#include "uninitialised.hpp"

#include <fixpoint/fixpoint.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace fp_superfractal {

using std::size_t;
using std::uint32_t;
using std::uint64_t;

/// Points per task: a few hundred microseconds of work for cheap maps, few tasks per buffer.
constexpr size_t chunk_points = 16384;
/// Points per map call inside a task: gathered, mapped, coloured and checked while in L1.
constexpr size_t batch_points = 512;

/// One generation of buffers: B * N points, buffer b at [b * N, (b + 1) * N).
struct Generation {
    // Not zeroed: the start tasks or a step write every element before it is read.
    fp_render::Buffer<double> x, y;
    fp_render::Buffer<float> r, g, b; ///< empty when the colourer needs no colour or colours are stolen
    fp_render::Buffer<double> u, v;   ///< the colour IFS's points; empty without colour stealing
    fp_render::Buffer<float> ci;      ///< the palette index (Colourer::palette_index); else empty
};

class Superfractal final : public fp::Renderer {
public:
    explicit Superfractal(const fp::ParamBag& p);

    int width() const override { return frame_.width; }
    int height() const override { return frame_.height; }
    std::optional<fp::Box> region() const override {
        return frame_.has_region ? std::optional(frame_.region) : std::nullopt;
    }
    uint64_t memory_bytes(unsigned workers) const override;
    uint64_t work_units() const override { return (steps_ + 1) * buffers_ * points_; }
    fp::Image render(fp::RenderContext& ctx, fp::RenderStats& stats) const override;

private:
    void fill_start(Generation& g, size_t b, size_t begin, size_t end, uint64_t stream) const;
    uint64_t step_chunk(const Generation& cur, Generation& next, size_t b, size_t begin, size_t end,
                        uint32_t ifs, const uint32_t* src) const;
    uint64_t repair(Generation& g, size_t b, uint64_t stream) const;

    fp::Frame frame_;       ///< width, height, view (region), background
    fp::FinishSpec finish_; ///< the child's histogram is supersample times the image, finished down to it
    double sxmin_ = 0, sxmax_ = 1, symin_ = 0, symax_ = 1; ///< start box
    uint64_t seed_ = 1, steps_ = 30, points_ = 100000, buffers_ = 2, child_ = 0;
    bool colour_ = true; ///< the colourer reads the colour sums
    bool steal_ = false; ///< colour stealing: points carry (u, v) of the colour IFS, not a colour
    bool rgb_ = true;    ///< points carry a colour (colour_ and not steal_)
    /// The colourer's palette_index(): the points carry a palette index too, blended toward each
    /// map's `color` by its `color_speed` (flam3's rule, as in chaos-game).
    bool palette_ = false;
    std::vector<float> map_index_, map_speed_; ///< per map: its color and color_speed
    fp::Rgb initial_colour_;
    fp_render::Picture picture_;
    std::vector<std::array<double, 6>> colour_maps_; ///< per map: [a, b, c, d, e, f] of its colour map

    std::vector<std::shared_ptr<const fp::Transform>> maps_;
    std::vector<fp::Rgb> colours_;
    std::vector<std::vector<uint32_t>> ifs_; ///< IFS i: indices in maps_ of its maps, in order
    size_t max_maps_ = 1;                    ///< most maps in one IFS
    std::vector<double> ifs_cum_, buffer_cum_;
    uint32_t ifs_fallback_ = 0, buffer_fallback_ = 0;
    std::shared_ptr<const fp::Colourer> colourer_;
};

} // namespace fp_superfractal
