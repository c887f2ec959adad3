// The orbit-trap renderer's class (orbit-trap.cpp: what it computes, its construction and
// schema; orbit-trap/tiles.cpp: the tiles, the whole image, bands and checkpoints).
#pragma once

#include "orbit-trap/batch.hpp"
#include "orbit-trap/reduce.hpp"

#include <fixpoint/fixpoint.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace fp_orbit_trap {

/// Samples per tile: the batch of one task (a few hundred microseconds of work).
constexpr size_t tile_samples = 1024;

class OrbitTrap final : public fp::Renderer {
public:
    explicit OrbitTrap(const fp::ParamBag& p);

    int width() const override { return frame_.width; }
    int height() const override { return frame_.height; }
    std::optional<fp::Box> region() const override {
        return frame_.has_region ? std::optional(frame_.region) : std::nullopt;
    }
    uint64_t memory_bytes(unsigned workers) const override;
    uint64_t work_units() const override { return uint64_t(frame_.width) * uint64_t(frame_.height); }
    fp::Image render(fp::RenderContext& ctx, fp::RenderStats& stats) const override;
    bool streams_rows() const override { return true; }
    bool keeps_checkpoints() const override { return true; }
    uint64_t memory_within(unsigned workers, uint64_t budget) const override;
    void render_rows(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink) const override;

private:
    void set_tile();
    /// render()'s tiles with checkpoints (below run's definition: "Checkpoints").
    template <class T>
    void run_checkpointed(fp::RenderContext& ctx, fp::Image& img, std::vector<TileStats>& per_tile,
                          std::vector<Scratch<T>>& scratch) const;
    template <class T>
    fp::Image run(fp::RenderContext& ctx, fp::RenderStats& stats) const;
    /// The image by bands of `band_rows` rows into the sink (Bands, above).
    template <class T>
    void run_rows(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink, size_t band_rows) const;
    /// Tile t into `image`, whose first pixel is pixel `image_p0` of the whole image.
    template <class T>
    TileStats tile(size_t t, Scratch<T>& s, float* image, size_t image_p0,
                   const fp::RenderContext& ctx) const;
    /// The workers' batches.
    uint64_t scratch_bytes(unsigned workers) const;
    /// Rows per band within `budget` (0: not even one).
    size_t band_rows(unsigned workers, uint64_t budget) const;

    fp::Frame frame_; ///< width, height, area (region), background (optional)
    double cx_ = 0, cy_ = 0, hx_ = 1, hy_ = 1;
    double iw_ = 1, ih_ = 1; ///< 1 / (W - 1), 1 / (H - 1); with `tile`, 1 / W and 1 / H
    uint32_t max_iterations_ = 100;
    std::vector<Offset> offsets_;
    size_t tile_pixels_ = 1;
    bool double_ = false;
    Reduction reduction_ = Reduction::fmod;
    std::shared_ptr<const fp::Transform> mapping_;
    std::shared_ptr<const fp::IterationScheme> iteration_;
    std::shared_ptr<const fp::Trap> traps_;
    std::shared_ptr<const fp::Colourer> colourer_;
    bool known_trap_ = false; ///< the traps are TrapKernel::euclidean_circles: tested inline
    KnownCircles<float> circles_f_;
    KnownCircles<double> circles_d_;
    const KnownCircles<float>& circles(float) const { return circles_f_; }
    const KnownCircles<double>& circles(double) const { return circles_d_; }
};

} // namespace fp_orbit_trap
